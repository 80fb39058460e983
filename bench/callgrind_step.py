"""Instruction counts (callgrind) of one engine step and of its parts, per step and per call, for
a few cases and one PBD method (docs/benchmarks.md#closed-form-contacts-in-pbdxpbd-issue-30).
Instruction counts do not depend on the machine's load, so they compare builds where timing on
a shared machine cannot.

    .venv/bin/python bench/callgrind_step.py [--pbdval PATH] [--method pbd.xpbd]
        [--duration 0.25] [--label NAME] [--set KEY=VALUE ...] CASE...

Runs `pbdval simulate CASE --engine pbd --method M --duration D [--set KEY=VALUE ...]` under
`valgrind --tool=callgrind` and reads, from the profile, the inclusive instructions and the
number of calls of the step and of its parts (contact set-up and solves, prediction, velocity
update, collision detection, joint solves). Writes them with their metadata (machine, the
binary's --version, the arguments) to bench/results/<host>/callgrind-step-<UTC stamp>.json
through bench_record.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

from bench_record import REPO, machine, write_record

PARTS = {
    "step": "pbd::World::step()",
    "contact_approach": "pbd::XpbdContact::beginSubstep(",
    "contact_follow": "pbd::XpbdContact::followSupportPoint(",
    "contact_position": "pbd::XpbdContact::solvePosition(",
    "contact_velocity": "pbd::XpbdContact::solveVelocity(",
    "predict": "pbd::predictPositions(",
    "velocity_update": "pbd::updateVelocities(",
    "detection": "pbd::CollisionDetector::detect(",
    "joint_positions": "pbd::solveJointPositionsXpbd(",
    "point_constraint": "pbd::projectPointConstraint(",
    "rotation_prediction": "pbd::integration::semiImplicitEulerRotation(",
}


def read_profile(profile: Path) -> dict[str, dict[str, int]]:
    """Inclusive instructions (callgrind_annotate) and call counts (the profile's calls= lines)
    of every part."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", str(profile)], capture_output=True,
                          text=True, check=True).stdout
    names: dict[str, str] = {}
    calls: Counter[str] = Counter()
    callee = ""
    with profile.open(encoding="utf-8", errors="replace") as lines:
        for line in lines:
            named = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line)
            if named:
                kind, key, name = named.groups()
                if name:
                    names[key] = name.strip()
                if kind == "cfn":
                    callee = names.get(key, key)
                continue
            counted = re.match(r"calls=(\d+)", line)
            if counted and callee:
                calls[callee] += int(counted.group(1))
    parts: dict[str, dict[str, int]] = {}
    for part, signature in PARTS.items():
        pattern = r"^\s*([\d,]+) \([\d. ]+%\)\s+\?\?\?:" + re.escape(signature)
        match = re.search(pattern, text, re.MULTILINE)
        instructions = int(match.group(1).replace(",", "")) if match else 0
        called = sum(count for name, count in calls.items() if name.startswith(signature))
        parts[part] = {"instructions": instructions, "calls": called}
    return parts


def profile_case(pbdval: Path, case: Path, method: str, duration: float,
                 assignments: list[str]) -> dict[str, Any]:
    """One case under callgrind (`assignments`: the method parameters, --set KEY=VALUE): every
    part's instructions per step and per call."""
    with tempfile.TemporaryDirectory() as scratch:
        out = Path(scratch) / "profile.out"
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", str(pbdval),
                        "simulate", str(case), "--engine", "pbd", "--method", method, "--duration",
                        str(duration), "--out", str(Path(scratch) / "t.npy"), "--quiet",
                        *(arg for assignment in assignments for arg in ("--set", assignment))],
                       check=True, capture_output=True)
        parts = read_profile(out)
    steps = parts["step"]["calls"]
    if steps == 0:
        raise RuntimeError(f"{case}: no call of pbd::World::step() in the profile")
    summary: dict[str, Any] = {"case": case.stem, "steps": steps, "parts": parts}
    summary["per_step"] = {part: values["instructions"] / steps for part, values in parts.items()}
    summary["per_call"] = {part: values["instructions"] / values["calls"]
                           for part, values in parts.items() if values["calls"] > 0}
    summary["calls_per_step"] = {part: values["calls"] / steps for part, values in parts.items()}
    return summary


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("cases", nargs="+", type=Path, help="scene files")
    parser.add_argument("--pbdval", type=Path, default=REPO / "build/release/bin/pbdval")
    parser.add_argument("--method", default="pbd.xpbd")
    parser.add_argument("--duration", type=float, default=0.25, help="simulated seconds (default 0.25)")
    parser.add_argument("--label", default="", help="a name for this build in the record (e.g. before, after)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="KEY=VALUE",
                        help="a method parameter for every case, passed to pbdval simulate (repeatable)")
    args = parser.parse_args()
    results = [profile_case(args.pbdval, case, args.method, args.duration, args.assignments)
               for case in args.cases]
    for result in results:
        print(f"{result['case']}: {result['per_step']['step']:,.0f} instructions per step; "
              f"contacts {result['calls_per_step']['contact_position']:.1f} per step "
              f"(over its substeps)")
    version = subprocess.run([str(args.pbdval), "--version"], capture_output=True, text=True,
                             check=True).stdout.strip()
    write_record("callgrind-step", {"machine": machine(), "version": version, "label": args.label,
                                    "method": args.method, "duration_s": args.duration,
                                    "assignments": args.assignments,
                                    "results": results})
    return 0


if __name__ == "__main__":
    sys.exit(main())
