"""Persistent engines (serve protocol 1, docs/external-engines.md#persistent-engines) from the
engine's side: pbdval.protocol.serve_runs as pybullet and mujoco-python run it, and `pbdval run`
handing its runs to them."""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from conftest import REPO, VENV_PYTHON, engine_environment


def serve_command(name: str) -> list[str]:
    """The catalogue entry's `serve` command as the runner runs it ("{python}" replaced,
    `--runs-per-child N` appended for a `runsPerChild` above 1: engine_catalogue.cpp)."""
    entry = json.loads((REPO / "engines" / f"{name}.json").read_text())
    assert entry["serve"]["protocol"] == 1
    command = [str(VENV_PYTHON) if word == "{python}" else word for word in entry["serve"]["command"]]
    runs_per_child = entry["serve"].get("runsPerChild", 1)
    return command + (["--runs-per-child", str(runs_per_child)] if runs_per_child > 1 else [])


@pytest.fixture
def server(tmp_path: Path) -> Iterator[Callable[[str], Path]]:
    """server("mujoco-python") → the socket of that engine's server, started as a worker of
    `pbdval run` starts it; stopped (by its pid) after the test."""
    started: list[subprocess.Popen[bytes]] = []

    def start(name: str) -> Path:
        path = tmp_path / f"{name}.socket"
        log = (tmp_path / f"{name}.stderr").open("wb")
        process = subprocess.Popen([*serve_command(name), "--socket", str(path)],
                                   cwd=REPO / "engines", env=engine_environment(),
                                   stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=log)
        started.append(process)
        deadline = time.monotonic() + 60  # the runner's start limit
        while time.monotonic() < deadline:
            assert process.poll() is None, (tmp_path / f"{name}.stderr").read_text()
            if path.exists():
                with socket.socket(socket.AF_UNIX) as probe:
                    try:
                        probe.connect(str(path))
                        return path
                    except OSError:
                        pass
            time.sleep(0.01)
        raise AssertionError(f"{name}'s server did not listen within 60 s")

    yield start
    for process in started:
        process.kill()
        process.wait()


def request(path: Path, document: Any) -> list[dict[str, Any]]:
    """One connection: sends `document` as a line, returns the replies until the server closes."""
    with socket.socket(socket.AF_UNIX) as connection:
        connection.connect(str(path))
        connection.sendall((json.dumps(document) + "\n").encode())
        data = b""
        while chunk := connection.recv(4096):
            data += chunk
    return [json.loads(line) for line in data.decode().splitlines()]


@pytest.mark.parametrize("engine", ["pybullet", "mujoco-python", "drake"])
def test_a_served_run_writes_the_single_shot_files_bit_for_bit(
        engine: str, server: Callable[[str], Path], export_scene: Callable[..., Path],
        run_engine: Callable[[str, Path], tuple[dict[str, Any], Path]], tmp_path: Path) -> None:
    method = {"pybullet": "pybullet.si", "mujoco-python": "mujoco-python.euler.newton", "drake": "drake.sap"}[engine]
    scene = export_scene("double_pendulum", method=method, duration=0.5)
    status, single = run_engine(engine, scene)
    assert status["status"] == "ok", status
    socket_path = server(engine)
    for attempt in range(2):  # the second run from the same server: nothing of the first remains
        out = tmp_path / f"served{attempt}"
        out.mkdir()
        replies = request(socket_path, {"protocol": 1, "scene": str(scene), "out": str(out),
                                        "stderr": str(tmp_path / f"served{attempt}.stderr")})
        assert len(replies) == 2 and "started" in replies[0], replies
        assert replies[1] == {"exited": 0}, (tmp_path / f"served{attempt}.stderr").read_text()
        assert (out / "trajectory.npy").read_bytes() == (single / "trajectory.npy").read_bytes()
        assert json.loads((out / "status.json").read_text()) == status


