"""`pbdval run` and `pbdval sweep` on a Dask cluster (docs/cluster.md).

    pbdval run [CASES...] [run options] --executor dask --scheduler tcp://HOST:8786
    pbdval sweep CASE --param ... [sweep options] --executor dask --scheduler-file FILE
    .venv/bin/python -m pbdval.cluster run|sweep [ARGS...] --scheduler ADDRESS

One plan, several executors: the plan is the pbdval command's own (`pbdval run --list-plan`);
every task runs one slice of it on a worker with the pbdval command itself (`pbdval run ...
--shard K/N`: the same isolation per run, timeouts and statuses as a local run) and sends back
the slice's folder (results.json and trajectories, zlib-compressed); the client writes the
slices and joins them with `pbdval merge`, so results.json and trajectories/ are what a local
run of the same plan writes. Workers must see the pbdval build and the case files at the same
paths as the client (a shared file system, or the same machine).

Faults: a worker that dies takes its running task with it; the scheduler runs the task again
elsewhere. A task that was running when workers died more than the scheduler allows
(`distributed.scheduler.allowed-failures`, default 3) is recorded as status `error` with the
reason, and the rest completes. An unreachable scheduler is an error after --connect-timeout
seconds; workers whose pbdval build differs from the client's are refused, naming both.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import zlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pbdval.errors import PbdvalError
from pbdval.results import Results, load_results, pbdval_binary

#: The commands that can run on the cluster.
COMMANDS = ("run", "sweep")


class ClusterError(PbdvalError, RuntimeError):
    """The cluster cannot run the plan: unreachable scheduler, mismatched workers, bad usage."""


@dataclass(frozen=True)
class SliceOutput:
    """What a task sends back: the slice folder's files (relative path → zlib-compressed bytes),
    the worker's host, and how long the slice took."""

    index: int
    files: dict[str, bytes]
    host: str
    seconds: float
    raw_bytes: int


def build_identity(binary: str) -> str:
    """`pbdval --version` of a build: version, commit (and local changes), build, precision."""
    return subprocess.run([binary, "--version"], capture_output=True, text=True, check=True).stdout.strip()


def worker_build_identity(binary: str) -> str:
    """build_identity, as run on each worker (a function of its own, so that the two sides of
    the comparison are computed independently)."""
    return subprocess.run([binary, "--version"], capture_output=True, text=True, check=True).stdout.strip()


