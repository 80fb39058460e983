"""Cloth and solids across engines: how far each run's particles are from every other's.

    pbdval run cases/tet_bar.json --engines pbd,pybullet,mujoco-python --out out/deformables
    .venv/bin/python examples/deformables_across_engines.py out/deformables

For every case of the results folder, every pair of ok runs that read back particles:
`particle_trajectory_error_rms` and `_max` of one against the other (the runner's metric code:
pbdval.measure with the other run as the reference), and the largest distance between their
mean shapes over the second half of the run (a structure released from rest oscillates about its
static shape, so the time means compare the static shapes).
"""

from __future__ import annotations

import itertools
import sys

import numpy as np

import pbdval


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    results = pbdval.load_results(argv[0])
    print("| case | run | against | particle_trajectory_error_rms (m) | max (m) | mean shapes, 2nd half (m) |")
    print("|---|---|---|---|---|---|")
    for case in results.cases:
        runs = [(r.label, r.trajectory()) for r in results.select(case=case)
                if r.ok and r.particles_path is not None]
        if len(runs) < 2:
            continue
        scene = pbdval.load_scene(results.cases[case]["file"])
        for (name_a, a), (name_b, b) in itertools.combinations(runs, 2):
            metrics = pbdval.measure(scene, a, reference=b)
            half = a.times >= a.times[-1] / 2
            assert a.particle_positions is not None and b.particle_positions is not None
            shape = np.linalg.norm(a.particle_positions[half].mean(axis=0)
                                   - b.particle_positions[half].mean(axis=0), axis=1).max()
            print(f"| {case} | {name_a} | {name_b} | {metrics['particle_trajectory_error_rms']:.3g} | "
                  f"{metrics['particle_trajectory_error_max']:.3g} | {shape:.3g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