def test_a_bad_request_is_answered_with_an_error_and_the_server_serves_on(
        server: Callable[[str], Path], export_scene: Callable[..., Path], tmp_path: Path) -> None:
    socket_path = server("mujoco-python")
    assert request(socket_path, {"protocol": 2}) == [{"error": "protocol: expected 1, got 2"}]
    replies = request(socket_path, {"protocol": 1, "scene": "", "out": "o", "stderr": "e"})
    assert replies == [{"error": "scene: expected a path, got ''"}]
    scene = export_scene("projectile", method="mujoco-python.euler.newton", duration=0.1)
    out = tmp_path / "out"
    out.mkdir()
    replies = request(socket_path, {"protocol": 1, "scene": str(scene), "out": str(out),
                                    "stderr": str(tmp_path / "stderr")})
    assert replies[-1] == {"exited": 0}
    # A run that fails as the single-shot command would: bad usage is exit status 2 (argparse).
    replies = request(socket_path, {"protocol": 1, "scene": str(scene), "out": str(tmp_path / "none"),
                                    "stderr": str(tmp_path / "stderr2")})
    assert replies[-1] == {"exited": 2}
    assert "not an existing directory" in (tmp_path / "stderr2").read_text()


def children(pid: int) -> list[int]:
    """The processes `pid` started (Linux /proc)."""
    return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]


def test_the_child_waiting_for_the_next_run_is_replaced_when_it_dies(
        server: Callable[[str], Path], export_scene: Callable[..., Path], tmp_path: Path) -> None:
    socket_path = server("pybullet")
    server_pid = next(int(p.name) for p in Path("/proc").iterdir() if p.name.isdigit()
                      and str(socket_path) in (p / "cmdline").read_bytes().decode(errors="replace"))
    deadline = time.monotonic() + 10  # the server forks it just after it starts listening
    while not (waiting := children(server_pid)) and time.monotonic() < deadline:
        time.sleep(0.01)
    assert len(waiting) == 1  # the next run's child, forked ahead
    os.kill(waiting[0], 9)
    scene = export_scene("projectile", method="pybullet.si", duration=0.1)
    out = tmp_path / "out"
    out.mkdir()
    replies = request(socket_path, {"protocol": 1, "scene": str(scene), "out": str(out),
                                    "stderr": str(tmp_path / "stderr")})
    assert replies[0]["started"] != waiting[0]
    assert replies[-1] == {"exited": 0}, (tmp_path / "stderr").read_text()
    assert json.loads((out / "status.json").read_text())["status"] == "ok"


#: Put first on the engines' PYTHONPATH (the runner appends the inherited one to its own, and a
#: PYTHONPATH folder comes before the interpreter's own sitecustomize): every Python interpreter
#: the runner starts writes its command line, one per line, to $PBDVAL_TEST_INTERPRETERS.
INTERPRETER_LOG = """\
import os, sys
with open(os.environ["PBDVAL_TEST_INTERPRETERS"], "a") as log:
    log.write(" ".join(sys.orig_argv) + "\\n")
"""


