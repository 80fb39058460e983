"""Children that serve several runs in turn (the catalogue's `serve.runsPerChild`, serve_runs'
`--runs-per-child`; docs/external-engines.md#persistent-engines): the order of the runs one child
serves changes no run's files, and a crash, a failure, a leftover process or the run limit ends
that child alone, the next run going to a fresh one."""

from __future__ import annotations

import json
import subprocess
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from test_serve import named_scene, request, run_named_projectiles, serve_command, server, toy_catalogue  # noqa: F401 -- `server` is a fixture

from conftest import REPO, VENV_PYTHON, engine_environment


def files(folder: Path) -> dict[str, bytes]:
    """Every file a run wrote to its output folder, by name, as bytes."""
    return {f.name: f.read_bytes() for f in sorted(folder.iterdir())}


def served(socket_path: Path, scene: Path, out: Path) -> tuple[int, dict[str, Any]]:
    """One run through the server: the pid of the child that ran it, and the server's last reply."""
    out.mkdir()
    replies = request(socket_path, {"protocol": 1, "scene": str(scene), "out": str(out),
                                    "stderr": str(out.with_suffix(".stderr"))})
    assert len(replies) == 2 and "started" in replies[0], replies
    return int(replies[0]["started"]), replies[1]


#: Scenes of different kinds for each engine (contacts, joints, reduced coordinates, particles),
#: each run served in turn by one child in several orders. pybullet's cloth comes before a
#: tet solid on purpose: Bullet's deformable world keeps something across resetSimulation (a tet
#: run served after a cloth run in the same child gave other nodes from its first samples on), so
#: a child that made one retires; the tet run must still give its single-shot bytes.
SCENES = {
    "pybullet": [("projectile", "pybullet.si"), ("contact_stack_5", "pybullet.si"),
                 ("double_pendulum", "pybullet.multibody.si"), ("cloth_hanging", "pybullet.si"),
                 ("tet_bar", "pybullet.si"), ("joint_ball", "pybullet.si"),
                 ("double_pendulum", "pybullet.si"), ("contact_incline_slide", "pybullet.si")],
    "mujoco-python": [("projectile", ""), ("contact_stack_5", ""), ("double_pendulum", ""),
                      ("cloth_hanging", ""), ("joint_ball", ""), ("contact_incline_slide", "")],
}


@pytest.mark.parametrize("engine", ["pybullet", "mujoco-python"])
def test_the_order_of_the_runs_one_child_serves_changes_no_run_s_files(
        engine: str, server: Callable[[str], Path], export_scene: Callable[..., Path],  # noqa: F811
        run_engine: Callable[[str, Path], tuple[dict[str, Any], Path]], tmp_path: Path) -> None:
    assert "--runs-per-child" in serve_command(engine)  # the catalogue declares it
    scenes = [export_scene(case, method=method, duration=0.3) for case, method in SCENES[engine]]
    single = [files(run_engine(engine, scene)[1]) for scene in scenes]
    socket_path = server(engine)
    count = len(scenes)
    orders = {"forward": list(range(count)), "backward": list(reversed(range(count))),
              "interleaved": [*range(1, count, 2), *range(0, count, 2)]}
    for name, order in orders.items():
        children = []
        for i in order:
            out = tmp_path / f"{name}-{i}"
            child, reply = served(socket_path, scenes[i], out)
            assert reply == {"exited": 0}, out.with_suffix(".stderr").read_text()
            children.append(child)
            assert files(out) == single[i], (name, SCENES[engine][i])
        # The runs were served in turn by fewer children than runs (children are reused).
        assert len(set(children)) < len(children), children


REUSE_TOY = """\
import os, signal, subprocess, sys, time
sys.path.insert(0, {examples!r})
from euler_engine import run as euler_run  # the template engine's integrator
from pbdval import protocol as pp

def main(argv=None):
    def run(scene, out):
        if "crash" in scene.name:
            os.kill(os.getpid(), signal.SIGSEGV)
        if "abort" in scene.name:
            os.abort()
        if "hang" in scene.name:
            time.sleep(300)
        if "fail" in scene.name:
            raise RuntimeError("a failing run")
        if "leave" in scene.name:  # a process that outlives the run
            left = subprocess.Popen(["sleep", "300"])
            (out / "left.txt").write_text(str(left.pid))
        return euler_run(scene, out)
    return pp.serve(argv, "toy", lambda scene: [], run, "toy 1")

if sys.argv[1:2] == ["--serve"]:
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "servers.txt"), "a") as f:
        f.write(" ".join(sys.argv[1:]) + "\\n")
    sys.exit(pp.serve_runs(sys.argv[2:], main, "toy, persistent"))
sys.exit(main())
"""


