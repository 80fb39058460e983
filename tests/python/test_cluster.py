"""The Dask executor (python/pbdval/cluster.py, docs/cluster.md) on a real cluster started here:
a scheduler and two workers (one thread each) on 127.0.0.1 from the project's venv. The merged
results must equal a local run of the same plan (statuses, metrics, trajectories, PBD state
hashes); faults must lose nothing or be reported as a status."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from pbdval import cluster
from pbdval.results import Results, load_results, pbdval_binary

REPO = Path(__file__).resolve().parents[2]
VENV = REPO / ".venv" / "bin"
CASES = [str(REPO / "cases" / f"{c}.json") for c in ("joint_hinge", "chain_10", "projectile", "contact_sphere_drop")]
RUN_ARGS = [*CASES, "--engines", "pbd,ode,bullet"]
RUNS = len(CASES) * 4  # per case: pbd and pbd.xpbd (the PBD engine's run methods), ode, bullet
TIMING = {"wall_time_s", "real_time_factor"}
START_TIMEOUT = 60.0  # s for the scheduler and workers to come up on a loaded 2-core machine


def start(command: list[str], log: Path, env: dict[str, str]) -> subprocess.Popen[bytes]:
    return subprocess.Popen(command, stdout=log.open("wb"), stderr=subprocess.STDOUT, env=env,
                            start_new_session=True)


@pytest.fixture(scope="module")
def scheduler_file(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    folder = tmp_path_factory.mktemp("dask")
    file = folder / "scheduler.json"
    env = {**os.environ,
           # A task on workers that died twice is given up (the "crashes a worker twice" test).
           "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "1",
           # One task per worker thread at a time (the default 1.1 queues a second one): a worker
           # killed by one task then takes no other task's count of deaths with it.
           "DASK_DISTRIBUTED__SCHEDULER__WORKER_SATURATION": "1.0",
           # Workers import this module's task functions (the fault tests).
           "PYTHONPATH": os.pathsep.join([str(Path(__file__).parent), str(REPO / "python")]),
           # Where the fault tests' tasks leave their markers (shared by both workers).
           "PBDVAL_CLUSTER_TEST_FOLDER": str(folder)}
    processes = [start([str(VENV / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0",
                        "--no-dashboard", "--scheduler-file", str(file)], folder / "scheduler.log", env)]
    deadline = time.monotonic() + START_TIMEOUT
    while not file.exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert file.exists(), (folder / "scheduler.log").read_text()
    for name in ("w1", "w2"):
        processes.append(start([str(VENV / "dask"), "worker", "--scheduler-file", str(file), "--nthreads", "1",
                                "--nworkers", "1", "--no-dashboard", "--name", name, "--host", "127.0.0.1"],
                               folder / f"{name}.log", env))
    from distributed import Client

    with Client(scheduler_file=str(file), timeout=START_TIMEOUT) as client:
        client.wait_for_workers(2, timeout=START_TIMEOUT)
    yield file
    for p in processes:
        os.killpg(p.pid, signal.SIGTERM)
    for p in processes:
        try:
            p.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)


def comparable(folder: Path) -> list[tuple[Any, ...]]:
    return [(r.case, r.engine, r.method, r.status, {k: v for k, v in r.metrics.items() if k not in TIMING},
             r.trajectory().positions.tobytes() if r.ok else b"") for r in load_results(folder)]


def local_run(folder: Path) -> Path:
    subprocess.run([str(pbdval_binary()), "run", *RUN_ARGS, "--out", str(folder), "--jobs", "2", "--quiet"],
                   check=True, capture_output=True)
    return folder


def test_the_cluster_gives_what_a_local_run_gives(scheduler_file: Path, tmp_path: Path) -> None:
    out = tmp_path / "dask"
    done = subprocess.run([str(pbdval_binary()), "run", *RUN_ARGS, "--executor", "dask", "--scheduler-file",
                           str(scheduler_file), "--out", str(out)], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert f"{RUNS} runs in {RUNS} tasks on 2 Dask workers" in done.stderr
    local = local_run(tmp_path / "local")
    assert comparable(out) == comparable(local)
    hashes = [r.get("state_hash") for r in json.loads((out / "results.json").read_text())["runs"]]
    assert any(hashes)
    assert hashes == [r.get("state_hash") for r in json.loads((local / "results.json").read_text())["runs"]]
    assert not (out / ".slices").exists()


def test_a_sweep_on_the_cluster_fits_what_a_local_sweep_fits(scheduler_file: Path, tmp_path: Path) -> None:
    sweep = [str(REPO / "cases" / "joint_hinge.json"), "--param", "timeStepSize=0.004,0.002,0.001",
             "--methods", "pbd,mujoco.rk4", "--reference", "fine"]
    done = subprocess.run([str(pbdval_binary()), "sweep", *sweep, "--executor", "dask", "--scheduler-file",
                           str(scheduler_file), "--out", str(tmp_path / "dask")],
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    subprocess.run([str(pbdval_binary()), "sweep", *sweep, "--out", str(tmp_path / "local"), "--quiet"],
                   check=True, capture_output=True)
    dask = json.loads((tmp_path / "dask" / "sweep.json").read_text())
    local = json.loads((tmp_path / "local" / "sweep.json").read_text())
    assert [(p["method"], p["parameters"], p["status"], p["metric"]) for p in dask["points"]] == \
        [(p["method"], p["parameters"], p["status"], p["metric"]) for p in local["points"]]
    assert [(f["method"], f["orders"], f["r_squared"], f["flags"]) for f in dask["fits"]] == \
        [(f["method"], f["orders"], f["r_squared"], f["flags"]) for f in local["fits"]]


def test_bad_arguments_are_reported_by_the_pbdval_command(scheduler_file: Path, tmp_path: Path) -> None:
    done = subprocess.run([str(pbdval_binary()), "run", *RUN_ARGS, "--methods", "no.such", "--executor", "dask",
                           "--scheduler-file", str(scheduler_file), "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, check=False)
    assert done.returncode == 2 and "no.such" in done.stderr


# --- faults -----------------------------------------------------------------------------------

def kill_worker_once(binary: str, run_args: list[str], index: int, count: int,
                     command: str = "run") -> cluster.SliceOutput:
    """Slice 2's first attempt kills the worker it runs on (the nanny restarts it)."""
    marker = Path(os.environ["PBDVAL_CLUSTER_TEST_FOLDER"]) / "killed-once"
    if index == 2 and not marker.exists():
        marker.write_text("killed once")
        os._exit(1)
    return cluster.run_slice(binary, run_args, index, count, command)


