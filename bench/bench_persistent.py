#!/usr/bin/env python3
"""The cost of external engines in a suite run (docs/benchmarks.md#persistent-engines): the
wall time of one `pbdval run` of many short cases, per engine, the Python engines against their
C++ twins (pybullet against bullet, mujoco-python against mujoco). Speed is measured here, never
asserted in tests.

    scripts/bench persistent [--binary PBDVAL] [--before PBDVAL]
        [--cases A,B,...] [--jobs N] [--repeat N] [--all-methods] [--out FILE.json]

The Python engines run as Python runs by default, their bytecode cached: a PYTHONDONTWRITEBYTECODE
in the environment (set in some sandboxes) would make every engine server compile the engines'
sources again at its start (15-20 ms of CPU each); the measured commands get the environment
without it, and PYTHONPYCACHEPREFIX pointing into the bench's own temporary folder (nothing is
written into the source tree), filled by one untimed run of each engine first.
--keep-environment measures with the environment as it is.

--before names another pbdval binary (e.g. a build without persistent engines) measured the same
way, interleaved with --binary, so that both see the same machine load. Each figure is the best
(minimum) of --repeat runs, the usual estimate of a cost on a machine whose other load only ever
adds time. Beside the wall time, the CPU time of the whole command (every process it started:
less sensitive to the other load of a shared machine than the wall time). The statuses of every
run are recorded beside the times.
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import resource
import subprocess
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

from bench_record import machine, write_record  # bench/, the script's own folder

REPO = Path(__file__).resolve().parents[1]

CASES = ["projectile", "free_tumbling_box", "joint_ball", "joint_hinge", "double_pendulum",
         "double_pendulum_boxes", "chain_10", "chain_mass_ratio", "contact_resting_box",
         "contact_incline_slide", "contact_incline_stick", "contact_sphere_drop",
         "contact_seed_bounce", "contact_seed_sink", "contact_rolling_sphere", "contact_stack_5",
         "contact_pyramid", "contact_sphere_pile", "contact_bowling_ball", "xpbd_resting_box",
         "xpbd_bouncing_sphere", "xpbd_incline_slide", "xpbd_incline_stick", "xpbd_pendulum_hinge"]
PAIRS = [("pybullet", "bullet"), ("mujoco-python", "mujoco")]
#: One run per case on both sides of a pair: pybullet's catalogue runs two methods per case
#: (runMethods: maximal coordinates and multibodies), bullet one; the pair compares pybullet.si,
#: the maximal-coordinate method (btRigidBody, as the built-in engine). --all-methods times
#: each engine's own run methods instead (pybullet then makes twice the runs).
SAME_RUNS = {"pybullet": ["--methods", "pybullet.si"]}


def children_cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


_PR_SET_CHILD_SUBREAPER = 36  # <linux/prctl.h>


def adopt_orphans() -> None:
    """Makes this process the subreaper of every process it starts: a process whose parent ends
    first (an engine server's children, killed when their server is: serve.runsPerChild keeps
    them alive between runs, so their server never reaps them) becomes this one's, and its CPU
    time is counted in RUSAGE_CHILDREN once reap_orphans has reaped it."""
    ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)


def reap_orphans() -> None:
    """Reaps the processes adopted during a command (each dies with its server: PR_SET_PDEATHSIG)."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            time.sleep(0.005)


def measured_environment(bytecode_cache: Path | None) -> dict[str, str]:
    """The environment of the measured commands: this one, or (`bytecode_cache` given) without
    PYTHONDONTWRITEBYTECODE and with Python's bytecode cached in that folder."""
    environment = dict(os.environ)
    if bytecode_cache is not None:
        environment.pop("PYTHONDONTWRITEBYTECODE", None)
        environment["PYTHONPYCACHEPREFIX"] = str(bytecode_cache)
    return environment


def run_once(binary: Path, engine: str, cases: list[str], jobs: int, extra: list[str],
             environment: dict[str, str]) -> tuple[float, float, dict[str, int]]:
    """Wall seconds of one `pbdval run` of `cases` in `engine` (`extra` arguments added), its
    CPU seconds (user and system, its every process: runs, engine servers and their children),
    and its runs' statuses."""
    with tempfile.TemporaryDirectory(prefix="pbdval-bench-persistent-") as folder:
        command = [str(binary), "run", *[str(REPO / "cases" / f"{c}.json") for c in cases],
                   "--engines", engine, "--jobs", str(jobs), "--out", str(Path(folder) / "out"),
                   "--timeout", "600", *extra]
        cpu_before = children_cpu_seconds()
        start = time.perf_counter()
        result = subprocess.run(command, capture_output=True, text=True, check=False, cwd=folder,
                                env=environment)
        seconds = time.perf_counter() - start
        reap_orphans()
        cpu = children_cpu_seconds() - cpu_before
        if result.returncode not in (0, 1):  # 1: some run not ok (a gate of its own), still timed
            raise RuntimeError(f"{' '.join(command)} exited {result.returncode}: {result.stderr[-2000:]}")
        runs = json.loads((Path(folder) / "out" / "results.json").read_text())["runs"]
        return seconds, cpu, dict(Counter(r["status"] for r in runs))