@pytest.mark.parametrize("tmpdir_length", ["short", "too long for a socket path"])
def test_pbdval_run_hands_its_runs_to_servers_and_leaves_nothing_behind(
        pbdval_binary: Path, tmp_path: Path, tmpdir_length: str) -> None:
    if tmpdir_length == "short":
        scratch = Path(tempfile.mkdtemp(prefix="pv-", dir="/tmp"))
    else:
        # A socket path has at most 107 bytes: the servers' folder goes under /tmp instead.
        scratch = tmp_path / ("a-temporary-folder-whose-path-is-long-" * 3)
        scratch.mkdir()
    site = tmp_path / "site"
    site.mkdir()
    (site / "sitecustomize.py").write_text(INTERPRETER_LOG)
    interpreters = tmp_path / "interpreters.txt"
    inherited = os.environ.get("PYTHONPATH", "")
    environment = dict(os.environ, TMPDIR=str(scratch), PBDVAL_TEST_INTERPRETERS=str(interpreters),
                       PYTHONPATH=str(site) + (os.pathsep + inherited if inherited else ""))
    cases = [str(REPO / "cases" / f"{name}.json") for name in ("projectile", "joint_hinge", "joint_ball")]
    try:
        process = subprocess.Popen([str(pbdval_binary), "run", *cases, "--engines", "pybullet,mujoco-python",
                                    "--jobs", "2", "--out", str(tmp_path / "out")],
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
                                   env=environment)
        _, stderr = process.communicate(timeout=600)
        assert process.returncode == 0, stderr
        runs = json.loads((tmp_path / "out" / "results.json").read_text())["runs"]
        # 3 cases × (pybullet's two run methods, maximal and reduced coordinates, + mujoco-python's).
        assert len(runs) == 9
        assert all(run["status"] == "ok" for run in runs), [(r["case"], r["engine"], r["reason"]) for r in runs]
        # Served: one interpreter per engine, started with its catalogue's `serve` command, and
        # none for a single run (`--scene`): the nine runs were forked from the two servers.
        started = interpreters.read_text().splitlines()
        assert sorted(line.split()[2] for line in started) == [
            "pbdval.external.mujoco", "pbdval.external.pybullet"], started
        assert all("--serve" in line.split() and "--scene" not in line.split() for line in started), started
        # The servers' sockets and logs, the runs' scratch folders: all gone with the command,
        # wherever the servers' folder was.
        assert list(scratch.iterdir()) == []
        assert list(Path("/tmp").glob(f"pbdval-serve-{process.pid}-*")) == []
    finally:
        if tmpdir_length == "short":
            shutil.rmtree(scratch, ignore_errors=True)


def test_servers_started_before_the_plan_are_stopped_when_there_is_nothing_to_run(
        pbdval_binary: Path, tmp_path: Path) -> None:
    # `pbdval run` starts the servers of the engines it is given by name before it reads the
    # cases; a command that then fails (a case file that does not exist) leaves none running
    # and nothing in $TMPDIR, and one that only lists its plan starts none.
    scratch = Path(tempfile.mkdtemp(prefix="pv-", dir="/tmp"))
    try:
        environment = dict(os.environ, TMPDIR=str(scratch))
        failed = subprocess.run([str(pbdval_binary), "run", str(tmp_path / "no-such-case.json"),
                                 "--engines", "pybullet,mujoco-python", "--out", str(tmp_path / "out")],
                                capture_output=True, text=True, cwd=tmp_path, env=environment,
                                check=False, timeout=120)
        assert failed.returncode == 2 and "no-such-case.json" in failed.stderr, failed.stderr
        listed = subprocess.run([str(pbdval_binary), "run", str(REPO / "cases" / "projectile.json"),
                                 "--engines", "pybullet", "--list-plan", "--out", str(tmp_path / "out")],
                                capture_output=True, text=True, cwd=tmp_path, env=environment,
                                check=False, timeout=120)
        assert listed.returncode == 0, listed.stderr
        assert list(scratch.iterdir()) == []
        # No process left whose command line names the scratch folder (a server's --socket).
        left = []
        for process in Path("/proc").iterdir():
            try:
                if str(scratch) in (process / "cmdline").read_bytes().decode(errors="replace"):
                    left.append(process.name)
            except OSError:
                pass  # not a process, or one that ended meanwhile
        assert left == []
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


