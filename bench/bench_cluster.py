"""Cluster benchmarks (docs/cluster.md#measured): the case library run locally with 2 processes
against a Dask cluster of 2 workers (one thread each) on the same machine, in one sitting; and
the planner's and the merger's cost for plans of growing size (about 1,000 to 10,000 runs).

    scripts/bench cluster [--out FILE.json] [--skip-throughput] [--binary PATH] [--copies N ...]

--binary times another build's pbdval (e.g. the main checkout's, for a before/after pair in one
sitting); --copies sets the plan sizes (the case library repeated N times).

scripts/bench runs it with .venv/bin/python and PYTHONPATH=python:build/release/python (this
checkout's package and extension; no edit of sys.path here).

Records bench/results/<host>/cluster-<UTC stamp>.json with the machine and the build.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from bench_record import machine, write_record  # bench/, the script's own folder

from pbdval.results import load_results, pbdval_binary

REPO = Path(__file__).resolve().parents[1]

VENV = REPO / ".venv" / "bin"


def timed(command: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - start


def throughput(folder: Path, binary: str) -> dict[str, Any]:
    local_s = timed([binary, "run", "--out", str(folder / "local"), "--jobs", "2", "--quiet"])
    runs = len(load_results(folder / "local"))
    scheduler_file = folder / "scheduler.json"
    processes = [subprocess.Popen([str(VENV / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0",
                                   "--no-dashboard", "--scheduler-file", str(scheduler_file)],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)]
    while not scheduler_file.exists():
        time.sleep(0.1)
    for name in ("w1", "w2"):
        processes.append(subprocess.Popen([str(VENV / "dask"), "worker", "--scheduler-file", str(scheduler_file),
                                           "--nthreads", "1", "--no-dashboard", "--name", name],
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                          start_new_session=True))
    try:
        from distributed import Client

        with Client(scheduler_file=str(scheduler_file)) as client:
            client.wait_for_workers(2, timeout=60)
        start = time.perf_counter()
        done = subprocess.run([binary, "run", "--executor", "dask", "--scheduler-file", str(scheduler_file),
                               "--out", str(folder / "dask")], check=True, capture_output=True, text=True)
        dask_s = time.perf_counter() - start
        sent = [line for line in done.stderr.splitlines() if "the workers sent" in line]
        tasks = [line for line in done.stderr.splitlines() if " tasks on " in line]
    finally:
        for p in processes:
            os.killpg(p.pid, signal.SIGTERM)
    row = {"runs": runs, "local_s": local_s, "dask_s": dask_s, "local_runs_per_s": runs / local_s,
           "dask_runs_per_s": runs / dask_s, "dask_over_local": dask_s / local_s,
           "tasks": tasks[0] if tasks else "", "data_sent": sent[0] if sent else ""}
    print(row["tasks"], row["data_sent"], sep="\n")
    print(f"case library: {runs} runs; local (2 processes) {local_s:.1f} s, Dask (2 workers) {dask_s:.1f} s: "
          f"ratio {dask_s / local_s:.3f}", flush=True)
    return row


def typical_record(folder: Path, binary: str) -> dict[str, Any]:
    """The record of a real run (metrics, per-joint errors, effective settings, notes): the
    merger is measured on records of realistic size, not on bare error records."""
    out = folder / "typical"
    subprocess.run([binary, "run", str(REPO / "cases" / "car.json"), "--engines", "bullet",
                    "--out", str(out), "--quiet", "--no-trajectories"], check=True, capture_output=True)
    record: dict[str, Any] = json.loads((out / "results.json").read_text())["runs"][0]
    return record


def plan_and_merge(folder: Path, copies: int, typical: dict[str, Any], binary: str) -> dict[str, Any]:
    """A plan of `copies` × the case library (each case file linked `copies` times)."""
    cases = folder / f"cases-{copies}"
    cases.mkdir()
    (cases / "models").symlink_to(REPO / "cases" / "models")
    for case in sorted((REPO / "cases").glob("*.json")):
        for k in range(copies):
            (cases / f"{case.stem}__{k}.json").symlink_to(case)
    plan = json.loads(subprocess.run([binary, "run", str(cases), "--list-plan"], capture_output=True,
                                     text=True, check=True).stdout)
    planner_s = min(timed([binary, "run", str(cases), "--list-plan"]) for _ in range(3))
    shards = []
    for k in (1, 2):
        out = folder / f"shard-{copies}-{k}"
        subprocess.run([binary, "run", str(cases), "--shard", f"{k}/2", "--fail-with", "not run (benchmark)",
                        "--out", str(out), "--quiet", "--no-trajectories"], check=True, capture_output=True)
        document = json.loads((out / "results.json").read_text())
        for run in document["runs"]:
            for key in ("status", "reason", "parameters", "settings", "facts", "metrics", "joint_error_by_type",
                        "notes", "reference"):
                if key in typical:
                    run[key] = typical[key]
        (out / "results.json").write_text(json.dumps(document, indent=1))
        shards.append(str(out))
    # Each merge into a new folder (a merge into a folder holding results reads them first, to
    # refuse another plan's: `merger_again_s` is that case).
    merger_s = min(timed([binary, "merge", *shards, "--out", str(folder / f"merged-{copies}-{k}"), "--quiet"])
                   for k in range(3))
    merger_again_s = min(timed([binary, "merge", *shards, "--out", str(folder / f"merged-{copies}-0"), "--quiet"])
                         for _ in range(3))
    size = int(plan["planSize"])
    results_bytes = (folder / f"merged-{copies}-0" / "results.json").stat().st_size
    print(f"plan of {size} runs: planner {planner_s:.3f} s, merger {merger_s:.3f} s "
          f"(into a folder holding them: {merger_again_s:.3f} s), results.json {results_bytes / 1e6:.1f} MB",
          flush=True)
    return {"runs": size, "planner_s": planner_s, "merger_s": merger_s, "merger_again_s": merger_again_s,
            "results_bytes": results_bytes}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--skip-throughput", action="store_true")
    parser.add_argument("--binary", type=Path, default=None, help="the pbdval to time (default: this build's)")
    parser.add_argument("--copies", type=int, nargs="+", default=[4, 16, 42],
                        help="plan sizes: the case library repeated this many times")
    args = parser.parse_args()
    binary = str(args.binary or pbdval_binary())
    version = subprocess.run([binary, "--version"], capture_output=True, text=True,
                             check=True).stdout.strip()
    document: dict[str, Any] = {"context": {**machine(), "pbdval": version, "binary": binary}}
    with tempfile.TemporaryDirectory(prefix="pbdval-bench-cluster-") as tmp:
        folder = Path(tmp)
        if not args.skip_throughput:
            document["throughput"] = throughput(folder, binary)
        typical = typical_record(folder, binary)
        document["record_bytes"] = len(json.dumps(typical, indent=1))
        document["plan_and_merge"] = [plan_and_merge(folder, copies, typical, binary) for copies in args.copies]
    write_record("cluster", document, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