def measure(binaries: dict[str, Path], cases: list[str], jobs: int, repeat: int,
            extra: dict[str, list[str]], environment: dict[str, str],
            warm_up: bool) -> dict[str, Any]:
    engines = [e for pair in PAIRS for e in pair]
    if warm_up:  # the bytecode cache filled (and the files read once), untimed
        for binary in binaries.values():
            for python, _ in PAIRS:
                run_once(binary, python, cases[:2], jobs, extra.get(python, []), environment)
    best: dict[str, dict[str, float]] = {label: {} for label in binaries}
    best_cpu: dict[str, dict[str, float]] = {label: {} for label in binaries}
    statuses: dict[str, dict[str, dict[str, int]]] = {label: {} for label in binaries}
    for attempt in range(repeat):
        for label, binary in binaries.items():
            for engine in engines:
                seconds, cpu, counts = run_once(binary, engine, cases, jobs, extra.get(engine, []),
                                                environment)
                best[label][engine] = min(seconds, best[label].get(engine, float("inf")))
                best_cpu[label][engine] = min(cpu, best_cpu[label].get(engine, float("inf")))
                statuses[label][engine] = counts
                print(f"[{attempt + 1}/{repeat}] {label} {engine}: {seconds:.2f} s (CPU {cpu:.2f} s) "
                      f"{counts}", flush=True)
    ratios = {label: {f"{python}/{cpp}": best[label][python] / best[label][cpp] for python, cpp in PAIRS}
              for label in binaries}
    cpu_ratios = {label: {f"{python}/{cpp}": best_cpu[label][python] / best_cpu[label][cpp]
                          for python, cpp in PAIRS} for label in binaries}
    return {"best_wall_s": best, "best_cpu_s": best_cpu, "statuses": statuses, "ratios": ratios,
            "cpu_ratios": cpu_ratios}


def context(binaries: dict[str, Path], cases: list[str], jobs: int, repeat: int,
            extra: dict[str, list[str]], bytecode_cache: bool) -> dict[str, Any]:
    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True, check=False).stdout.strip()
    return {
        **machine(), "commit": commit,
        "binaries": {label: {"path": str(b), "version": subprocess.run(
            [str(b), "--version"], capture_output=True, text=True, check=False).stdout.strip()}
            for label, b in binaries.items()},
        "cases": cases, "jobs": jobs, "repeat": repeat, "engine_arguments": extra,
        "python_bytecode_cached": bytecode_cache,
        "PYTHONDONTWRITEBYTECODE_in_environment": os.environ.get("PYTHONDONTWRITEBYTECODE"),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--binary", type=Path, default=REPO / "build" / "release" / "bin" / "pbdval")
    parser.add_argument("--before", type=Path, default=None, help="another pbdval to compare with")
    parser.add_argument("--cases", default=",".join(CASES))
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--all-methods", action="store_true",
                        help="each engine's own run methods (pybullet: two runs per case)")
    parser.add_argument("--keep-environment", action="store_true",
                        help="measure with the environment as it is (PYTHONDONTWRITEBYTECODE kept)")
    parser.add_argument("--out", type=Path, default=None,
                        help="JSON file (default: bench/results/<host>/persistent-<UTC stamp>.json)")
    args = parser.parse_args()
    adopt_orphans()
    cases = [c for c in args.cases.split(",") if c]
    binaries = {"after": args.binary.resolve()}
    if args.before is not None:
        binaries["before"] = args.before.resolve()
    extra = {} if args.all_methods else SAME_RUNS
    with tempfile.TemporaryDirectory(prefix="pbdval-bench-bytecode-") as cache:
        bytecode_cache = None if args.keep_environment else Path(cache)
        environment = measured_environment(bytecode_cache)
        document = {"context": context(binaries, cases, args.jobs, args.repeat, extra,
                                       bytecode_cache is not None),
                    **measure(binaries, cases, args.jobs, args.repeat, extra, environment,
                              warm_up=bytecode_cache is not None)}
    for label, ratios in document["ratios"].items():
        print(label, "wall", {k: round(v, 2) for k, v in ratios.items()},
              "CPU", {k: round(v, 2) for k, v in document["cpu_ratios"][label].items()})
    write_record("persistent", document, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
