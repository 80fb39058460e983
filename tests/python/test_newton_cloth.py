"""The newton engine's particles (python/pbdval/external/newton/cloth.py, docs/engine-newton.md#cloth):
free fall, pinned particles, the springs' stiffness through an energy turning point, Newton's
dihedral bending potential as derived from its kernels, and what it refuses by name. Expected
values are closed forms; tolerances carry Warp's float32 state."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_engines import assert_ok

import linear_fem
from pbdval import protocol as pp
from pbdval.external.newton import cloth

NEWTON = "newton"
#: Warp's float32 unit round-off (2^-24).
FLOAT32_EPSILON = 2.0**-24

Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]


def edited(path: Path, edit: Callable[[dict[str, Any]], None]) -> Path:
    """The resolved scene at `path` changed by `edit`, written beside it."""
    document = json.loads(path.read_text())
    edit(document)
    out = path.with_name(path.stem + "-edited.json")
    out.write_text(json.dumps(document))
    return out


def particle_table(out: Path, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(times, states (samples, particles, 6)) from particles.npy."""
    rows = np.load(out / "particles.npy")
    samples = rows.reshape(-1, count, 8)
    assert np.array_equal(samples[:, :, 1], np.tile(np.arange(count), (len(samples), 1)))
    return samples[:, 0, 0], samples[:, :, 2:8]


@pytest.mark.parametrize("method,substeps", [("newton.xpbd", 5), ("newton.semiImplicit", 10)])
def test_newton_unpinned_cloth_falls_as_one_semi_implicit_euler_parabola(
        export_scene: Export, run_engine: Run, method: str, substeps: int) -> None:
    """Unpinned, the flat cloth falls without deforming: every particle follows
    x_n = x0 + n(n+1)/2 h^2 g, v_n = n h g (n internal steps), its springs and bending edges at
    rest. The cloth's kinetic energy is then (1/2) M |v_n|^2, the closed form of the fall."""
    def unpin(d: dict[str, Any]) -> None:
        for p in d["particles"]:
            p["mass"] = d["particles"][1]["mass"]  # any positive mass: the fall does not depend on it
        d["triangleModels"][0]["staticParticles"] = []

    scene_path = edited(export_scene("cloth_hanging", method=method, parameters={"substeps": substeps},
                                     duration=0.5), unpin)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    times, states = particle_table(out, len(scene.particles))
    h = scene.time_step_size / substeps
    n = np.rint(times / h)[:, None, None]
    g = np.array(scene.gravity)
    x0 = np.array([p.position for p in scene.particles])[None]
    x = x0 + n * (n + 1) / 2 * h * h * g
    v = np.broadcast_to(n * h * g, states[:, :, 3:].shape)
    # float32, as the rigid projectile's bound (test_newton.py): each internal step rounds the
    # position (2^-24 |x|) and the velocity, 2 N 2^-24 max|x| over N steps; the springs and edges
    # see float32 residuals of their rest lengths and angles (C ~ 2^-24 l, l = 0.125 m), whose
    # corrections, summed over a particle's up to 6 springs, add at most 6 x 0.125 x 2^-24 per
    # step: 3 N 2^-24 max|x| in all. SolverXPBD's particle velocity is the float32 difference
    # quotient (x - x_old)/h (apply_particle_deltas), off by up to 2^-24 |x| / h each step, and
    # the next step moves by it: the velocity error grows to N 2^-24 |x| / h and the position's
    # to N^2/2 2^-24 |x| (measured: 2.6e-3 m of the bound's 9e-3 m over 0.5 s at h = 1 ms).
    steps = scene.steps * substeps
    scale = FLOAT32_EPSILON * float(np.max(np.abs(x)))
    xpbd = method == "newton.xpbd"
    x_bound = (3 * steps + (steps**2 / 2 if xpbd else 0.0)) * scale
    v_bound = 3 * steps * FLOAT32_EPSILON * float(np.max(np.abs(v))) + (steps * scale / h if xpbd else 0.0)
    assert float(np.max(np.abs(states[1:, :, :3] - x[1:]))) < x_bound
    assert float(np.max(np.abs(states[1:, :, 3:] - v[1:]))) < v_bound


