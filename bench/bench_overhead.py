"""What a run costs outside its stepping (docs/benchmarks.md#outside-the-stepping): `pbdval run`
of one case and one method, the whole command's wall time against the engine's stepping time
(the run's `wall_time_s`: the sum of its step() calls), interleaved between two builds.

    scripts/bench overhead [--binary PATH] [--before PATH] [--case FILE] [--method M]
                           [--repeat N] [--multi K] [--library] [--out FILE.json]

Each repetition runs, for each build in turn, `pbdval run CASE --engines E --methods M --jobs 1`
twice: with the case's own reference and with `--reference none` (the harness alone). The share
outside the stepping is 1 - wall_time_s / (the command's wall time). `--multi K` also runs,
in each repetition, one command of K copies of the case (`--reference none`): the start-up is
paid once there, and a run's share of the wall time is (T_K - T_1) / (K - 1), against its
stepping time (docs/benchmarks.md#outside-the-stepping). `--library` also times
`pbdval run cases --jobs 2` (the whole case library) once per build, interleaved.

scripts/bench runs it with .venv/bin/python and PYTHONPATH=python:build/release/python.
Records bench/results/<host>/overhead-<UTC stamp>.json with the machine, both builds and the
parameters.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Any

from bench_record import machine, write_record  # bench/, the script's own folder

from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[1]


def timed(command: list[str]) -> tuple[float, float]:
    """Wall time and CPU time (user + system of the process and of the processes it waited for,
    its runs' children) of `command`."""
    start = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    stderr = process.stderr.read() if process.stderr else b""
    if os.waitstatus_to_exitcode(status) != 0:
        raise subprocess.CalledProcessError(os.waitstatus_to_exitcode(status), command, stderr=stderr)
    return wall, usage.ru_utime + usage.ru_stime


def run_once(program: str, out: Path, case: Path, engine: str, method: str, reference: bool) -> dict[str, Any]:
    command = [program, "run", str(case), "--engines", engine, "--methods", method, "--jobs", "1",
               "--out", str(out), "--quiet", "--force"]
    if not reference:
        command += ["--reference", "none"]
    wall, cpu = timed(command)
    runs = json.loads((out / "results.json").read_text())["runs"]
    if len(runs) != 1 or runs[0]["status"] not in ("ok", "suspect"):
        raise SystemExit(f"bench_overhead: expected one measured run, got {[r['status'] for r in runs]}")
    stepping = float(runs[0]["metrics"]["wall_time_s"])
    return {"wall_s": wall, "cpu_s": cpu, "stepping_s": stepping, "steps": runs[0]["metrics"]["steps"],
            "outside_share": 1 - stepping / wall, "metrics": runs[0]["metrics"]}


def copies_of(case: Path, count: int, folder: Path) -> Path:
    """A folder of `count` copies of `case` (named NAME_k), its meshes reachable as beside the
    case (relative geometry paths)."""
    folder.mkdir()
    text = case.read_text()
    name = json.loads(text)["Name"]
    for k in range(count):
        copy = re.sub(r'"Name"\s*:\s*"[^"]*"', f'"Name": "{name}_{k}"', text, count=1)
        (folder / f"{name}_{k}.json").write_text(copy)
    for entry in case.parent.iterdir():
        if entry.is_dir():
            (folder / entry.name).symlink_to(entry.resolve())
    return folder


def run_many(program: str, out: Path, cases: Path, engine: str, method: str) -> dict[str, Any]:
    """One `pbdval run` of a folder of cases (--reference none): its wall time and the runs'
    stepping."""
    command = [program, "run", str(cases), "--engines", engine, "--methods", method, "--jobs", "1",
               "--out", str(out), "--quiet", "--force", "--reference", "none"]
    wall, cpu = timed(command)
    runs = json.loads((out / "results.json").read_text())["runs"]
    if any(run["status"] not in ("ok", "suspect") for run in runs):
        raise SystemExit(f"bench_overhead: expected measured runs, got {[r['status'] for r in runs]}")
    stepping = sum(float(run["metrics"]["wall_time_s"]) for run in runs)
    timings = {"wall_time_s", "real_time_factor"}
    metrics = sorted(json.dumps({"case": run["case"], **{name: value for name, value in run["metrics"].items()
                                                          if name not in timings}}, sort_keys=True)
                     for run in runs)
    return {"wall_s": wall, "cpu_s": cpu, "stepping_s": stepping, "runs": len(runs),
            "outside_share": 1 - stepping / wall, "metrics": metrics}


def summary(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Medians of the repetitions (the machine is shared: single figures move by tens of per cent)."""
    def median(key: str) -> float:
        values = sorted(float(r[key]) for r in rows)
        return values[len(values) // 2]
    return {"median_wall_s": median("wall_s"), "median_cpu_s": median("cpu_s"),
            "median_stepping_s": median("stepping_s"), "median_outside_share": median("outside_share"),
            "best_wall_s": min(float(r["wall_s"]) for r in rows), "best_cpu_s": min(float(r["cpu_s"]) for r in rows)}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", type=Path, default=None, help="the pbdval to time (default: this build's)")
    parser.add_argument("--before", type=Path, default=None, help="another pbdval, timed interleaved")
    parser.add_argument("--case", type=Path, default=REPO / "cases" / "double_pendulum.json")
    parser.add_argument("--engine", default="pbd")
    parser.add_argument("--method", default="pbd")
    parser.add_argument("--repeat", type=int, default=9)
    parser.add_argument("--multi", type=int, default=0,
                        help="also run K copies of the case in one command (start-up paid once)")
    parser.add_argument("--library", action="store_true", help="also time `pbdval run cases --jobs 2`")
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    builds = {"after": str(args.binary or pbdval_binary())}
    if args.before:
        builds = {"before": str(args.before), **builds}

    def version_of(program: str) -> str:
        return subprocess.run([program, "--version"], capture_output=True, text=True, check=True).stdout.strip()

    document: dict[str, Any] = {
        "context": {**machine(), "builds": {side: {"binary": program, "pbdval": version_of(program)}
                                            for side, program in builds.items()},
                    "parameters": {"case": str(args.case), "engine": args.engine, "method": args.method,
                                   "repeat": args.repeat, "jobs": 1, "multi": args.multi,
                                   "library": args.library}}}
    rows: dict[str, dict[str, list[dict[str, Any]]]] = {
        side: {"reference": [], "no_reference": []} for side in builds}
    many: dict[str, list[dict[str, Any]]] = {side: [] for side in builds}
    with tempfile.TemporaryDirectory(prefix="pbdval-bench-overhead-") as tmp:
        folder = Path(tmp)
        copies = copies_of(args.case, args.multi, folder / "copies") if args.multi > 1 else None
        for k in range(args.repeat):
            for side, program in builds.items():
                for reference in (True, False):
                    row = run_once(program, folder / f"{side}-{reference}", args.case, args.engine, args.method,
                                   reference)
                    rows[side]["reference" if reference else "no_reference"].append(row)
                if copies:
                    many[side].append(run_many(program, folder / f"{side}-many", copies, args.engine, args.method))
            print(f"repetition {k + 1}/{args.repeat}: " + "; ".join(
                f"{side} {rows[side]['reference'][-1]['wall_s'] * 1e3:.1f} / "
                f"{rows[side]['no_reference'][-1]['wall_s'] * 1e3:.1f} ms" for side in builds), flush=True)
        # The results themselves must not change: every metric but the timings, bit for bit.
        timings = {"wall_time_s", "real_time_factor"}
        for kind in ("reference", "no_reference"):
            values = {side: {name: value for name, value in rows[side][kind][0]["metrics"].items()
                             if name not in timings} for side in builds}
            if len({json.dumps(v, sort_keys=True) for v in values.values()}) != 1:
                raise SystemExit(f"bench_overhead: the builds' metrics differ ({kind})")
        if args.multi > 1 and len({json.dumps(many[side][0]["metrics"]) for side in builds}) != 1:
            raise SystemExit("bench_overhead: the builds' metrics differ (multi)")
        document["same_metrics"] = True
        if args.multi > 1:
            document["multi"] = {}
            for side in builds:
                for row in many[side]:
                    del row["metrics"]
                many_summary = summary(many[side])
                single = summary(rows[side]["no_reference"])
                per_run_wall = (many_summary["median_wall_s"] - single["median_wall_s"]) / (args.multi - 1)
                per_run_stepping = many_summary["median_stepping_s"] / args.multi
                document["multi"][side] = {
                    "runs": args.multi, "summary": many_summary, "repetitions": many[side],
                    "per_run_wall_s": per_run_wall, "per_run_stepping_s": per_run_stepping,
                    "per_run_outside_share": 1 - per_run_stepping / per_run_wall}
                print(f"{side}, {args.multi} runs in one command: median wall "
                      f"{many_summary['median_wall_s'] * 1e3:.1f} ms, per run {per_run_wall * 1e3:.2f} ms "
                      f"of which stepping {per_run_stepping * 1e3:.2f} ms: "
                      f"{1 - per_run_stepping / per_run_wall:.1%} outside", flush=True)
        for side in builds:
            for kind in ("reference", "no_reference"):
                for row in rows[side][kind]:
                    del row["metrics"]
        document["runs"] = {side: {kind: {"summary": summary(kinds[kind]), "repetitions": kinds[kind]}
                                   for kind in kinds} for side, kinds in rows.items()}
        for side in builds:
            for kind in ("reference", "no_reference"):
                s = document["runs"][side][kind]["summary"]
                print(f"{side}, {kind}: median wall {s['median_wall_s'] * 1e3:.1f} ms, "
                      f"CPU {s['median_cpu_s'] * 1e3:.1f} ms, stepping {s['median_stepping_s'] * 1e3:.1f} ms: "
                      f"{s['median_outside_share']:.1%} outside")
        if args.library:
            library: dict[str, Any] = {}
            for side, program in builds.items():
                out = folder / f"library-{side}"
                wall, cpu = timed([program, "run", str(REPO / "cases"), "--jobs", "2", "--out", str(out), "--quiet"])
                runs = json.loads((out / "results.json").read_text())["runs"]
                statuses: dict[str, int] = {}
                for run in runs:
                    statuses[run["status"]] = statuses.get(run["status"], 0) + 1
                library[side] = {"wall_s": wall, "cpu_s": cpu, "runs": len(runs), "statuses": statuses}
                print(f"case library, {side}: {wall:.1f} s wall, {cpu:.1f} s CPU, {len(runs)} runs {statuses}",
                      flush=True)
            document["library"] = library
    write_record("overhead", document, args.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
