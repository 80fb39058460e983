"""Predictability horizon of a chaotic case, measured with a twin run, and the short-horizon
copy of a case that a convergence sweep against a converged reference uses.

A double pendulum or a chain released horizontally amplifies a perturbation δ of its initial
state to δ·G(t), where the growth G(t) rises roughly as e^{λt} (λ: the largest finite-time
Lyapunov exponent). A method's error at step h behaves like C·hᵖ·G(t) only while that product
is small against the scene's length scale; past that, errors saturate at O(1 m) and a log-log
fit of error against h measures nothing (docs/convergence.md). The twin run measures G(t): the
same scene, once as given and once with every dynamic body and every joint turned by δ about
the first joint's pivot (a rigid rotation of the whole mechanism, so the joints stay satisfied),
both integrated by the same accurate method; G(t) is the largest body separation over δ times
the largest pivot distance.

    .venv/bin/python -m pbdval.horizon twin cases/double_pendulum.json --duration 5
    .venv/bin/python -m pbdval.horizon short cases/double_pendulum.json --duration 1 --out DIR
"""

from __future__ import annotations

import argparse
import copy
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

Vector = tuple[float, float, float]

_JOINT_KEYS = ("HingeJoints", "BallJoints", "UniversalJoints", "SliderJoints")


def _rotate_z(point: Sequence[float], pivot: Sequence[float], angle: float) -> list[float]:
    """`point` turned by `angle` (rad) about the z axis through `pivot`."""
    dx, dy = point[0] - pivot[0], point[1] - pivot[1]
    c, s = math.cos(angle), math.sin(angle)
    return [pivot[0] + c * dx - s * dy, pivot[1] + s * dx + c * dy, float(point[2])]


def joints_of(scene: dict[str, Any]) -> list[dict[str, Any]]:
    """The scene's joints in scene order (hinge, ball, universal, slider)."""
    return [joint for key in _JOINT_KEYS for joint in scene.get(key) or []]


def pivot_of(scene: dict[str, Any], joint: int = 0) -> list[float]:
    """The position of joint `joint` (0: the mechanism's fixed pivot)."""
    joints = joints_of(scene)
    if not 0 <= joint < len(joints):
        raise ValueError(f"joint {joint}: the scene has {len(joints)} hinge, ball, universal or "
                         "slider joints")
    return [float(v) for v in joints[joint]["position"]]


def turned_scene(scene: dict[str, Any], angle: float, joint: int = 0) -> dict[str, Any]:
    """A copy of `scene` with the part of the mechanism beyond joint `joint` turned by `angle`
    (rad) about the z axis through that joint: every dynamic body from the joint's second body
    on (scene order, as in a chain) and the positions of the joints from it on. Joint 0 turns
    the whole mechanism about its pivot. Joint axes along z stay the same; a body that already
    has a rotation or a joint with a non-z axis is refused (the rotation would have to be
    composed, which this twin run does not need)."""
    pivot = pivot_of(scene, joint)
    first_body = int(joints_of(scene)[joint]["bodyID2"])
    ids = [int(body["id"]) for body in scene.get("RigidBodies", [])]
    turned = copy.deepcopy(scene)
    for body in turned.get("RigidBodies", []):
        if not body.get("isDynamic", True) or ids.index(int(body["id"])) < ids.index(first_body):
            continue
        if "rotationAxis" in body or "rotationAngle" in body:
            raise ValueError(f"body {body.get('id')} has a rotation; only unrotated bodies are turned")
        body["translation"] = _rotate_z(body["translation"], pivot, angle)
        body["rotationAxis"] = [0.0, 0.0, 1.0]
        body["rotationAngle"] = angle
    for index, item in enumerate(joints_of(turned)):
        axis = item.get("axis")
        if axis is not None and (abs(axis[0]) > 0 or abs(axis[1]) > 0):
            raise ValueError(f"joint {index}: an axis off z ({axis}) would turn with the bodies")
        if index >= joint:
            item["position"] = _rotate_z(item["position"], pivot, angle)
    return turned


def short_horizon_scene(scene: dict[str, Any], duration: float) -> dict[str, Any]:
    """A copy of `scene` whose Validation.duration is `duration` (s); nothing else changes."""
    if not (duration > 0 and math.isfinite(duration)):
        raise ValueError(f"duration: expected a positive number of seconds, got {duration}")
    short = copy.deepcopy(scene)
    validation = short.setdefault("Validation", {"schema": 1})
    validation["duration"] = duration
    return short


Positions = dict[tuple[float, int], Vector]


def read_positions(path: Path) -> Positions:
    """(t, body id) → centre of mass from a `pbdval simulate` CSV."""
    positions: Positions = {}
    with path.open(newline="") as handle:
        for row in csv.DictReader(handle):
            key = (round(float(row["t"]), 9), int(row["id"]))
            positions[key] = (float(row["x"]), float(row["y"]), float(row["z"]))
    return positions


