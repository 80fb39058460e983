"""Cosserat rods' energy through files (docs/cli.md#segments, docs/metrics.md#energy): `pbdval
simulate --segments FILE` writes every rod segment's orientation and angular velocity per sample
(CSV or NPY, the same table bit for bit), `Trajectory.read(..., particles=, segments=)` reads them
back, and `pbdval.measure` on that trajectory gives exactly the runner's metrics (results.json of
`pbdval run`), for an XPBD rod (elastic energy from the segments) and the PBD rod_helix case."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import pbdval
from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[2]
NON_MEASURED = {"wall_time_s", "steps", "real_time_factor"}  # timings, not metrics of states
SEGMENTS = 10


def cantilever_scene(tmp_path: Path) -> Path:
    """A horizontal XPBD cantilever (L = 1 m, 10 segments, r = 1 cm, ρ = 1000 kg/m³,
    E = 1 GPa, ν = 0.3) clamped at its first particle and segment, released at rest; the seed
    step's Gauss–Seidel converged (200 iterations: with the physical quaternion inertia a few
    iterations leave the rod far softer than its moduli, docs/methods.md#cosserat-rods)."""
    scene = {
        "Simulation": {"timeStepSize": 0.001, "subSteps": 1, "maxIterations": 200},
        "LineModels": [{
            "points": [[0.1 * i, 0, 0] for i in range(SEGMENTS + 1)],
            "radius": 0.01, "density": 1000, "youngsModulus": 1e9, "shearModulus": 1e9 / 2.6,
            "staticParticles": [0], "staticSegments": [0],
        }],
        "Validation": {"schema": 1, "duration": 0.4, "sampleInterval": 0.01,
                       "description": "an XPBD cantilever swinging under gravity"},
    }
    path = tmp_path / "cantilever.json"
    path.write_text(json.dumps(scene))
    return path


def simulate(scene: Path, out: Path, suffix: str, method: str, interval: float) -> tuple[Path, Path, Path]:
    files = tuple(out / f"{name}{suffix}" for name in ("bodies", "particles", "segments"))
    subprocess.run([str(pbdval_binary()), "simulate", str(scene), "--method", method,
                    "--sample-interval", str(interval), "--out", str(files[0]),
                    "--particles", str(files[1]), "--segments", str(files[2]), "--quiet"],
                   check=True, capture_output=True, text=True)
    return files  # type: ignore[return-value]


def rotation_matrices(q: np.ndarray) -> np.ndarray:
    """R(q) of (…, 4) unit quaternions (w, x, y, z), written out here."""
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], -2)


def test_segments_as_csv_and_npy(tmp_path: Path) -> None:
    scene = cantilever_scene(tmp_path)
    _, _, csv = simulate(scene, tmp_path, ".csv", "pbd", 0.01)
    _, particles, npy = simulate(scene, tmp_path, ".npy", "pbd", 0.01)
    assert csv.read_text().splitlines()[0] == "t,index,qw,qx,qy,qz,wx,wy,wz"
    table = np.load(npy)
    assert table.dtype == np.float64 and table.shape == (41 * SEGMENTS, 9)  # 41 samples x 10
    assert np.array_equal(table, np.loadtxt(csv, delimiter=",", skiprows=1))
    _times, rotations, angular = pbdval.read_segments(npy)
    assert rotations.shape == (41, SEGMENTS, 4) and angular.shape == (41, SEGMENTS, 3)
    assert np.all(rotations[:, :, 0] >= 0)  # w >= 0, as the body files
    # Unit quaternions (renormalised after every correction): |q| = 1 to a few roundings.
    np.testing.assert_allclose(np.linalg.norm(rotations, axis=-1), 1, rtol=0, atol=1e-14)
    directors = rotation_matrices(rotations)
    # The clamped segment keeps its rest frame (docs/scene-format.md#linemodels: d3 = e_x,
    # d1 = d3 x e_y = e_z) and does not turn; the computation of R: a few roundings.
    np.testing.assert_allclose(directors[:, 0, :, 2], np.tile([1.0, 0, 0], (41, 1)), atol=1e-15)
    np.testing.assert_allclose(directors[:, 0, :, 0], np.tile([0.0, 0, 1], (41, 1)), atol=1e-15)
    assert np.array_equal(angular[:, 0], np.zeros((41, 3)))
    # d3 follows its segment: the shear strain of the stiff rod is ~ weight / (kappa G A) =
    # 3.1 N / 1.2e5 N ~ 3e-5 (a few times that while swinging); 1e-3 leaves room for the
    # Gauss–Seidel residual.
    _, x, _ = pbdval.read_particles(particles)
    tangents = np.diff(x, axis=1)
    tangents /= np.linalg.norm(tangents, axis=-1, keepdims=True)
    assert np.abs(directors[:, :, :, 2] - tangents).max() < 1e-3
    # It swings down to about twice its static sag q L^4/(8 EI) = 4 cm (Euler-Bernoulli), so the
    # segments turn.
    assert 0.06 < -x[:, -1, 1].min() < 0.1 and np.abs(angular).max() > 0.1


