"""The protocol's particle side (python/pbdval/protocol.py, docs/external-engines.md#particles):
the resolved scene's cloth and solid models, and the particle trajectory an engine writes."""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from pbdval import protocol as pp


def test_a_cloths_topology_masses_and_material_come_through(export_scene: Callable[..., Path]) -> None:
    scene = pp.read_resolved_scene(export_scene("cloth_hanging", method="pbd"))
    assert len(scene.triangle_models) == 1 and not scene.tet_models
    cloth = scene.triangle_models[0]
    assert (cloth.first_particle, cloth.particle_count) == (0, len(scene.particles))
    x = np.array([p.position for p in scene.particles])
    # The 1 m x 1 m square of the case: the triangles tile it, so their areas sum to 1 m^2
    # (closed form; round-off ~1e-16 per triangle).
    a, b, c = (x[cloth.triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    assert area.sum() == pytest.approx(1.0, rel=1e-12)
    # Lumped masses: a third of density x area from each triangle to each of its vertices,
    # static particles 0. So the total is 0.3 kg less the static vertices' shares, computed here
    # from the triangles alone (round-off ~1e-16 kg per term).
    masses = np.array([p.mass for p in scene.particles])
    assert all(masses[i] == 0 for i in cloth.static_particles)
    assert cloth.density == 0.3
    static_share = sum(0.3 * area[t] / 3 for t in range(len(area))
                       for v in cloth.triangles[t] if v in cloth.static_particles)
    assert static_share > 0
    assert masses.sum() == pytest.approx(0.3 - static_share, rel=1e-12)
    assert (cloth.method_name, cloth.bending_method_name) == ("xpbd_distance", "isometric_xpbd")
    assert cloth.material["stiffness"] == 1000 and cloth.material["bendingStiffness"] == 1


def test_a_solids_boundary_encloses_its_tets(export_scene: Callable[..., Path]) -> None:
    scene = pp.read_resolved_scene(export_scene("tet_bar", method="pbd"))
    (bar,) = scene.tet_models
    x = np.array([p.position for p in scene.particles])[bar.first_particle:]
    a, b, c, d = (x[bar.tets[:, k]] for k in range(4))
    volumes = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6
    assert (volumes > 0).all()  # positively oriented
    # The 1 m x 0.2 m x 0.2 m bar of the case: 0.04 m^3 (closed form).
    assert volumes.sum() == pytest.approx(0.04, rel=1e-12)
    # Divergence theorem: the outward boundary faces enclose the same volume, sum (1/6) a.(b x c).
    fa, fb, fc = (x[bar.boundary_faces[:, k]] for k in range(3))
    enclosed = np.einsum("ij,ij->i", fa, np.cross(fb, fc)).sum() / 6
    assert enclosed == pytest.approx(0.04, rel=1e-12)
    assert bar.method_name == "fem_xpbd"
    assert bar.material["stiffness"] == 1e6 and bar.material["poissonRatio"] == 0.3


def test_bad_models_name_the_json_path(export_scene: Callable[..., Path]) -> None:
    document = json.loads(export_scene("tet_bar", method="pbd").read_text())
    broken = copy.deepcopy(document)
    broken["tetModels"][0]["tets"][3][2] = 99
    with pytest.raises(pp.SceneError, match=r"tetModels\[0\]\.tets\[3\]\[2\]: expected a vertex index in \[0, 99\)"):
        pp.parse_resolved_scene(broken, "s.json")
    broken = copy.deepcopy(document)
    broken["tetModels"][0]["particleCount"] = 100
    with pytest.raises(pp.SceneError, match=r"tetModels\[0\]\.particleCount"):
        pp.parse_resolved_scene(broken, "s.json")
    broken = copy.deepcopy(document)
    broken["deformables"]["tetModels"] = 2
    with pytest.raises(pp.SceneError, match=r"deformables\.tetModels: expected 1"):
        pp.parse_resolved_scene(broken, "s.json")


def test_simulate_writes_the_particles_at_the_samples(export_scene: Callable[..., Path],
                                                       tmp_path: Path) -> None:
    scene = pp.read_resolved_scene(export_scene("tet_bar", method="pbd", duration=0.05,
                                                sample_interval=0.02))
    x0 = np.array([p.position for p in scene.particles])
    clock = {"t": 0.0}

    def step() -> None:
        clock["t"] += scene.time_step_size

    def particles(t: float) -> np.ndarray:  # a uniform drift at 1 m/s along x
        return np.hstack([x0 + [t, 0, 0], np.tile([1.0, 0, 0], (len(x0), 1))])

    status = pp.simulate(scene, tmp_path, step, lambda t: [], particles=particles)
    assert status.status == "ok"
    rows = np.load(tmp_path / pp.PARTICLES_NPY_FILE)
    times = [n * scene.time_step_size for n in scene.sample_steps()]
    assert rows.shape == (len(times) * len(x0), 8)
    assert np.array_equal(rows[:, 0], np.repeat(times, len(x0)))
    assert np.array_equal(rows[:, 1], np.tile(np.arange(len(x0)), len(times)))
    np.testing.assert_array_equal(rows[-len(x0):, 2:5], x0 + [times[-1], 0, 0])


def test_simulate_stops_at_a_blown_up_particle_and_needs_a_reader(export_scene: Callable[..., Path],
                                                                  tmp_path: Path) -> None:
    scene = pp.read_resolved_scene(export_scene("tet_bar", method="pbd", duration=0.05))
    x0 = np.array([p.position for p in scene.particles])

    def particles(t: float) -> np.ndarray:
        v = np.zeros_like(x0)
        if t > 0.02:
            v[5, 1] = np.inf
        return np.hstack([x0, v])

    (tmp_path / "a").mkdir()
    status = pp.simulate(scene, tmp_path / "a", lambda: None, lambda t: [], particles=particles)
    assert status.status == "diverged" and "particle 5" in status.reason
    rows = np.load(tmp_path / "a" / pp.PARTICLES_NPY_FILE)
    assert not np.isfinite(rows[-len(x0):]).all()  # the diverged state is the last sample
    (tmp_path / "b").mkdir()
    with pytest.raises(ValueError, match="particles"):
        pp.simulate(scene, tmp_path / "b", lambda: None, lambda t: [])


def test_the_particle_csv_has_the_simulate_header(tmp_path: Path) -> None:
    with pp.ParticleTrajectoryWriter(tmp_path, binary=False) as writer:
        writer.write(0.0, np.array([[0.5, 1, 2, 0, -1, 0]]))
    lines = (tmp_path / pp.PARTICLES_FILE).read_text().splitlines()
    assert lines == ["t,index,x,y,z,vx,vy,vz", "0,0,0.5,1,2,0,-1,0"]