@dataclass(frozen=True)
class Growth:
    times: list[float]
    growth: list[float]  # G(t): largest separation / (δ · largest pivot distance)

    def first_time_above(self, factor: float) -> float:
        """The first sample time at which G ≥ factor (inf when it never gets there)."""
        for t, g in zip(self.times, self.growth):
            if g >= factor:
                return t
        return math.inf

    def exponent(self, start: float, end: float) -> float:
        """Least-squares slope of log G over [start, end] (1/s): the finite-time Lyapunov
        exponent over that window."""
        points = [(t, math.log(g)) for t, g in zip(self.times, self.growth)
                  if start <= t <= end and g > 0]
        if len(points) < 2:
            raise ValueError(f"fewer than two samples with G > 0 in [{start}, {end}] s")
        mean_t = sum(p[0] for p in points) / len(points)
        mean_y = sum(p[1] for p in points) / len(points)
        num = sum((t - mean_t) * (y - mean_y) for t, y in points)
        den = sum((t - mean_t) ** 2 for t, _ in points)
        return num / den


def growth_of(base: Positions, twin: Positions, angle: float, reach: float) -> Growth:
    """G(t) from the two runs' positions (common samples only)."""
    by_time: dict[float, float] = {}
    for key, p in base.items():
        q = twin.get(key)
        if q is None:
            continue
        d = math.dist(p, q)
        by_time[key[0]] = max(by_time.get(key[0], 0.0), d)
    times = sorted(by_time)
    return Growth(times, [by_time[t] / (angle * reach) for t in times])


def reach_of(scene: dict[str, Any]) -> float:
    """The largest distance of a dynamic body's centre from the pivot (m)."""
    pivot = pivot_of(scene)
    return max(math.dist(body["translation"], pivot)
               for body in scene.get("RigidBodies", []) if body.get("isDynamic", True))


def _simulate(pbdval: str, scene: Path, out: Path, args: Sequence[str]) -> None:
    subprocess.run([pbdval, "simulate", str(scene), "--out", str(out), "--quiet", *args],
                   check=True)


def twin_growth(pbdval: str, case: Path, angle: float, duration: float,
                simulate_args: Sequence[str], joint: int = 0) -> Growth:
    """Runs `case` and its twin turned by `angle` beyond `joint` and returns G(t)."""
    scene = json.loads(case.read_text())
    with tempfile.TemporaryDirectory() as folder:
        base_scene = Path(folder) / case.name
        twin_scene = Path(folder) / ("twin-" + case.name)
        # The model files (geometryFile) are relative to the scene's folder.
        os.symlink(case.parent.resolve() / "models", Path(folder) / "models")
        base_scene.write_text(json.dumps(scene))
        twin_scene.write_text(json.dumps(turned_scene(scene, angle, joint)))
        args = ["--duration", str(duration), *simulate_args]
        _simulate(pbdval, base_scene, Path(folder) / "base.csv", args)
        _simulate(pbdval, twin_scene, Path(folder) / "twin.csv", args)
        return growth_of(read_positions(Path(folder) / "base.csv"),
                         read_positions(Path(folder) / "twin.csv"), angle, reach_of(scene))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pbdval.horizon", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    twin = sub.add_parser("twin", help="measure G(t) with a twin run")
    twin.add_argument("case", type=Path)
    twin.add_argument("--pbdval", default=os.environ.get("PBDVAL", "build/release/bin/pbdval"))
    twin.add_argument("--angle", type=float, default=1e-7, help="δ, rad")
    twin.add_argument("--duration", type=float, default=5.0)
    twin.add_argument("--engine", default="mujoco")
    twin.add_argument("--method", default="mujoco.rk4")
    twin.add_argument("--step", type=float, default=2.5e-4, help="the twin runs' time step, s")
    twin.add_argument("--joint", type=int, default=0,
                      help="turn the mechanism beyond this joint (0: all of it)")
    twin.add_argument("--window", type=float, nargs=2, default=None,
                      help="fit λ over [START, END] s (default: the whole run)")
    short = sub.add_parser("short", help="write the case with a shorter Validation.duration")
    short.add_argument("case", type=Path)
    short.add_argument("--duration", type=float, required=True)
    short.add_argument("--out", type=Path, required=True, help="folder (gets CASE.json, models)")
    args = parser.parse_args(argv)

    if args.command == "short":
        args.out.mkdir(parents=True, exist_ok=True)
        scene = short_horizon_scene(json.loads(args.case.read_text()), args.duration)
        (args.out / args.case.name).write_text(json.dumps(scene, indent=2) + "\n")
        return 0

    growth = twin_growth(args.pbdval, args.case, args.angle, args.duration,
                         ["--engine", args.engine, "--method", args.method,
                          "--set", f"timeStepSize={args.step}", "--sample-interval", "0.01"], args.joint)
    for t, g in zip(growth.times, growth.growth):
        if abs(t * 10 - round(t * 10)) < 1e-6:
            print(f"t = {t:5.2f} s   G = {g:.3e}")
    for factor in (10.0, 1e2, 1e3, 1e4):
        print(f"G first >= {factor:g} at t = {growth.first_time_above(factor):.2f} s")
    start, end = args.window if args.window else (growth.times[1], growth.times[-1])
    print(f"finite-time Lyapunov exponent over [{start}, {end}] s: "
          f"{growth.exponent(start, end):.3f} 1/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
