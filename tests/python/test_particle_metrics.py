"""Particle models through the Python API (docs/python.md, docs/metrics.md#particle-models): a
simulated cloth's trajectory carries its particles, `measure` reports the stretch of its edges
and `energy` the XPBD constraints' elastic energy, each equal to an independent numpy computation
from the same arrays; the `--particles` file of `pbdval simulate` reads back to the same arrays."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import pbdval
from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[2]
PLANE = REPO / "tests" / "data" / "meshes" / "plane_3x3.obj"  # 1 m × 1 m, 3 × 3 vertices
STIFFNESS = 2000.0  # N/m: soft enough that the cloth's weight stretches it measurably


def cloth_scene(tmp_path: Path) -> Path:
    scene = {
        "Simulation": {"timeStepSize": 0.005, "subSteps": 5, "maxIterations": 2,
                       "clothSimulationMethod": 4, "clothBendingMethod": 0, "cloth_stiffness": STIFFNESS},
        "Validation": {"duration": 0.5, "sampleInterval": 0.05},
        "TriangleModels": [{"id": 1, "geometryFile": str(PLANE), "staticParticles": [0, 2]}],
    }
    path = tmp_path / "cloth.json"
    path.write_text(json.dumps(scene))
    return path


def edges_of(obj: Path) -> list[tuple[int, int]]:
    """Every edge of the OBJ's faces once, each polygon split into a fan around its first vertex
    as docs/scene-format.md says the loader does (an independent reading of the file)."""
    edges: set[tuple[int, int]] = set()
    for line in obj.read_text().splitlines():
        if line.startswith("f "):
            face = [int(token.split("/")[0]) - 1 for token in line.split()[1:]]
            for k in range(1, len(face) - 1):
                for a, b in ((face[0], face[k]), (face[k], face[k + 1]), (face[k + 1], face[0])):
                    edges.add((min(a, b), max(a, b)))
    return sorted(edges)


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[pbdval.Scene, pbdval.Trajectory, Path]:
    tmp_path = tmp_path_factory.mktemp("cloth")
    path = cloth_scene(tmp_path)
    scene = pbdval.load_scene(path)
    info, trajectory = pbdval.simulate(scene, "pbd")
    assert info.ok, info
    return scene, trajectory, path


def test_trajectory_carries_the_particles(run: tuple[pbdval.Scene, pbdval.Trajectory, Path]) -> None:
    _, trajectory, _ = run
    assert trajectory.particle_positions is not None and trajectory.particle_velocities is not None
    assert trajectory.particle_positions.shape == (len(trajectory), 9, 3)
    assert trajectory.particle_velocities.shape == (len(trajectory), 9, 3)
    # The pinned corners (vertices 0 and 2 at (0,0,0) and (1,0,0)) never move.
    assert np.array_equal(trajectory.particle_positions[:, 0], np.zeros((len(trajectory), 3)))
    assert np.array_equal(trajectory.particle_positions[:, 2], np.tile([1.0, 0, 0], (len(trajectory), 1)))


def test_stretch_metrics_equal_numpy(run: tuple[pbdval.Scene, pbdval.Trajectory, Path]) -> None:
    scene, trajectory, _ = run
    metrics = pbdval.measure(scene, trajectory, reference=False)
    x = trajectory.particle_positions
    assert x is not None
    edges = edges_of(PLANE)
    assert len(edges) == 16
    strains = np.array([np.linalg.norm(x[:, a] - x[:, b], axis=1) / np.linalg.norm(x[0, a] - x[0, b]) - 1
                        for a, b in edges])
    # The same formula over the same doubles, summed in another order: round-off ~10⁻¹⁶ of
    # strains of O(10⁻³).
    assert metrics["particle_stretch_max"] == pytest.approx(np.abs(strains).max(), rel=1e-12)
    assert metrics["particle_stretch_rms"] == pytest.approx(np.sqrt(np.mean(strains**2)), rel=1e-12)
    # The cloth hangs from two corners: its weight (7 free particles of 1 kg, the seed's masses)
    # stretches the edges by up to about 7 · 9.81 N / 2000 N/m ≈ 3.4 cm on 0.5 m edges, a strain
    # of order 10⁻², and it is measurably stretched at all.
    assert 1e-3 < metrics["particle_stretch_max"] < 0.2
    assert "tet_volume_error_max" not in metrics  # no tet models


def test_elastic_energy_equals_numpy(run: tuple[pbdval.Scene, pbdval.Trajectory, Path]) -> None:
    scene, trajectory, _ = run
    energy = pbdval.energy(scene, trajectory)
    x = trajectory.particle_positions
    assert x is not None and energy.elastic is not None
    # ½ k (ℓ − ℓ₀)² over the edges with a free end (the edge 0–2 does not exist: both pinned
    # corners are on the border, not joined by an edge of the plane).
    expected = np.zeros(len(trajectory))
    for a, b in edges_of(PLANE):
        rest = np.linalg.norm(x[0, a] - x[0, b])
        expected += 0.5 * STIFFNESS * (np.linalg.norm(x[:, a] - x[:, b], axis=1) - rest) ** 2
    assert energy.elastic[0] == 0.0
    np.testing.assert_allclose(energy.elastic, expected, rtol=1e-12, atol=1e-15)
    # The total includes it: total = translational + rotational + gravitational + spring + elastic.
    np.testing.assert_allclose(
        energy.total, energy.translational + energy.rotational + energy.gravitational + energy.spring + energy.elastic,
        rtol=1e-14, atol=1e-12)


def test_particle_file_reads_back_to_the_same_arrays(
        run: tuple[pbdval.Scene, pbdval.Trajectory, Path], tmp_path: Path) -> None:
    _, trajectory, path = run
    for suffix in (".csv", ".npy"):
        bodies, particles = tmp_path / f"bodies{suffix}", tmp_path / f"particles{suffix}"
        subprocess.run([str(pbdval_binary()), "simulate", str(path), "--duration", "0.5", "--sample-interval", "0.05",
                        "--out", str(bodies), "--particles",
                        str(particles), "--quiet"], check=True, capture_output=True, text=True)
        read = pbdval.Trajectory.read(bodies, particles=particles)
        assert read.particle_positions is not None and trajectory.particle_positions is not None
        # The same build and input give bitwise-identical PBD results; CSV keeps 17 digits.
        np.testing.assert_array_equal(read.particle_positions, trajectory.particle_positions)
        np.testing.assert_array_equal(read.particle_velocities, trajectory.particle_velocities)


def test_bad_particle_files_are_named(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("t,x\n0,1\n")
    with pytest.raises(ValueError, match="bad.csv.*header"):
        pbdval.read_particles(bad)
    ragged = tmp_path / "ragged.csv"
    ragged.write_text("t,index,x,y,z,vx,vy,vz\n0,0,0,0,0,0,0,0\n0,1,0,0,0,0,0,0\n0.1,0,0,0,0,0,0,0\n")
    with pytest.raises(ValueError, match="ragged.csv.*whole samples"):
        pbdval.read_particles(ragged)


def test_mesh_export_writes_the_particles_surface(
        run: tuple[pbdval.Scene, pbdval.Trajectory, Path], tmp_path: Path) -> None:
    # docs/cli.md#mesh-export: frame k at the first state at or after k / fps. With 10 fps over
    # 0.5 s of 5 ms steps: frames 0..5, each the cloth's particles at t = k / 10 exactly the
    # states sampled every 0.1 s.
    _, _, path = run
    export = tmp_path / "meshes"
    particles = tmp_path / "p.npy"
    subprocess.run([str(pbdval_binary()), "simulate", str(path), "--duration", "0.5", "--sample-interval", "0.1",
                    "--out", str(tmp_path / "b.csv"), "--particles", str(particles), "--export-dir", str(export),
                    "--export-format", "ply", "--export-fps", "10", "--quiet"],
                   check=True, capture_output=True, text=True)
    assert sorted(p.name for p in export.iterdir()) == [f"cloth0_{k:05d}.ply" for k in range(6)]
    _, positions, _ = pbdval.read_particles(particles)
    assert positions.shape[0] == 6
    for k in range(6):
        data = (export / f"cloth0_{k:05d}.ply").read_bytes()
        body = data[data.index(b"end_header\n") + len(b"end_header\n"):]
        vertices = np.frombuffer(body[: 9 * 3 * 8], dtype="<f8").reshape(9, 3)
        np.testing.assert_array_equal(vertices, positions[k])  # float64 written as is
