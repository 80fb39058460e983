"""Particle states from `pbdval simulate --particles FILE` (docs/cli.md#particles): one row per
particle per sample, as CSV or NPY (the same table, bit for bit), for a cloth of XPBD distance
constraints pinned at two corners: the pinned particles stay where they are, the cloth falls,
and its edges keep their rest lengths within the stretch its weight can cause."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np

from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[2]
PLANE = REPO / "tests" / "data" / "meshes" / "plane_3x3.obj"  # 1 m × 1 m, 3 × 3 vertices


def cloth_scene(tmp_path: Path) -> Path:
    scene = {
        "Simulation": {"timeStepSize": 0.005, "subSteps": 5, "maxIterations": 2,
                       "clothSimulationMethod": 4, "clothBendingMethod": 0},
        # Pinned at the corners (0, 0, 0) and (1, 0, 0): vertices 0 and 2 of the file.
        "TriangleModels": [{"id": 1, "geometryFile": str(PLANE), "staticParticles": [0, 2]}],
    }
    path = tmp_path / "cloth.json"
    path.write_text(json.dumps(scene))
    return path


def simulate(scene: Path, particles: Path) -> None:
    subprocess.run([str(pbdval_binary()), "simulate", str(scene), "--duration", "1", "--sample-interval", "0.05",
                    "--out", str(particles.with_suffix(".bodies.csv")), "--particles", str(particles), "--quiet"],
                   check=True, capture_output=True, text=True)


def test_particles_as_csv_and_npy(tmp_path: Path) -> None:
    scene = cloth_scene(tmp_path)
    simulate(scene, tmp_path / "p.csv")
    simulate(scene, tmp_path / "p.npy")
    header = (tmp_path / "p.csv").read_text().splitlines()[0]
    assert header == "t,index,x,y,z,vx,vy,vz"
    table = np.load(tmp_path / "p.npy")
    assert table.dtype == np.float64 and table.shape == (21 * 9, 8)  # 21 samples × 9 particles
    assert np.array_equal(table, np.loadtxt(tmp_path / "p.csv", delimiter=",", skiprows=1))

    samples = table.reshape(21, 9, 8)
    assert np.array_equal(samples[:, :, 1], np.tile(np.arange(9), (21, 1)))
    positions = samples[:, :, 2:5]
    # The pinned corners do not move at all.
    for pinned, where in ((0, (0, 0, 0)), (2, (1, 0, 0))):
        assert np.array_equal(positions[:, pinned], np.tile(where, (21, 1)))
    # Pinned at its near corners, the cloth swings down: the far corner (vertex 8, at (1, 0, 1))
    # passes below the pins (0.98 m measured at 0.5 s; it folds, having no bending, so it comes
    # no farther than 1 m from the pinned edge, the x axis).
    far = positions[:, 8]
    assert far[:, 1].min() < -0.9
    assert np.all(np.hypot(far[:, 1], far[:, 2]) < 1.01)
    # Every edge of the file's 8 triangles keeps its rest length within 1 %: the default XPBD
    # stiffness 10⁵ N/m against the weight of at most 7 free particles of 1 kg (the seed's
    # masses) stretches an edge by ≤ 7 × 9.81 / 10⁵ m ≈ 0.7 mm, 0.14 % of 0.5 m, plus swinging.
    rest = positions[0]
    edges = set()
    for face in ((0, 3, 4, 1), (1, 4, 5, 2), (3, 6, 7, 4), (4, 7, 8, 5)):  # the file's quads
        for k in range(4):
            a, b = face[k], face[(k + 1) % 4]
            edges.add((min(a, b), max(a, b)))
    for a, b in edges:
        rest_length = np.linalg.norm(rest[a] - rest[b])
        lengths = np.linalg.norm(positions[:, a] - positions[:, b], axis=1)
        assert np.all(np.abs(lengths / rest_length - 1) < 0.01), (a, b, lengths / rest_length)


def test_free_particles_fall_as_semi_implicit_euler(tmp_path: Path) -> None:
    # clothSimulationMethod 0: no constraints. After n substeps of h_s (v += g h_s, then
    # x += v h_s) a particle from rest is at y = −g h_s² n(n + 1)/2: −4.909905 m after 1 s
    # (n = 1000, h_s = 1 ms). Round-off of 1000 additions to a value of ~5 m, ε each:
    # 10³ × 5 × 2.2·10⁻¹⁶ ≈ 10⁻¹² m; allowed 10⁻¹¹.
    scene = json.loads(cloth_scene(tmp_path).read_text())
    scene["Simulation"]["clothSimulationMethod"] = 0
    path = tmp_path / "free.json"
    path.write_text(json.dumps(scene))
    simulate(path, tmp_path / "free.npy")
    last = np.load(tmp_path / "free.npy").reshape(-1, 9, 8)[-1]
    n, substep, g = 1000, 0.001, 9.81
    assert np.allclose(last[[1, 3, 4, 5, 6, 7, 8], 3], -g * substep**2 * n * (n + 1) / 2, rtol=0, atol=1e-11)
    assert np.array_equal(last[[0, 2], 3], [0.0, 0.0])  # the pinned ones


def test_particles_file_errors_are_named(tmp_path: Path) -> None:
    scene = cloth_scene(tmp_path)
    result = subprocess.run([str(pbdval_binary()), "simulate", str(scene), "--duration", "0.1",
                             "--particles", str(tmp_path)], capture_output=True, text=True, check=False)
    assert result.returncode == 2
    assert str(tmp_path) in result.stderr
