"""One case in three engines from Python: the PBD library stepped in this process, pybullet and
MuJoCo (current, from PyPI) through the external-engine protocol; the energy drift of each,
measured by the suite's own metric code (docs/python.md).

    .venv/bin/python examples/energy_drift.py [CASE.json] [--duration S]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import pbdval

REPO = Path(__file__).resolve().parents[1]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", nargs="?", default=str(REPO / "cases/joint_hinge.json"))
    parser.add_argument("--duration", type=float, default=None, help="seconds (default: the case's)")
    args = parser.parse_args()

    scene = pbdval.load_scene(args.case)
    duration, interval = scene.run_length()
    duration = args.duration or duration
    print(f"{Path(args.case).name}: {scene.body_count} bodies, h = {scene.time_step} s, {duration} s")
    print(f"{'engine/method':<32} {'status':<12} {'max |dE|/E_ref':>15} {'final dE/E_ref':>15}")

    # The PBD library, stepped here: sample every `interval` like the runner does.
    sim = pbdval.Simulation(scene, "pbd")
    stride = max(1, round(interval / scene.time_step)) if interval > 0 else 1
    steps = round(duration / scene.time_step)
    states = [sim.state()]
    for done in range(0, steps, stride):
        sim.step(min(stride, steps - done))
        states.append(sim.state())
    trajectory = pbdval.Trajectory(
        times=np.array([s.time for s in states]),
        ids=scene.body_ids,
        positions=np.stack([s.positions for s in states]),
        quaternions=np.stack([s.quaternions for s in states]),
        velocities=np.stack([s.velocities for s in states]),
        angular_velocities=np.stack([s.angular_velocities for s in states]),
    )
    report("pbd/pbd", "ok", pbdval.energy(scene, trajectory).relative_drift)

    # pybullet and MuJoCo in their own processes (the protocol), sampled by the runner's loop.
    for method in ("pybullet", "mujoco-python"):
        info, trajectory = pbdval.simulate(scene, method, duration=duration)
        label = f"{info.engine}/{info.method}"
        if not info.ok:
            report(label, info.status, None)
            continue
        report(label, "ok", pbdval.energy(scene, trajectory).relative_drift)
    return 0


def report(label: str, status: str, drift: np.ndarray | None) -> None:
    if drift is None:
        print(f"{label:<32} {status:<12} {'-':>15} {'-':>15}")
    else:
        print(f"{label:<32} {status:<12} {np.max(np.abs(drift)):>15.3e} {drift[-1]:>15.3e}")


if __name__ == "__main__":
    raise SystemExit(main())