@pytest.mark.parametrize("case", ["cantilever", "rod_helix"])
def test_measure_from_files_gives_the_runner_metrics(case: str, tmp_path: Path) -> None:
    scene_path = cantilever_scene(tmp_path) if case == "cantilever" else REPO / "cases/rod_helix.json"
    methods = ["pbd", "pbd.xpbd"] if case == "cantilever" else ["pbd"]
    results = pbdval.run([scene_path], engines=["pbd"], methods=methods, out=tmp_path / "out", jobs=1)
    assert len(results) == len(methods)
    scene = pbdval.load_scene(scene_path)
    interval = 0.01
    for run in results:
        assert run.ok, (run.label, run.reason)
        expected = {k: v for k, v in run.metrics.items() if k not in NON_MEASURED}
        substeps = int(run.facts["integratorStepsPerSceneStep"])
        for suffix in (".csv", ".npy"):
            folder = tmp_path / f"{run.method}{suffix}"
            folder.mkdir()
            bodies, particles, segments = simulate(scene_path, folder, suffix, run.method, interval)
            trajectory = pbdval.Trajectory.read(bodies, particles=particles, segments=segments)
            assert trajectory.segment_rotations is not None
            metrics = pbdval.measure(scene, trajectory, integration_step=scene.time_step / substeps)
            # The same build and input give bitwise-identical PBD runs, the files keep every bit
            # and the energy does not depend on a quaternion's sign: equal to the last bit.
            assert metrics.values == expected, (run.label, suffix)
            assert any("rotational kinetic energy ½ |ω|²/(4 w_q)" in n for n in metrics.notes)
            if case == "cantilever":
                assert any("includes the XPBD Cosserat rods' elastic energy" in n for n in metrics.notes)
                energy = pbdval.energy(scene, trajectory)
                assert energy.elastic is not None and energy.elastic.max() > 0
            # Without the segment file the rods' terms are left out, and a note says so.
            without = pbdval.measure(scene, pbdval.Trajectory.read(bodies, particles=particles),
                                     integration_step=scene.time_step / substeps)
            assert any("rotational kinetic energy" in n and "not included" in n for n in without.notes)


def test_in_memory_trajectory_carries_the_segments(tmp_path: Path) -> None:
    scene = pbdval.load_scene(cantilever_scene(tmp_path))
    info, trajectory = pbdval.simulate(scene, "pbd", duration=0.1, sample_interval=0.01)
    assert info.ok, info.reason
    assert trajectory.segment_rotations is not None and trajectory.segment_angular_velocities is not None
    assert trajectory.segment_rotations.shape == (len(trajectory), SEGMENTS, 4)
    assert trajectory.segment_angular_velocities.shape == (len(trajectory), SEGMENTS, 3)
    # The arrays the core takes back: the same energies as the trajectory read from files.
    bodies, particles, segments = simulate(cantilever_scene(tmp_path), tmp_path, ".npy", "pbd", 0.01)
    read = pbdval.Trajectory.read(bodies, particles=particles, segments=segments)
    # The files hold w >= 0; the engine's quaternions may have either sign (the same rotation).
    assert trajectory.segment_rotations is not None and read.segment_rotations is not None
    signs = np.where(trajectory.segment_rotations[..., :1] < 0, -1.0, 1.0)
    np.testing.assert_array_equal(read.segment_rotations[: len(trajectory)], signs * trajectory.segment_rotations)
    a, b = pbdval.energy(scene, trajectory), pbdval.energy(scene, read)
    np.testing.assert_array_equal(a.total, b.total[: len(trajectory)])
    # Arrays of the wrong shape are refused, naming them.
    bad = pbdval.Trajectory(**{**trajectory.__dict__, "segment_rotations": trajectory.segment_rotations[:, :3]})
    with pytest.raises(Exception, match="segment_rotations"):
        pbdval.energy(scene, bad)


def test_bad_segment_files_are_named(tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("t,index,x,y,z,vx,vy,vz\n0,0,0,0,0,0,0,0\n")
    with pytest.raises(ValueError, match="bad.csv.*header"):
        pbdval.read_segments(bad)
    ragged = tmp_path / "ragged.csv"
    ragged.write_text("t,index,qw,qx,qy,qz,wx,wy,wz\n0,0,1,0,0,0,0,0,0\n0,1,1,0,0,0,0,0,0\n0.1,0,1,0,0,0,0,0,0\n")
    with pytest.raises(ValueError, match="ragged.csv.*whole samples"):
        pbdval.read_segments(ragged)