@pytest.fixture
def toy_server(tmp_path: Path) -> Iterator[Callable[[int], Path]]:
    """toy_server(runs_per_child) → the socket of the reuse toy (REUSE_TOY) served with
    `--runs-per-child runs_per_child`; stopped after the test."""
    started: list[subprocess.Popen[bytes]] = []

    def start(runs_per_child: int) -> Path:
        folder = tmp_path / f"toy{len(started)}"
        folder.mkdir()
        (folder / "toy.py").write_text(REUSE_TOY.format(examples=str(REPO / "examples")))
        socket_path = folder / "toy.socket"
        log = folder / "toy.stderr"
        with log.open("wb") as errors:
            process = subprocess.Popen([str(VENV_PYTHON), "toy.py", "--serve", "--socket", str(socket_path),
                                        "--runs-per-child", str(runs_per_child)],
                                       cwd=folder, env=engine_environment(), stdin=subprocess.DEVNULL,
                                       stdout=subprocess.DEVNULL, stderr=errors)
        started.append(process)
        deadline = time.monotonic() + 60  # the runner's start limit
        while not socket_path.exists():
            assert process.poll() is None and time.monotonic() < deadline, log.read_text()
            time.sleep(0.01)
        return socket_path

    yield start
    for process in started:
        process.kill()
        process.wait()


def status(out: Path) -> str:
    return str(json.loads((out / "status.json").read_text())["status"])


def test_a_crash_an_abort_a_failure_or_a_leftover_process_ends_only_its_own_child(
        toy_server: Callable[[int], Path], export_scene: Callable[..., Path], tmp_path: Path) -> None:
    socket_path = toy_server(50)
    reference = tmp_path / "reference"
    first, reply = served(socket_path, named_scene(export_scene, "first"), reference)
    assert reply == {"exited": 0} and status(reference) == "ok"
    trajectory = (reference / "trajectory.npy").read_bytes()

    def clean_run(name: str) -> int:
        """A run that ends cleanly, with the first run's trajectory bytes; its child's pid."""
        out = tmp_path / name
        child, reply = served(socket_path, named_scene(export_scene, name), out)
        assert reply == {"exited": 0}, out.with_suffix(".stderr").read_text()
        assert status(out) == "ok" and (out / "trajectory.npy").read_bytes() == trajectory
        return child

    assert clean_run("second") == first  # a clean run keeps its child for the next
    # A crash: the run gets its own signal, the next run a fresh child.
    crashed, reply = served(socket_path, named_scene(export_scene, "crash"), tmp_path / "crash")
    assert crashed == first and reply == {"signaled": 11}
    after_crash = clean_run("then_one")
    assert after_crash != first
    assert not Path(f"/proc/{first}").exists()
    aborted, reply = served(socket_path, named_scene(export_scene, "abort"), tmp_path / "abort")
    assert aborted == after_crash and reply == {"signaled": 6}
    after_abort = clean_run("then_two")
    assert after_abort != after_crash
    # A run that raises: status error, as single-shot; its child retires all the same.
    failed, reply = served(socket_path, named_scene(export_scene, "fail"), tmp_path / "fail")
    assert failed == after_abort and reply == {"exited": 0} and status(tmp_path / "fail") == "error"
    after_failure = clean_run("then_three")
    assert after_failure != after_abort
    # A run that leaves a process: its child retires, and the process ends with its group.
    left_by, reply = served(socket_path, named_scene(export_scene, "leave"), tmp_path / "leave")
    assert left_by == after_failure and reply == {"exited": 0} and status(tmp_path / "leave") == "ok"
    left = int((tmp_path / "leave" / "left.txt").read_text())
    assert clean_run("then_four") != after_failure
    deadline = time.monotonic() + 10  # killed with the group before the reply; reaped by init
    while Path(f"/proc/{left}").exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    assert not Path(f"/proc/{left}").exists()


def test_a_child_retires_after_its_runs_per_child(
        toy_server: Callable[[int], Path], export_scene: Callable[..., Path], tmp_path: Path) -> None:
    socket_path = toy_server(3)
    children = []
    for i in range(7):
        out = tmp_path / f"run{i}"
        child, reply = served(socket_path, named_scene(export_scene, f"run{i}"), out)
        assert reply == {"exited": 0} and status(out) == "ok"
        children.append(child)
    # Runs one after the other: 3 per child, then a fresh one.
    assert [children.index(c) for c in children] == [0, 0, 0, 3, 3, 3, 6]
    assert not Path(f"/proc/{children[0]}").exists()


def test_pbdval_run_passes_runs_per_child_and_a_hang_or_crash_reaches_no_other_run(
        pbdval_binary: Path, tmp_path: Path) -> None:
    catalogue = toy_catalogue(tmp_path, REUSE_TOY, runsPerChild=4)
    order = ["a_first", "b_second", "c_hang", "d_next", "e_crash", "f_next", "g_fail", "h_last"]
    runs, left = run_named_projectiles(pbdval_binary, tmp_path, catalogue, order, 1)
    assert runs["c_hang"]["status"] == "timeout", runs["c_hang"]
    assert runs["e_crash"]["status"] == "error" and "signal 11" in runs["e_crash"]["reason"], runs["e_crash"]
    assert runs["g_fail"]["status"] == "error" and "a failing run" in runs["g_fail"]["reason"], runs["g_fail"]
    for name in ("a_first", "b_second", "d_next", "f_next", "h_last"):
        assert runs[name]["status"] == "ok", runs[name]
    # One server, given the catalogue's runsPerChild (the runner appends --socket PATH).
    servers = (catalogue / "servers.txt").read_text().splitlines()
    assert len(servers) == 1 and servers[0].split()[:4] == ["--serve", "--runs-per-child", "4", "--socket"], servers
    assert left == []

