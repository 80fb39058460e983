"""The numpy linear-FEM reference (tests/python/linear_fem.py) against closed forms, and the
cantilever case's expected deflection against it."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import linear_fem
from conftest import REPO
from pbdval import protocol as pp

E, NU = 1e7, 0.3


def test_rigid_motions_cost_nothing_and_constant_strain_is_exact() -> None:
    x, tets = linear_fem.tet_lattice((3, 2, 2), (0.0, 0.0, 0.0), 0.1)
    k = linear_fem.stiffness_matrix(x, tets, E, NU)
    scale = np.abs(k).max()
    # Translations and infinitesimal rotations are in the null space: K u = 0 to round-off
    # (~1e-15 of the largest entry times the ~30 terms of a row).
    omega = np.array([0.3, -0.2, 0.5])
    for u in (np.tile([1.0, 0, 0], (len(x), 1)), np.tile([0, 0, 1.0], (len(x), 1)), np.cross(omega, x)):
        assert np.abs(k @ u.reshape(-1)).max() < 1e-12 * scale
    # Patch test: a linear field u = A x has the constant strain sym(A); linear tets represent it
    # exactly, so every interior node is in equilibrium (closed form: zero net force).
    a = np.array([[1e-3, 2e-4, 0], [0, -5e-4, 1e-4], [3e-4, 0, 2e-4]])
    force = (k @ (x @ a.T).reshape(-1)).reshape(-1, 3)
    interior = np.all((x > 1e-9) & (x < x.max(axis=0) - 1e-9), axis=1)
    assert interior.any()
    assert np.abs(force[interior]).max() < 1e-12 * scale


def test_an_axially_loaded_bar_stretches_by_fl_over_ea() -> None:
    # A 0.4 m x 0.1 m x 0.1 m bar, nu = 0 (no lateral coupling), its end x = 0 fixed, a force F
    # spread over the end face x = L as the consistent load of a uniform traction: the exact
    # solution u = F x / (E A) is linear, which linear tets represent exactly (closed form).
    x, tets = linear_fem.tet_lattice((4, 1, 1), (0.0, 0.0, 0.0), 0.1)
    k = linear_fem.stiffness_matrix(x, tets, E, 0.0)
    force = 50.0
    end = np.isclose(x[:, 0], 0.4)
    f = np.zeros_like(x)
    # The consistent nodal loads of a uniform traction on the face's triangles: each triangle's
    # third to each of its corners. The face (a square split into two triangles by one diagonal)
    # gives the two diagonal corners 1/3 and the other two 1/6 of F.
    face_tris = [tri for tet in tets for tri in ([tet[0], tet[1], tet[2]], [tet[0], tet[1], tet[3]],
                                                  [tet[0], tet[2], tet[3]], [tet[1], tet[2], tet[3]])
                 if end[tri].all()]
    for tri in face_tris:
        area = 0.5 * np.linalg.norm(np.cross(x[tri[1]] - x[tri[0]], x[tri[2]] - x[tri[0]]))
        f[tri, 0] += force * area / 0.01 / 3
    fixed = np.flatnonzero(np.isclose(x[:, 0], 0.0))
    free = np.setdiff1d(np.arange(len(x)), fixed)
    dofs = (3 * free[:, None] + np.arange(3)).reshape(-1)
    u = np.zeros(3 * len(x))
    # The fixed face holds all three components, which a nu = 0 stretch does not need.
    u[dofs] = np.linalg.solve(k[np.ix_(dofs, dofs)], f.reshape(-1)[dofs])
    displacement = u.reshape(-1, 3)
    # A dense solve of ~100 unknowns with condition number ~1e3: round-off ~1e-13 of the largest
    # displacement; 1e-9 of it leaves margin and still fails for any discretisation error.
    largest = force * 0.4 / (E * 0.01)
    np.testing.assert_allclose(displacement[:, 0], force * x[:, 0] / (E * 0.01), rtol=0, atol=1e-9 * largest)


def test_the_cantilever_approaches_timoshenko_with_refinement() -> None:
    # The beam of tests/common/cantilever_beam.h: L = 0.5 m, H = 0.1 m, rho = 1000 kg/m^3,
    # E = 1e7 Pa, nu = 0, g = 0.981 m/s^2. Euler-Bernoulli q L^4 / (8 E I) plus Timoshenko's
    # shear term q L^2 / (2 kappa G A) (kappa = 5/6, G = E/2).
    q, inertia = 1000 * 0.981 * 0.01, 0.1 ** 4 / 12
    timoshenko = q * 0.5 ** 4 / (8 * E * inertia) + q * 0.5 ** 2 / (2 * 5 / 6 * E / 2 * 0.01)
    errors = []
    for cells in (1, 2, 4):
        x, tets = linear_fem.tet_lattice((5 * cells, cells, cells), (0.0, -0.05, -0.05), 0.1 / cells)
        m = linear_fem.lumped_masses(x, tets, 1000.0)
        fixed = np.flatnonzero(np.isclose(x[:, 0], 0.0))
        u = linear_fem.static_displacement(x, tets, m, fixed, np.array([0, -0.981, 0]), E, 0.0)
        tip = -u[np.isclose(x[:, 0], 0.5), 1].mean()
        errors.append(1 - tip / timoshenko)
    # Linear tets lock in bending: too stiff (error > 0), less so with every refinement, and the
    # error falls by at least the first-order factor 2 per halving once the mesh resolves the
    # section (the element's known O(h) locking in bending, reaching O(h^2) asymptotically).
    assert all(e > 0 for e in errors)
    assert errors[0] > errors[1] > errors[2]
    assert errors[1] / errors[2] > 2


def test_the_cantilever_cases_expected_deflection_is_the_linear_fem_solution(
        export_scene: Callable[..., Path]) -> None:
    case = json.loads((REPO / "cases" / "tet_cantilever.json").read_text())
    spec = case["Validation"]["staticDisplacement"]
    scene = pp.read_resolved_scene(export_scene("tet_cantilever", method="pbd"))
    (beam,) = scene.tet_models
    x = np.array([p.position for p in scene.particles])
    masses = np.array([p.mass for p in scene.particles])
    fixed = np.flatnonzero(masses == 0)
    assert len(fixed) == 25  # the 5 x 5 nodes of the clamped face
    u = linear_fem.static_displacement(x, beam.tets, masses, fixed, np.array(scene.gravity),
                                       float(beam.material["stiffness"]), float(beam.material["poissonRatio"]))
    lo, hi = np.array(spec["region"]["min"]), np.array(spec["region"]["max"])
    region = np.all((x >= lo) & (x <= hi), axis=1)
    assert region.sum() == 25  # the tip face
    direction = np.array(spec["direction"], dtype=float)
    solved = float((u[region] @ (direction / np.linalg.norm(direction))).mean())
    # The case states the solve to 4 significant digits.
    assert spec["expected"] == pytest.approx(solved, rel=5e-4)