TOY_ENGINE = """\
import os, signal, sys, time
sys.path.insert(0, {examples!r})
from euler_engine import run as euler_run  # the template engine's integrator
from pbdval import protocol as pp

LEFT_BY_EARLIER_RUNS = []

def main(argv=None):
    def run(scene, out):
        if LEFT_BY_EARLIER_RUNS or pp.DIVERGENCE_LIMIT != 1e6:
            raise RuntimeError(f"state left by an earlier run: {{LEFT_BY_EARLIER_RUNS}}")
        if "hang" in scene.name:
            time.sleep(300)
        if "crash" in scene.name:
            os.kill(os.getpid(), signal.SIGSEGV)
        result = euler_run(scene, out)
        if "leak" in scene.name:  # globals of the engine and of the protocol module changed
            LEFT_BY_EARLIER_RUNS.append(scene.name)
            pp.DIVERGENCE_LIMIT = 1e-9
        return result
    return pp.serve(argv, "toy", lambda scene: [], run, "toy 1")

if sys.argv[1:2] == ["--serve"]:
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "servers.txt"), "a") as f:
        f.write(f"{{os.getpid()}}\\n")
    sys.exit(pp.serve_runs(sys.argv[2:], main, "toy, persistent"))
sys.exit(main())
"""


def toy_catalogue(tmp_path: Path, engine_source: str = TOY_ENGINE, **serve: Any) -> Path:
    """A catalogue folder with a toy engine (TOY_ENGINE unless given) as `toy`, single-shot and
    served, with `serve`'s extra members in its serve entry (e.g. runsPerChild=4)."""
    catalogue = tmp_path / "catalogue"
    catalogue.mkdir()
    (catalogue / "toy.py").write_text(engine_source.format(examples=str(REPO / "examples")))
    (catalogue / "toy.json").write_text(json.dumps({
        "protocol": 1, "name": "toy", "command": ["{python}", "toy.py"],
        "serve": {"protocol": 1, "command": ["{python}", "toy.py", "--serve"], **serve},
        "defaultMethod": "toy.a", "methods": [{"name": "toy.a", "parameters": []}]}))
    return catalogue


def run_named_projectiles(pbdval_binary: Path, tmp_path: Path, catalogue: Path, order: list[str],
                          jobs: int) -> tuple[dict[str, dict[str, Any]], list[Path]]:
    """`pbdval run` of the projectile case under each name of `order` (the toy engine's mode),
    with the catalogue's toy engine, a 3 s timeout and `jobs` workers: its runs by case name and
    what its servers left in $TMPDIR. The command must succeed."""
    cases = tmp_path / "cases"
    cases.mkdir()
    (cases / "models").symlink_to(REPO / "cases" / "models")  # the meshes the case names
    projectile = (REPO / "cases" / "projectile.json").read_text()
    for name in order:
        (cases / f"{name}.json").write_text(projectile.replace('"Name": "projectile"', f'"Name": "{name}"'))
    # A short $TMPDIR: under pytest's long one the servers' socket paths would not fit a Unix
    # socket's 107 bytes and every run would be single-shot (run_scheduler.cpp, ServerPool).
    scratch = Path(tempfile.mkdtemp(prefix="pbdval-t-", dir="/tmp"))
    try:
        result = subprocess.run([str(pbdval_binary), "run", *[str(cases / f"{n}.json") for n in order],
                                 "--engines", "toy", "--jobs", str(jobs), "--timeout", "3",
                                 "--out", str(tmp_path / "out")],
                                capture_output=True, text=True, cwd=tmp_path, check=False, timeout=600,
                                env=dict(os.environ, TMPDIR=str(scratch),
                                         PBDVAL_ENGINE_CATALOGUE=str(catalogue)))
        left = list(scratch.iterdir())
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    assert result.returncode == 0, result.stderr
    runs = {r["case"]: r for r in json.loads((tmp_path / "out" / "results.json").read_text())["runs"]}
    return runs, left


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_hang_a_crash_and_a_leak_in_pbdval_run_do_not_reach_the_other_runs_of_its_one_server(
        pbdval_binary: Path, tmp_path: Path, jobs: int) -> None:
    catalogue = toy_catalogue(tmp_path)
    order = ["a_first", "b_hang", "c_leak", "d_next", "e_crash", "f_leak", "g_last"]
    runs, left = run_named_projectiles(pbdval_binary, tmp_path, catalogue, order, jobs)
    assert runs["b_hang"]["status"] == "timeout", runs["b_hang"]
    assert runs["e_crash"]["status"] == "error" and "signal 11" in runs["e_crash"]["reason"], runs["e_crash"]
    # Every other run saw a pristine engine (the toy raises on what a leak run left).
    for name in ("a_first", "c_leak", "d_next", "f_leak", "g_last"):
        assert runs[name]["status"] == "ok", runs[name]
    # One server for the whole command, whatever the number of workers, and it outlived the
    # hang and the crash (they are not restarts).
    assert len((catalogue / "servers.txt").read_text().split()) == 1
    # Nothing left: no scratch folder, no socket, no process of the engine.
    assert left == []
    still = [p.name for p in Path("/proc").iterdir() if p.name.isdigit()
             and str(catalogue) in _cmdline(p)]
    assert still == []


