"""`python -m pbdval.external.pybullet --scene RESOLVED.json --out OUTDIR`: the engine's process
(protocol 1, docs/external-engines.md), as the catalogue entry engines/pybullet.json runs it.
`python -m pbdval.external.pybullet --serve --socket PATH`: the persistent process that serves
many runs, each in a forked child (the catalogue's `serve`; pbdval.protocol.serve_runs)."""

import json
import os
import sys
from typing import Any

# One BLAS thread (before numpy is loaded: pybullet imports it): the engine's array operations
# are small, and OpenBLAS's thread pool costs the interpreter's start 40-45 ms of CPU and leaves
# threads spinning in the server every run's child is forked from
# (docs/benchmarks.md#fourth-pass). A value set in the environment is kept.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# pybullet's C code prints a "pybullet build time" banner to file descriptor 1 when it is
# imported: an engine keeps standard output free of anything but data, so from here on file
# descriptor 1 is standard error (before the import below loads pybullet).
os.dup2(2, 1)

import pybullet as pb

from pbdval.external.pybullet.engine import main


class ServedClient:
    """Serve mode's physics client. The server opens one DIRECT physics client before it forks
    any run's child (pb.connect costs 20-40 ms of CPU on its own), and a child's first run's
    pb.connect(pb.DIRECT) gets its own copy of it, the fork's: a client as fresh as the one the
    single-shot run opens, since the server never uses it (pybullet's DIRECT client is in the
    process, without threads). A child that serves several runs (the catalogue's
    `serve.runsPerChild`) hands each later run the same client with its world rebuilt from
    scratch (`between_runs`). Served and single-shot runs are compared bit for bit
    (tests/python/test_serve.py, ServedShippedEngines in tests/validation/test_external_engine.cpp)."""

    def __init__(self) -> None:
        self.opened = pb.connect(pb.DIRECT)
        self.connect = pb.connect
        self.reset_simulation = pb.resetSimulation
        self.taken = False  # by the child's current run; False when it is forked
        self.reusable = True  # no run of this child made a world between_runs cannot rebuild
        pb.connect = self.connect_or_take_the_open_client
        pb.resetSimulation = self.reset_and_note_the_world

    def connect_or_take_the_open_client(self, *args: Any, **kwargs: Any) -> Any:
        if not self.taken and args == (pb.DIRECT,) and not kwargs:
            self.taken = True
            return self.opened
        self.reusable = False  # a client of its own: the child retires after the run
        return self.connect(*args, **kwargs)

    def reset_and_note_the_world(self, *args: Any, **kwargs: Any) -> Any:
        # Bullet's deformable world keeps something across resetSimulation that the API does not
        # reset: a cloth run served before a tet run changed the tet run's nodes from its 100th
        # sample on (docs/external-engines.md#persistent-engines). A child that made one retires.
        flags = args[0] if args else kwargs.get("flags", 0)
        if int(flags) & pb.RESET_USE_DEFORMABLE_WORLD:
            self.reusable = False
        return self.reset_simulation(*args, **kwargs)

    def between_runs(self) -> bool:
        """After a run, in a child that may serve another: the client's world rebuilt as a new
        client has it (resetSimulation deletes the dynamics world, its solver, broadphase and
        every body, constraint and shape, and makes a new one with the defaults; the body and
        constraint ids start from 0 again), and what it keeps outside the world set back to a
        new client's values: the time step and substeps, the contact breaking threshold (a
        global of Bullet's), the mesh file cache (emptied: a later mesh file may have an earlier
        one's name). Every run sets every parameter it uses anyway (engine.PybulletRun._world,
        multibody.py). False when the run made a world this cannot rebuild."""
        if not self.reusable or not self.taken:
            return False
        c = self.opened
        self.reset_simulation(physicsClientId=c)
        pb.setPhysicsEngineParameter(enableFileCaching=0, physicsClientId=c)
        pb.setPhysicsEngineParameter(enableFileCaching=1, fixedTimeStep=NEW_CLIENT_TIME_STEP,
                                     numSubSteps=0, contactBreakingThreshold=NEW_CLIENT_BREAKING_THRESHOLD,
                                     physicsClientId=c)
        self.taken = False
        return True


def needs_a_fresh_child(scene_path: str) -> bool:
    """A run with cloth or solids (Bullet's deformable world) goes to a fresh child: a used one
    gives it other results. A tet solid run served in a child after some multibody runs (car,
    robot_kuka_iiwa_swing, robot_minitaur_drop, robot_pendulum5 in pybullet.multibody.si) or
    after a cloth run gave other node positions than the same run in a fresh process: something
    of Bullet's outside the world, which resetSimulation and the API do not reset, reaches the
    deformable world's solve (docs/external-engines.md#persistent-engines)."""
    with open(scene_path, "rb") as scene_file:
        document = json.load(scene_file)
    return bool(document.get("triangleModels")) or bool(document.get("tetModels"))


#: What a new pybullet client has (PhysicsServerCommandProcessor's m_physicsDeltaTime, Bullet's
#: gContactBreakingThreshold), set back between the runs of one child.
NEW_CLIENT_TIME_STEP = 1.0 / 240.0
NEW_CLIENT_BREAKING_THRESHOLD = 0.02


if sys.argv[1:2] == ["--serve"]:
    from pbdval.external.pybullet import multibody  # noqa: F401 -- once, not in each run's child
    from pbdval.protocol import serve_runs

    # A served run's output goes to its standard error too, as above.
    client = ServedClient()
    sys.exit(serve_runs(sys.argv[2:], main, "pybullet as a persistent pbdval external engine",
                        stdout_to_stderr=True, between_runs=client.between_runs,
                        fresh_child_for=needs_a_fresh_child))
sys.exit(main())
