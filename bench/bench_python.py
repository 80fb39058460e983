"""Benchmarks of the Python side (docs/benchmarks.md#python): what the external-engine protocol
costs over an engine's own stepping, and what `import pbdval` costs to read states into numpy.
Speed is measured here, never asserted in tests.

    scripts/bench python [--repeat N] [--out FILE.json]

scripts/bench runs it with .venv/bin/python and PYTHONPATH=python:build/release/python, so
`import pbdval` is this checkout's package and extension (no edit of sys.path here).

1. Protocol overhead, per external engine and case (5 s of simulated time):
   step_s      the engine's own stepping cost, in this process: the resolved scene built with the
               engine's own adapter code, then only its step call (pb.stepSimulation, mj_step)
               for every step of the run;
   protocol_s  the same run through the protocol as the suite runs it (pbdval.simulate: a child
               process, Python start-up and imports, the resolved scene, the engine's sampling
               loop with its per-step divergence check, the CSV, the runner reading it back);
   startup_s   the protocol's fixed part: the same with a one-step run;
   overhead    protocol_s / step_s - 1.
2. Reading states: Simulation.read (into preallocated arrays) and Simulation.state (new arrays)
   for a scene of 1000 free bodies, median of many calls.
Each figure is the best (minimum) of --repeat runs, the usual estimate of a cost on a machine
whose other load only ever adds time.
"""

from __future__ import annotations

import argparse
import functools
import importlib
import json
import os
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from bench_record import machine, write_record  # bench/, the script's own folder

import pbdval
from pbdval import protocol as pp

REPO = Path(__file__).resolve().parents[1]

DURATION = 5.0  # s of simulated time (the "5 s case")
CASES = ["joint_hinge", "chain_10", "contact_bouncing_balls", "contact_stack_5"]
ENGINES = {"pybullet.si": "pbdval.external.pybullet.engine",
           "mujoco-python.euler.newton": "pbdval.external.mujoco.engine"}


def load_adapter(module: str) -> Any:
    return importlib.import_module(module)


def best(repeat: int, run: Callable[[], float]) -> float:
    return min(run() for _ in range(repeat))


def in_process_stepping(method: str, scene: pbdval.Scene) -> float:
    """Seconds for the run's steps alone, engine built by its own adapter in this process."""
    adapter = load_adapter(ENGINES[method])
    resolved = pp.parse_resolved_scene(scene.resolved(method, duration=DURATION))
    if method.startswith("pybullet"):
        run = adapter.PybulletRun(resolved)
        step: Callable[[], None] = lambda: adapter.pb.stepSimulation(physicsClientId=run.client)
    else:
        run = adapter.MujocoRun(resolved)
        mj = adapter.mujoco
        step = lambda: mj.mj_step(run.model, run.data)
    steps = resolved.steps
    start = time.perf_counter()
    for _ in range(steps):
        step()
    return time.perf_counter() - start


def through_protocol(method: str, scene: pbdval.Scene, duration: float) -> float:
    start = time.perf_counter()
    info, _ = pbdval.simulate(scene, method, duration=duration)
    elapsed = time.perf_counter() - start
    if not info.ok:
        raise RuntimeError(f"{method}: {info.status}: {info.reason}")
    return elapsed


def protocol_overhead(repeat: int) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    for case in CASES:
        scene = pbdval.load_scene(REPO / "cases" / f"{case}.json")
        for method in ENGINES:
            try:
                step_s = best(repeat, functools.partial(in_process_stepping, method, scene))
                protocol_s = best(repeat, functools.partial(through_protocol, method, scene, DURATION))
                startup_s = best(repeat, functools.partial(through_protocol, method, scene, scene.time_step))
            except RuntimeError as error:
                rows.append({"case": case, "method": method, "error": str(error)})
                continue
            steps = round(DURATION / scene.time_step)
            rows.append({
                "case": case, "method": method, "steps": steps, "step_s": step_s, "protocol_s": protocol_s,
                "startup_s": startup_s, "overhead": protocol_s / step_s - 1,
                "per_step_overhead_us": 1e6 * (protocol_s - startup_s - step_s) / steps,
            })
            print(f"{case:24s} {method:28s} steps {steps:5d}  step {step_s * 1e3:8.1f} ms  protocol "
                  f"{protocol_s * 1e3:8.1f} ms  (start-up {startup_s * 1e3:6.1f} ms)  overhead "
                  f"{100 * rows[-1]['overhead']:7.1f} %", flush=True)
    return rows


def free_bodies_scene(folder: Path, count: int) -> Path:
    bodies = [{"id": i, "translation": [2.0 * (i % 10), 2.0 * ((i // 10) % 10), 2.0 * (i // 100)],
               "rotationAxis": [0, 0, 1], "rotationAngle": 0.0, "scale": [1, 1, 1], "density": 500,
               "isDynamic": True, "velocity": [0.1, 0, 0], "angularVelocity": [0, 0.2, 0],
               "collisionObjectType": 1, "collisionObjectScale": [0.5, 0.5, 0.5]}
              for i in range(count)]
    path = folder / f"free_{count}.json"
    path.write_text(json.dumps({"Simulation": {"timeStepSize": 0.005, "subSteps": 1}, "RigidBodies": bodies}))
    return path


def read_states(count: int, calls: int) -> dict[str, Any]:
    with tempfile.TemporaryDirectory() as folder:
        scene = pbdval.load_scene(free_bodies_scene(Path(folder), count))
    sim = pbdval.Simulation(scene, "pbd")
    sim.step(1)
    buffer = pbdval.BodyStates(scene.body_count)

    def median_us(call: Callable[[], object]) -> float:
        samples = []
        for _ in range(calls):
            start = time.perf_counter_ns()
            call()
            samples.append(time.perf_counter_ns() - start)
        return statistics.median(samples) / 1e3

    read_us = median_us(lambda: sim.read(buffer))
    state_us = median_us(sim.state)
    copy_us = median_us(lambda: np.copy(buffer.packed))  # the memory traffic alone, for scale
    print(f"read {count} bodies: Simulation.read {read_us:.1f} µs, Simulation.state {state_us:.1f} µs "
          f"(a numpy copy of the same {buffer.packed.nbytes / 1e3:.0f} kB: {copy_us:.1f} µs)")
    return {"bodies": count, "read_us": read_us, "state_us": state_us, "numpy_copy_us": copy_us, "calls": calls}


def metadata() -> dict[str, Any]:
    import mujoco
    import pybullet  # noqa: F401

    return {
        **machine(), "numpy": np.__version__,
        "mujoco": mujoco.__version__, "pbdval": importlib.import_module("pbdval._core").version,
        "binary": os.popen(f"{pbdval.results.pbdval_binary()} --version").read().strip(),
        "duration_s": DURATION,
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", type=Path, default=None,
                        help="JSON file (default: bench/results/<host>/python-<UTC stamp>.json)")
    args = parser.parse_args()
    from pbdval import results as _  # noqa: F401  (pbdval.results.pbdval_binary in metadata)

    document = {"context": metadata(), "protocol": protocol_overhead(args.repeat),
                "read_states": [read_states(n, 2000) for n in (10, 100, 1000)]}
    write_record("python", document, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