def named_scene(export_scene: Callable[..., Path], name: str) -> Path:
    """The projectile's resolved scene under another scene name (the toy engine's mode)."""
    path = export_scene("projectile", method="toy.a", duration=0.1)
    document = json.loads(path.read_text())
    document["name"] = name
    named = path.with_name(f"{name}.json")
    named.write_text(json.dumps(document))
    return named


def test_one_server_runs_a_second_run_while_the_first_hangs_and_kills_a_run_whose_runner_left(
        export_scene: Callable[..., Path], tmp_path: Path) -> None:
    catalogue = toy_catalogue(tmp_path)
    socket_path = tmp_path / "toy.socket"
    log = tmp_path / "toy.stderr"
    with log.open("wb") as errors:
        process = subprocess.Popen([str(VENV_PYTHON), "toy.py", "--serve", "--socket", str(socket_path)],
                                   cwd=catalogue, env=engine_environment(), stdin=subprocess.DEVNULL,
                                   stdout=subprocess.DEVNULL, stderr=errors)
    try:
        deadline = time.monotonic() + 60  # the runner's start limit
        while not socket_path.exists():
            assert process.poll() is None and time.monotonic() < deadline, log.read_text()
            time.sleep(0.01)

        def request_line(scene: Path, out: Path) -> bytes:
            out.mkdir()
            return (json.dumps({"protocol": 1, "scene": str(scene), "out": str(out),
                                "stderr": str(out / "stderr")}) + "\n").encode()

        hanging = socket.socket(socket.AF_UNIX)
        hanging.connect(str(socket_path))
        hanging.sendall(request_line(named_scene(export_scene, "hang"), tmp_path / "hang"))
        started = json.loads(hanging.makefile().readline())
        hanging_pid = started["started"]
        # While that run hangs, the same server runs others to their end: a leak, then one
        # that would see it.
        for name in ("leak", "next"):
            out = tmp_path / name
            replies = request(socket_path, json.loads(request_line(named_scene(export_scene, name), out)))
            assert replies[-1] == {"exited": 0}, (out / "stderr").read_text()
            assert json.loads((out / "status.json").read_text())["status"] == "ok", (out / "status.json").read_text()
        assert Path(f"/proc/{hanging_pid}").exists()  # still hanging meanwhile
        # Its runner leaves (a stopped `pbdval run`): the server kills the run's process group.
        hanging.close()
        deadline = time.monotonic() + 10  # the server looks every 20 ms; generous on a loaded machine
        while hanging_pid in children(process.pid) and time.monotonic() < deadline:
            time.sleep(0.01)
        assert hanging_pid not in children(process.pid)
        assert process.poll() is None  # and serves on
        out = tmp_path / "after"
        replies = request(socket_path, json.loads(request_line(named_scene(export_scene, "after"), out)))
        assert replies[-1] == {"exited": 0}, (out / "stderr").read_text()
    finally:
        process.kill()
        process.wait()


def _cmdline(process: Path) -> str:
    try:
        return (process / "cmdline").read_bytes().decode(errors="replace")
    except OSError:  # it ended meanwhile
        return ""