def kill_worker_always(binary: str, run_args: list[str], index: int, count: int,
                       command: str = "run") -> cluster.SliceOutput:
    if index == 1:
        os._exit(1)
    return cluster.run_slice(binary, run_args, index, count, command)


def test_a_worker_killed_mid_run_loses_nothing(scheduler_file: Path, tmp_path: Path) -> None:
    from distributed import Client

    with Client(scheduler_file=str(scheduler_file), timeout=START_TIMEOUT) as client:
        results = cluster.run_on_cluster(client, RUN_ARGS, tmp_path / "out", quiet=True, task=kill_worker_once)
        assert isinstance(results, Results)  # `run` gives a results folder
        client.wait_for_workers(2, timeout=START_TIMEOUT)  # the nanny brought it back
    assert all(r.ok for r in results), [(r.case, r.label, r.reason) for r in results if not r.ok]
    assert comparable(tmp_path / "out") == comparable(local_run(tmp_path / "local"))


def test_a_run_that_kills_workers_twice_is_an_error(scheduler_file: Path, tmp_path: Path) -> None:
    from distributed import Client

    with Client(scheduler_file=str(scheduler_file), timeout=START_TIMEOUT) as client:
        results = cluster.run_on_cluster(client, RUN_ARGS, tmp_path / "out", quiet=True, task=kill_worker_always)
        assert isinstance(results, Results)  # `run` gives a results folder
        client.wait_for_workers(2, timeout=START_TIMEOUT)
    failed = [r for r in results if not r.ok]
    assert len(failed) == 1 and failed[0].status == "error"
    assert "workers that died" in failed[0].reason
    assert len(results) == RUNS and sum(r.ok for r in results) == RUNS - 1


def test_workers_of_another_build_are_refused(scheduler_file: Path, tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    from distributed import Client

    real = cluster.build_identity
    # The client's identity changes here only; workers import the real function.
    monkeypatch.setattr(cluster, "build_identity", lambda binary: real(binary).replace("commit:", "commit: other"))
    with (Client(scheduler_file=str(scheduler_file), timeout=START_TIMEOUT) as client,
          pytest.raises(cluster.ClusterError, match="runs another pbdval build")):
        cluster.run_on_cluster(client, RUN_ARGS, tmp_path / "out", quiet=True)


def test_an_unreachable_scheduler_is_a_clear_error_within_the_timeout(tmp_path: Path) -> None:
    start_time = time.monotonic()
    done = subprocess.run([str(pbdval_binary()), "run", *RUN_ARGS, "--executor", "dask", "--scheduler",
                           "tcp://127.0.0.1:9", "--connect-timeout", "2", "--out", str(tmp_path / "o")],
                          capture_output=True, text=True, check=False)
    elapsed = time.monotonic() - start_time
    assert done.returncode == 2
    assert "cannot reach the Dask scheduler tcp://127.0.0.1:9 within 2 s" in done.stderr
    assert elapsed < 15  # 2 s of connecting, plus interpreter and Dask import time
