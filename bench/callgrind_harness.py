"""Instruction counts (callgrind) of the PBD step, the ball-joint position solve and the harness
around them, on chain_100 (docs/benchmarks.md#instruction-counts). Instruction counts do not
depend on the machine's load, so they are measured where timing is too noisy.

    .venv/bin/python bench/callgrind_harness.py [--duration S] [--json FILE]

Runs `pbdval simulate cases/chain_100.json` (every step written, as CSV and as NPY) and
`pbdval run` of the same case with its own sample interval (the pbd method, one worker;
trajectories as CSV and as NPY) under
`valgrind --tool=callgrind` and prints, from `callgrind_annotate --inclusive=yes`:
instructions in total, in the engine's step (pbd::World::step), in the CSV writer, in the
metrics, the share outside the step, and the instructions per ball-joint position solve
(BallJoint::solvePosition over steps × subSteps × maxIterations × joints). With --json, the
numbers and their metadata (commit, compiler flags from the binary's --version) are written.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PBDVAL = REPO / "build/release/bin/pbdval"
CASE = REPO / "cases/chain_100.json"
FUNCTIONS = {"step": r"pbd::World::step\(\)", "csv": r"pbdval::writeCsvRows\(",
             "npy": r"pbdval::writeTrajectoryNpy\(",
             "metrics": r"pbdval::measureSamples\(", "ball": r"pbd::BallJoint::solvePosition\(",
             "simulation": r"pbdval::runSimulation\("}


def inclusive(profile: Path) -> dict[str, int]:
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(profile)], capture_output=True,
                          text=True, check=True).stdout
    totals = re.search(r"([\d,]+)\s+\(100\.0%\)\s+PROGRAM TOTALS", text)
    if totals is None:
        raise RuntimeError(f"callgrind_annotate printed no PROGRAM TOTALS for {profile}")
    counts = {"total": int(totals.group(1).replace(",", ""))}
    for name, pattern in FUNCTIONS.items():
        match = re.search(r"^\s*([\d,]+) \([\d. ]+%\)\s+\?\?\?:" + pattern, text, re.MULTILINE)
        counts[name] = int(match.group(1).replace(",", "")) if match else 0
    return counts


def profile(arguments: list[str], folder: Path, name: str) -> dict[str, int]:
    """Runs pbdval under callgrind (children traced: `run` isolates each run in a worker) and sums
    the profiles of every process."""
    pattern = folder / f"{name}.%p"
    subprocess.run(["valgrind", "--tool=callgrind", "--trace-children=yes", f"--callgrind-out-file={pattern}",
                    str(PBDVAL), *arguments], check=True, capture_output=True)
    total: dict[str, int] = {}
    for file in sorted(folder.glob(f"{name}.*")):
        for key, value in inclusive(file).items():
            total[key] = total.get(key, 0) + value
    return total


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=0.5, help="simulated seconds for simulate (default 0.5)")
    parser.add_argument("--json", type=Path, help="also write the numbers here")
    args = parser.parse_args()
    scene = json.loads(CASE.read_text())
    sim = scene["Simulation"]
    joints = len(scene.get("BallJoints", []))
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        simulate = profile(["simulate", str(CASE), "--duration", str(args.duration), "--out",
                            str(folder / "c.csv"), "--quiet"], folder, "simulate")
        simulate_npy = profile(["simulate", str(CASE), "--duration", str(args.duration), "--out",
                                str(folder / "c.npy"), "--quiet"], folder, "npy")
        run = profile(["run", str(CASE), "--engines", "pbd", "--methods", "pbd", "--out", str(folder / "out"),
                       "--jobs", "1", "--quiet"], folder, "run")
        run_npy = profile(["run", str(CASE), "--engines", "pbd", "--methods", "pbd", "--out", str(folder / "rnpy"),
                           "--jobs", "1", "--quiet", "--trajectory-format", "npy"], folder, "rnpy")
    steps = round(args.duration / sim["timeStepSize"])
    solves = steps * sim["subSteps"] * sim["maxIterations"] * joints
    report = {"case": "chain_100", "duration_s": args.duration, "ball_joint_solves": solves,
              "simulate": simulate, "simulate_npy": simulate_npy, "run": run, "run_npy": run_npy,
              "instructions_per_ball_solve": simulate["ball"] / solves,
              "simulate_outside_step_share": 1 - simulate["step"] / simulate["total"],
              "simulate_loop_outside_step_share": 1 - simulate["step"] / simulate["simulation"],
              "run_outside_step_share": 1 - run["step"] / run["total"],
              "run_npy_outside_step_share": 1 - run_npy["step"] / run_npy["total"],
              "simulate_npy_outside_step_share": 1 - simulate_npy["step"] / simulate_npy["total"],
              "simulate_npy_loop_outside_step_share": 1 - simulate_npy["step"] / simulate_npy["simulation"],
              "version": subprocess.run([str(PBDVAL), "--version"], capture_output=True, text=True,
                                         check=True).stdout.strip()}
    for label, counts in (("simulate (CSV every step)", simulate), ("simulate (NPY every step)", simulate_npy),
                          ("run (the case's sampling, CSV)", run), ("run (the case's sampling, NPY)", run_npy)):
        print(f"{label}: {counts['total']:,} instructions; step {counts['step'] / counts['total']:.1%}, "
              f"CSV {counts['csv'] / counts['total']:.1%}, NPY {counts['npy'] / counts['total']:.1%}, "
              f"metrics {counts['metrics'] / counts['total']:.1%}, "
              f"outside the step {1 - counts['step'] / counts['total']:.1%}")
    print(f"simulate, the stepping loop only (no start-up): outside the step "
          f"{report['simulate_loop_outside_step_share']:.1%} (CSV), "
          f"{report['simulate_npy_loop_outside_step_share']:.1%} (NPY)")
    print(f"ball-joint position solve: {report['instructions_per_ball_solve']:.0f} instructions "
          f"({solves:,} solves)")
    if args.json:
        args.json.write_text(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