def run_slice(binary: str, run_args: Sequence[str], index: int, count: int,
              command: str = "run") -> SliceOutput:
    """The task: `pbdval COMMAND RUN_ARGS --shard INDEX/COUNT` in a temporary folder on the
    worker, its files sent back compressed. Runs in the worker's process; the runs themselves in
    the pbdval command's child processes."""
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="pbdval-slice-") as folder:
        argv = [binary, command, *run_args, "--shard", f"{index}/{count}", "--out", folder,
                "--jobs", "1", "--quiet"]
        done = subprocess.run(argv, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            raise RuntimeError(f"pbdval {command} --shard {index}/{count} exited {done.returncode}: "
                               f"{done.stderr.strip()[-2000:]}")
        files: dict[str, bytes] = {}
        raw = 0
        for path in sorted(Path(folder).rglob("*")):
            if path.is_file():
                data = path.read_bytes()
                raw += len(data)
                files[str(path.relative_to(folder))] = zlib.compress(data, 1)
    return SliceOutput(index, files, socket.gethostname(), time.perf_counter() - start, raw)


def write_slice(output: SliceOutput, folder: Path) -> None:
    """A slice's files under `folder`; its results.json names trajectories by the worker's
    temporary folder, so they are renamed to where they are now."""
    for relative, packed in output.files.items():
        target = folder / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(zlib.decompress(packed))
    results = folder / "results.json"
    document = json.loads(results.read_text())
    for run in document.get("runs", []):
        trajectory = run.get("trajectory") or ""
        marker = "/trajectories/"
        if marker in trajectory:
            run["trajectory"] = str(folder / ("trajectories/" + trajectory.split(marker, 1)[1]))
    temporary = results.with_suffix(".json.tmp")
    temporary.write_text(json.dumps(document, indent=1))
    os.replace(temporary, results)


def parse_arguments(command: str, argv: Sequence[str]) -> tuple[argparse.Namespace, list[str]]:
    """The client's own options; everything else is passed to `pbdval COMMAND` unchanged (the
    pbdval command checks it, once, when it lists the plan)."""
    parser = argparse.ArgumentParser(prog=f"pbdval {command} --executor dask",
                                     description=f"pbdval {command} on a Dask cluster (docs/cluster.md)")
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--scheduler", help="the scheduler's address, e.g. tcp://10.0.0.5:8786")
    where.add_argument("--scheduler-file", help="the scheduler's file (dask scheduler --scheduler-file)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    parser.add_argument("--connect-timeout", type=float, default=10.0,
                        help="seconds to reach the scheduler (default 10)")
    parser.add_argument("--runs-per-task", type=int, default=None,
                        help="runs per Dask task (default: the plan over 16 tasks per worker, at "
                             "least 1: start-up amortised, balance and fault isolation kept)")
    parser.add_argument("--quiet", action="store_true", help="no progress, only the summary")
    parser.add_argument("--jobs", type=int, default=None, help=argparse.SUPPRESS)  # local only
    args, passed = parser.parse_known_args(argv)
    if args.runs_per_task is not None and args.runs_per_task < 1:
        parser.error("--runs-per-task: expected at least 1")
    return args, passed


def plan_of(binary: str, run_args: Sequence[str], command: str = "run") -> dict[str, Any]:
    done = subprocess.run([binary, command, *run_args, "--list-plan"], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise ClusterError(done.stderr.strip() or f"pbdval {command} --list-plan exited {done.returncode}")
    plan: dict[str, Any] = json.loads(done.stdout)
    return plan


def connect(args: argparse.Namespace) -> Any:
    from distributed import Client  # imported only by the Dask executor

    address = args.scheduler or args.scheduler_file
    try:
        if args.scheduler_file:
            if not Path(args.scheduler_file).is_file():
                raise ClusterError(f"--scheduler-file {args.scheduler_file}: no such file")
            return Client(scheduler_file=args.scheduler_file, timeout=args.connect_timeout)
        return Client(args.scheduler, timeout=args.connect_timeout)
    except (OSError, TimeoutError) as error:
        raise ClusterError(f"cannot reach the Dask scheduler {address} within {args.connect_timeout:g} s: "
                           f"{error}") from error


def check_workers(client: Any, binary: str) -> int:
    """Every worker must run the client's pbdval build; returns the number of workers."""
    mine = build_identity(binary)
    theirs: dict[str, str] = client.run(worker_build_identity, binary)
    if not theirs:
        raise ClusterError("the Dask cluster has no workers")
    for worker, identity in theirs.items():
        if identity != mine:
            raise ClusterError(f"worker {worker} runs another pbdval build:\n  worker: "
                               + identity.replace("\n", "; ") + "\n  client: " + mine.replace("\n", "; "))
    return len(theirs)


#: Tasks per worker when --runs-per-task is not given. Each task pays a start-up (a pbdval
#: process that plans before it runs: 50-100 ms); one task per run cost the case library 51 %
#: over a local run, 16 tasks per worker 5 % (docs/cluster.md#measured).
TASKS_PER_WORKER = 16


def run_on_cluster(client: Any, run_args: Sequence[str], out: Path, *, runs_per_task: int | None = None,
                   quiet: bool = False, task: Callable[..., SliceOutput] = run_slice,
                   command: str = "run") -> Results | Path:
    """Runs the plan of `pbdval COMMAND RUN_ARGS` on `client`'s cluster and writes OUT as the
    local command does: a results folder for `run` (returned as Results), sweep.json for
    `sweep` (its path returned). `task` is the function each task runs (tests replace it to
    kill workers)."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    binary = str(pbdval_binary())
    plan = plan_of(binary, run_args, command)
    size = int(plan["planSize"])
    workers = check_workers(client, binary)
    if runs_per_task is None:
        runs_per_task = max(1, -(-size // (TASKS_PER_WORKER * workers)))
    count = max(1, -(-size // runs_per_task))
    slices = out / ".slices"
    if slices.exists():
        shutil.rmtree(slices)
    slices.mkdir(parents=True)
    if not quiet:
        print(f"pbdval {command}: {size} runs in {count} tasks on {workers} Dask workers "
              f"({client.scheduler.address}), output in {out}/", file=sys.stderr, flush=True)
    futures = {client.submit(task, binary, list(run_args), k, count, command,
                             key=f"pbdval-slice-{k}-of-{count}-{plan['planDigest']}", pure=False, retries=0): k
               for k in range(1, count + 1)}
    sent = raw = 0
    start = time.perf_counter()
    for done, future in enumerate(as_completed(futures), start=1):
        k = futures[future]
        try:
            output: SliceOutput = future.result()
            write_slice(output, slices / str(k))
            sent += sum(len(v) for v in output.files.values())
            raw += output.raw_bytes
            line = f"slice {k} on {output.host} in {output.seconds:.1f} s"
        except KilledWorker as error:
            reason = (f"the run's Dask task was on workers that died ({error}); not retried "
                      "further (distributed.scheduler.allowed-failures)")
            record_failure(binary, run_args, k, count, reason, slices / str(k), command)
            line = f"slice {k}: error: workers died running it"
        except Exception as error:  # noqa: BLE001  (any task failure becomes the runs' status)
            record_failure(binary, run_args, k, count, f"the Dask task failed: {error}", slices / str(k), command)
            line = f"slice {k}: error: {error}"
        if not quiet:
            print(f"[{done:3d}/{count}] {time.perf_counter() - start:6.1f} s  {line}", file=sys.stderr, flush=True)
    folders = [str(slices / str(k)) for k in range(1, count + 1)]
    if command == "sweep":
        joined = subprocess.run([binary, "sweep", *run_args, "--from-shards", ",".join(folders), "--out", str(out)],
                                capture_output=True, text=True, check=False)
    else:
        force = ["--force"] if "--force" in run_args else []  # the run's own --force, for its --out
        joined = subprocess.run([binary, "merge", *folders, "--out", str(out), "--move", "--quiet", *force],
                                capture_output=True, text=True, check=False)
    if joined.returncode != 0:
        raise ClusterError(f"joining the slices failed: {joined.stderr.strip()}")
    shutil.rmtree(slices)
    if not quiet:
        print(joined.stdout.strip(), file=sys.stderr)
        print(f"pbdval {command}: the workers sent {sent / 1e6:.2f} MB (compressed from {raw / 1e6:.2f} MB)",
              file=sys.stderr)
    if command == "sweep":
        return out / "sweep.json"
    return load_results(out)


def record_failure(binary: str, run_args: Sequence[str], index: int, count: int, reason: str,
                   folder: Path, command: str = "run") -> None:
    """The slice's runs as status error with `reason`, written by the pbdval command itself."""
    if folder.exists():
        shutil.rmtree(folder)
    done = subprocess.run([binary, command, *run_args, "--shard", f"{index}/{count}", "--fail-with", reason,
                           "--out", str(folder), "--quiet"], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise ClusterError(f"could not record the failure of slice {index}: {done.stderr.strip()}")


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] not in COMMANDS:
        print("usage: python -m pbdval.cluster run|sweep [ARGS...] --scheduler ADDRESS [options]", file=sys.stderr)
        return 2
    command = argv[0]
    args, run_args = parse_arguments(command, argv[1:])
    try:
        with connect(args) as client:
            outcome = run_on_cluster(client, run_args, Path(args.out), runs_per_task=args.runs_per_task,
                                     quiet=args.quiet, command=command)
    except ClusterError as error:
        print(f"pbdval {command} --executor dask: error: {error}", file=sys.stderr)
        return 2
    if isinstance(outcome, Path):
        print(f"wrote {outcome}")
        return 0
    statuses: dict[str, int] = {}
    for r in outcome:
        statuses[r.status] = statuses.get(r.status, 0) + 1
    print(f"{len(outcome)} runs: " + ", ".join(f"{n} {s}" for s, n in sorted(statuses.items()))
          + f"; results in {Path(args.out) / 'results.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
