"""Cluster benchmarks (docs/cluster.md#measured): the case library run locally with 2 processes
against a Dask cluster of 2 workers (one thread each) on the same machine, in one sitting; and
the planner's and the merger's cost for plans of growing size (about 1,000 to 10,000 runs).

    scripts/bench cluster [--out FILE.json] [--skip-throughput] [--binary PATH] [--before PATH]
                          [--copies N ...] [--repeat N]

--binary times another build's pbdval; --before times a second one (e.g. the main checkout's)
on the same shards, its merges interleaved with --binary's so that both see the same load, and
checks that both write the same merged bytes (but the creation time); --copies sets the plan
sizes (the case library repeated N times); --repeat the merges per binary (the best counts).
Every merge's wall time and CPU time (the process's user + system, from wait4) are recorded.

scripts/bench runs it with .venv/bin/python and PYTHONPATH=python:build/release/python (this
checkout's package and extension; no edit of sys.path here).

Records bench/results/<host>/cluster-<UTC stamp>.json with the machine and the build.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
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


def timed_with_cpu(command: list[str]) -> tuple[float, float]:
    """Wall time and CPU time (user + system of the process and what it waited for) of `command`."""
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    stderr = process.stderr.read() if process.stderr else b""
    if process.returncode != 0:
        raise subprocess.CalledProcessError(process.returncode, command, stderr=stderr)
    return wall, usage.ru_utime + usage.ru_stime


CREATED = re.compile(rb'"created": "[^"]*"')


def merged_bytes(folder: Path) -> bytes:
    """The merged results.json with its creation time blanked (the one field two merges of the
    same shards may write differently)."""
    return CREATED.sub(b'"created": ""', (folder / "results.json").read_bytes())


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


def merge_before_after(folder: Path, shards: list[str], binary: str, before: str, repeat: int) -> dict[str, Any]:
    """Merges of the same shards into a new folder by `before` and `binary`, interleaved, each
    merged file compared byte for byte (but the creation time)."""
    out = folder / "merged-pair"
    times: dict[str, list[tuple[float, float]]] = {"before": [], "after": []}
    same_bytes = True
    for _ in range(repeat):
        written: dict[str, bytes] = {}
        for side, program in (("before", before), ("after", binary)):
            times[side].append(timed_with_cpu([program, "merge", *shards, "--out", str(out), "--quiet"]))
            written[side] = merged_bytes(out)
            shutil.rmtree(out)
        same_bytes = same_bytes and written["before"] == written["after"]
    row: dict[str, Any] = {"same_bytes": same_bytes}
    for side, pairs in times.items():
        row[f"{side}_wall_s"] = [wall for wall, _ in pairs]
        row[f"{side}_cpu_s"] = [cpu for _, cpu in pairs]
        row[f"{side}_best_wall_s"] = min(wall for wall, _ in pairs)
        row[f"{side}_best_cpu_s"] = min(cpu for _, cpu in pairs)
    print(f"  merge before: best {row['before_best_wall_s']:.3f} s wall, {row['before_best_cpu_s']:.3f} s CPU; "
          f"after: best {row['after_best_wall_s']:.3f} s wall, {row['after_best_cpu_s']:.3f} s CPU; "
          f"same bytes: {same_bytes}", flush=True)
    if not same_bytes:
        raise SystemExit("bench_cluster: the two builds' merged results.json differ")
    return row


def plan_and_merge(folder: Path, copies: int, typical: dict[str, Any], binary: str, before: str | None = None,
                   repeat: int = 3) -> dict[str, Any]:
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
    size = int(plan["planSize"])
    pair = merge_before_after(folder, shards, binary, before, repeat) if before else None
    merges = [timed_with_cpu([binary, "merge", *shards, "--out", str(folder / f"merged-{copies}-{k}"), "--quiet"])
              for k in range(repeat)]
    merges_again = [timed_with_cpu([binary, "merge", *shards, "--out", str(folder / f"merged-{copies}-0"), "--quiet"])
                    for _ in range(repeat)]
    merger_s = min(wall for wall, _ in merges)
    merger_again_s = min(wall for wall, _ in merges_again)
    results_bytes = (folder / f"merged-{copies}-0" / "results.json").stat().st_size
    print(f"plan of {size} runs: planner {planner_s:.3f} s, merger {merger_s:.3f} s "
          f"(into a folder holding them: {merger_again_s:.3f} s), results.json {results_bytes / 1e6:.1f} MB",
          flush=True)
    row: dict[str, Any] = {
        "runs": size, "planner_s": planner_s, "merger_s": merger_s, "merger_cpu_s": min(cpu for _, cpu in merges),
        "merger_again_s": merger_again_s, "merger_again_cpu_s": min(cpu for _, cpu in merges_again),
        "results_bytes": results_bytes}
    if pair:
        row["before_after"] = pair
    return row


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--skip-throughput", action="store_true")
    parser.add_argument("--binary", type=Path, default=None, help="the pbdval to time (default: this build's)")
    parser.add_argument("--before", type=Path, default=None,
                        help="another pbdval whose merges are timed interleaved with --binary's")
    parser.add_argument("--copies", type=int, nargs="+", default=[4, 16, 42],
                        help="plan sizes: the case library repeated this many times")
    parser.add_argument("--repeat", type=int, default=3, help="merges per binary and plan (the best counts)")
    args = parser.parse_args()
    binary = str(args.binary or pbdval_binary())
    before = str(args.before) if args.before else None

    def version_of(program: str) -> str:
        return subprocess.run([program, "--version"], capture_output=True, text=True, check=True).stdout.strip()

    document: dict[str, Any] = {"context": {**machine(), "pbdval": version_of(binary), "binary": binary,
                                            "parameters": {"copies": args.copies, "repeat": args.repeat}}}
    if before:
        document["context"]["before"] = {"pbdval": version_of(before), "binary": before}
    with tempfile.TemporaryDirectory(prefix="pbdval-bench-cluster-") as tmp:
        folder = Path(tmp)
        if not args.skip_throughput:
            document["throughput"] = throughput(folder, binary)
        typical = typical_record(folder, binary)
        document["record_bytes"] = len(json.dumps(typical, indent=1))
        document["plan_and_merge"] = [plan_and_merge(folder, copies, typical, binary, before, args.repeat)
                                      for copies in args.copies]
    write_record("cluster", document, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