def test_newton_pinned_particles_stay_where_the_scene_put_them(export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("cloth_hanging", method="newton.xpbd", parameters={"substeps": 5}, duration=0.5)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    _, states = particle_table(out, len(scene.particles))
    pinned = [i for i, p in enumerate(scene.particles) if p.mass == 0]
    assert pinned == [0, 8]
    x0 = np.array([scene.particles[i].position for i in pinned])
    # Exactly: the first sample is the scene's state, the later ones Newton's float32 copy of it,
    # which no solver moves (mass 0: no gravity, every correction weighted by the inverse mass 0).
    assert np.array_equal(states[0, pinned, :3], x0)
    assert np.array_equal(states[1:, pinned, :3], np.broadcast_to(x0.astype(np.float32), states[1:, pinned, :3].shape))
    assert not np.any(states[:, pinned, 3:])
    # and the rest of the cloth did move: it swings down from the two corners
    assert float(np.min(states[-1, :, 1])) < float(np.min(x0[:, 1])) - 0.3


def test_newton_springs_turn_a_released_mass_at_the_depth_where_the_spring_energy_pays_for_the_fall(
        export_scene: Export, run_engine: Run) -> None:
    """One cloth triangle, two corners pinned at (+-a, y0, 0), the third released at rest a
    below them, its springs (k = the cloth's 1000 N/m) at their rest length L = a sqrt(2).
    Energy conservation gives the lowest point: 2 (1/2) k (sqrt(a^2 + d^2) - L)^2 = m g (d - a),
    independent of the engine. The semi-implicit Euler step is symplectic: the turning point is
    reached to O(omega h_s) of the swing."""
    a, mass, y0 = 0.5, 1.0, 1.0

    def triangle(d: dict[str, Any]) -> None:
        d["particles"] = [{"position": [-a, y0, 0.0], "velocity": [0.0, 0.0, 0.0], "mass": 0.0},
                          {"position": [a, y0, 0.0], "velocity": [0.0, 0.0, 0.0], "mass": 0.0},
                          {"position": [0.0, y0 - a, 0.0], "velocity": [0.0, 0.0, 0.0], "mass": mass}]
        d["triangleModels"][0].update(particleCount=3, triangles=[[0, 2, 1]], staticParticles=[0, 1])

    scene_path = edited(export_scene("cloth_hanging", method="newton.semiImplicit", duration=1.0,
                                     sample_interval=0.005), triangle)
    scene = pp.read_resolved_scene(scene_path)
    k, g = float(scene.triangle_models[0].material["stiffness"]), -float(scene.gravity[1])
    rest = a * math.sqrt(2.0)

    def surplus(depth: float) -> float:  # spring energy minus the fall's work
        return k * (math.hypot(a, depth) - rest) ** 2 - mass * g * (depth - a)

    low, high = a + 1e-9, a + 1.0  # surplus < 0 just below the start, > 0 a metre further
    for _ in range(200):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if surplus(middle) < 0 else (low, middle)
    expected_depth = 0.5 * (low + high)

    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    _, states = particle_table(out, 3)
    free = states[:, 2, :3]
    depth = y0 - float(np.min(free[:, 1]))
    swing = expected_depth - a
    # omega^2 = 2 k sin^2(45 deg) / m at the rest geometry; symplectic Euler's energy error at a
    # turning point ~ omega h_s of the swing; sampling every 5 ms finds the lowest point to
    # (omega dt)^2 / 8 of the swing (a cosine near its extremum). 2x for the stiffening.
    omega = math.sqrt(k / mass)
    h_s = scene.time_step_size / 10
    tolerance = 2 * swing * (omega * h_s + (omega * 0.005) ** 2 / 8)
    assert depth == pytest.approx(expected_depth, abs=tolerance)
    # by symmetry the mass moves vertically only (float32 round-off of the x = 0 balance)
    assert float(np.max(np.abs(free[:, [0, 2]]))) < 1e-5


def newton_hinge(fold: float, ke: float, solver: str, step: float) -> np.ndarray:
    """One step of Newton's `solver` on two unit-edge triangles, the edge (0,0,0)-(1,0,0), the
    opposite vertices a distance 0.5 from it, the second face turned by `fold` about the edge,
    with zero velocity, no gravity, only Newton's bending edge (ke), three vertices pinned: the
    free vertex's (position change, velocity) after the step."""
    from pbdval.external.newton.engine import _import_newton

    wp, newton = _import_newton()
    d = 0.5
    flat = np.array([[0, 0, 0], [1, 0, 0], [0.4, d, 0], [0.4, -d, 0]], dtype=float)
    triangles = np.array([[0, 1, 2], [1, 0, 3]])
    folded = flat.copy()
    folded[3] = [0.4, -d * math.cos(fold), d * math.sin(fold)]
    edges = cloth.bending_edges(triangles)
    assert len(edges) == 1
    builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    for i, x in enumerate(folded):
        builder.add_particle(wp.vec3(*x), wp.vec3(0.0, 0.0, 0.0), 1.0 if i == 3 else 0.0, radius=1e-3)
    (i, j, k, l), = edges
    builder.add_edge(i, j, k, l, rest=float(cloth.dihedral_angles(flat, edges)[0]), edge_ke=ke, edge_kd=0.0)
    model = builder.finalize(device="cpu")
    state_in, state_out = model.state(), model.state()
    if solver == "xpbd":
        newton.solvers.SolverXPBD(model, iterations=1).step(state_in, state_out, model.control(), None, step)
    else:
        state_in.clear_forces()
        newton.solvers.SolverSemiImplicit(model).step(state_in, state_out, model.control(), None, step)
    moved = state_out.particle_q.numpy()[3].astype(float) - folded[3]
    return np.concatenate([moved, state_out.particle_qd.numpy()[3].astype(float)])


@pytest.mark.parametrize("fold", [0.1, 0.4])
def test_newton_explicit_bending_force_is_the_gradient_of_ke_edge_length_area_theta_squared(fold: float) -> None:
    """cloth.py's reading of eval_bending: the potential ke |e| A theta^2. With |e| = 1, both
    faces of area A = d/2 and the free vertex d from the edge (|dtheta/dx| = 1/d), the force on
    it is 2 ke |e| A theta / d = ke theta, along its face's normal, towards the flat sheet."""
    ke, step = 3.0, 1e-3
    result = newton_hinge(fold, ke, "semiImplicit", step)
    force = result[3:] / step  # v = h f / m, m = 1
    # float32 round-off of the angle and of v (1e-6 relative) is far below 1e-5.
    assert float(np.linalg.norm(force)) == pytest.approx(ke * fold, rel=1e-5)
    opening = np.array([0.0, math.sin(fold), math.cos(fold)])  # d(x_3)/d(fold) / d
    assert float(force @ opening) == pytest.approx(-ke * fold, rel=1e-5)


@pytest.mark.parametrize("fold", [0.1, 0.4])
def test_newton_xpbd_bending_acts_as_the_potential_ke_area_theta_squared(fold: float) -> None:
    """cloth.py's reading of bending_constraint: compliance 1/(ke h^2) on C = theta with the
    "gradient" 2A grad(theta), i.e. the force of ke A theta^2: here ke theta (|e| = 1, A = d/2,
    |grad theta| = 1/d), so one step from rest moves the free vertex by h^2 ke theta / m. One
    XPBD iteration reaches it to the relative w |d|^2 ke h^2 (its compliance against the
    vertex's inverse mass), 1e-3 here."""
    ke, step = 1.0, math.sqrt(1e-3)  # ke h^2 = 1e-3, w = 1, |d| = |e| = 1
    moved = newton_hinge(fold, ke, "xpbd", step)[:3]
    # 2x the compliance bound above; float32 (1e-7 of 1e-3 m moves) is far below it
    assert float(np.linalg.norm(moved)) / step**2 == pytest.approx(ke * fold, rel=2e-3)


def test_newton_bending_matches_the_seeds_energy_on_the_matching_cylinder_and_not_elsewhere(
        export_scene: Export) -> None:
    """The matched edge_ke makes Newton's energy of the cloth bent at the matching curvature the
    seed's; at half that curvature Newton's quadratic energy is a quarter, the seed's quartic
    one a sixteenth (to the chord's second order): Newton's is 4x stiffer there."""
    scene = pp.read_resolved_scene(export_scene("cloth_hanging", method="newton.xpbd"))
    tm = scene.triangle_models[0]
    x = np.array([p.position for p in scene.particles])
    kappa, k = 2.0, float(tm.material["bendingStiffness"])
    ke = cloth.matched_edge_stiffness(x, tm.triangles, k, kappa, cloth.XPBD_BENDING)
    edges = cloth.bending_edges(tm.triangles)

    def energies(curvature: float) -> tuple[float, float]:
        from pbdval.external import cloth_bending

        bent = cloth_bending.cylinder(x, tm.triangles, curvature)
        seed = cloth_bending.isometric_xpbd_energy(cloth_bending.bending_stencils(x, tm.triangles), bent, k)
        newton = ke * float(np.sum(cloth.bending_weights(bent, edges, cloth.XPBD_BENDING)
                                   * cloth.dihedral_angles(bent, edges) ** 2))
        return seed, newton

    seed, newton = energies(kappa)
    assert newton == pytest.approx(seed, rel=1e-12)
    seed_half, newton_half = energies(kappa / 2)
    # Newton's: quadratic in the angles, which halve with the curvature up to the chords'
    # deviation from the arcs, (kappa l)^2 / 24 with l = 0.125 m: 1e-3.
    assert newton_half / newton == pytest.approx(0.25, rel=1e-2)
    # The seed's C is 2 sin^2(theta/2) (...) = theta^2/2 (1 - theta^2/12): C^2 halves its
    # quartic law by theta^2/8 at most, theta <= kappa x 0.177 m (a cell's diagonal) = 0.35 rad:
    # 1.6e-2.
    assert seed_half / seed == pytest.approx(1 / 16, rel=2e-2)


@pytest.mark.parametrize("case,method,edit,feature", [
    ("cloth_hanging", "newton.xpbd", {"simulationMethod": 1, "methodName": "distance"},
     "TriangleModels[0]: cloth method 1 (distance)"),
    ("cloth_hanging", "newton.semiImplicit", {"bendingMethod": 2, "bendingMethodName": "isometric"},
     "TriangleModels[0]: bending method 2 (isometric)"),
    ("tet_bar", "newton.xpbd", {}, "TetModels[0]: solid method 3 (fem_xpbd)"),
    ("solid_collision", "newton.semiImplicit", {}, "contact between particle models (TetModels[0], TetModels[1])"),
])
def test_newton_names_the_particle_model_it_cannot_run(export_scene: Export, run_engine: Run, case: str,
                                                       method: str, edit: dict[str, Any], feature: str) -> None:
    def change(d: dict[str, Any]) -> None:
        if edit:
            d["triangleModels"][0].update(edit)

    status, out = run_engine(NEWTON, edited(export_scene(case, method=method), change))
    assert status["status"] == "unsupported"
    assert any(u.startswith(feature) for u in status["unsupported"]), status["unsupported"]
    assert not (out / "particles.npy").exists()


@pytest.mark.parametrize("poisson", [0.0, 0.3, 0.45])
def test_newton_neo_hookean_tet_gives_the_linear_elastic_forces_of_the_mapped_young_and_poisson(
        poisson: float) -> None:
    """cloth.neo_hookean's reading of eval_tetrahedra: at small strain Newton's stable
    neo-Hookean tet with k_mu = 4/3 mu, k_lambda = lambda + 5/6 mu has linear elasticity's
    forces -K u for (E, nu) (tests/python/linear_fem.py, numpy alone), measured as m dv/h after
    one semi-implicit step from rest under a homogeneous strain of size eps = 1e-3."""
    from pbdval.external.newton.engine import _import_newton

    wp, newton = _import_newton()
    young, eps, step = 1e4, 1e-3, 1e-4
    rest = np.array([[0.0, 0.0, 0.0], [1.0, 0.1, 0.0], [0.2, 0.9, 0.1], [0.1, 0.2, 1.1]])
    gradient = np.array([[0.3, -0.8, 0.5], [0.6, 0.2, -0.4], [-0.1, 0.7, 0.9]])  # fixed, generic
    u = eps * rest @ gradient.T
    k_mu, k_lambda = cloth.neo_hookean(young, poisson)
    builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    for x in rest:
        builder.add_particle(wp.vec3(*x), wp.vec3(0.0, 0.0, 0.0), 1.0, radius=1e-3)
    builder.add_tetrahedron(0, 1, 2, 3, k_mu=k_mu, k_lambda=k_lambda, k_damp=0.0)
    model = builder.finalize(device="cpu")
    state_in, state_out = model.state(), model.state()
    state_in.particle_q.assign((rest + u).astype(np.float32))
    state_in.clear_forces()
    newton.solvers.SolverSemiImplicit(model).step(state_in, state_out, model.control(), None, step)
    force = state_out.particle_qd.numpy().astype(float) / step  # m = 1
    expected = -(linear_fem.stiffness_matrix(rest, np.array([[0, 1, 2, 3]]), young, poisson)
                 @ u.reshape(-1)).reshape(-1, 3)
    # The models differ at second order in the strain: a relative O(eps), 5 eps allowed (the
    # quadratic terms' coefficients are O(1) multiples of the moduli' linear ones); float32 loses
    # 2^-24 of the stresses ~k I that cancel at rest, 2^-24 / eps = 6e-5 relative. With mu and
    # lambda given to Newton unmapped the error is 0.08-0.67.
    tolerance = 5 * eps
    assert np.max(np.abs(force - expected)) < tolerance * np.max(np.abs(expected))
