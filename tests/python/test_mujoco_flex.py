"""mujoco-python's particles as MuJoCo flexes (pbdval.external.mujoco.flexes): the model is the
scene's (vertices, order, masses, elements), its elastic laws are the ones documented (closed
forms of homogeneous strains), internal forces leave the centre of mass on the integrator's own
parabola, pinned particles stay, a cantilever sags as an independent static FEM solve says, and
the runner accepts the particles file."""

from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

import linear_fem
from conftest import REPO
from pbdval import protocol as pp
from pbdval.external import cloth_bending
from pbdval.external.mujoco import engine, flexes

MUJOCO = "mujoco-python"  # the catalogue entry run_engine runs
Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]




def scene_of(export_scene: Export, case: str, method: str, edit: Callable[[dict[str, Any]], None] | None = None,
             **kwargs: Any) -> pp.ResolvedScene:
    path = export_scene(case, method=method, **kwargs)
    document = json.loads(path.read_text())
    if edit is not None:
        edit(document)
        path.write_text(json.dumps(document))
    return pp.read_resolved_scene(path)


def without_bodies(document: dict[str, Any]) -> None:
    document["bodies"], document["contactPairs"] = [], []


def step(run: Any, scene_steps: int = 1) -> None:
    for _ in range(scene_steps * run.substeps):
        mujoco.mj_step(run.model, run.data)


def elastic_forces(run: Any, positions: np.ndarray) -> np.ndarray:
    """(D, 3) passive forces on the dynamic particles with every particle at `positions` and at
    rest (flex elasticity is in qfrc_passive under the explicit integrators)."""
    layout = run.layout
    run.data.qpos[layout.qpos] = (positions - layout.positions0)[layout.dynamic]
    run.data.qvel[:] = 0.0
    mujoco.mj_forward(run.model, run.data)
    forces: np.ndarray = run.data.qfrc_passive[layout.dofs].copy()
    return forces


# --- the model is the scene's --------------------------------------------------------------

@pytest.mark.parametrize("case", ["cloth_hanging", "tet_bar", "solid_collision"])
def test_flex_vertices_masses_and_elements_are_the_scenes(export_scene: Export, case: str) -> None:
    scene = scene_of(export_scene, case, "mujoco-python.euler.newton")
    run = engine.MujocoRun(scene)
    model, data = run.model, run.data
    positions = np.array([p.position for p in scene.particles])
    masses = np.array([p.mass for p in scene.particles])
    assert model.nflexvert == len(scene.particles)
    # Vertex i is particle i: the same numbers, not merely close.
    assert np.array_equal(data.flexvert_xpos, positions)
    bodies = model.flex_vertbodyid
    assert np.array_equal(bodies[masses == 0], np.zeros(int((masses == 0).sum())))  # pinned: world
    assert np.array_equal(model.body_mass[bodies[masses > 0]], masses[masses > 0])  # exact masses
    # Total mass: fsum rounds the exact sum once, so equal multisets of masses give equal totals.
    assert math.fsum(model.body_mass[1:]) == math.fsum(masses)
    assert np.array_equal(run.layout.state(data)[:, :3], positions)
    models: tuple[pp.TriangleModel | pp.TetModel, ...] = (*scene.triangle_models, *scene.tet_models)
    assert model.nflex == len(models)
    for f, m in enumerate(models):
        elements = np.asarray(m.triangles if isinstance(m, pp.TriangleModel) else m.tets) + m.first_particle
        dim = elements.shape[1] - 1
        assert model.flex_dim[f] == dim and model.flex_vertadr[f] == m.first_particle
        first = model.flex_elemdataadr[f]
        compiled = model.flex_elem[first:first + elements.size].reshape(-1, dim + 1) + model.flex_vertadr[f]
        if dim == 2:  # triangles keep their order and orientation
            assert np.array_equal(compiled, elements)
        else:  # MuJoCo may reorder a tet's vertices ("the compiler rearranges them as needed")
            assert np.array_equal(np.sort(compiled, axis=1), np.sort(elements, axis=1))


# --- the elastic laws, against closed forms -----------------------------------------------

def test_membrane_of_a_square_grid_is_four_thirds_k(export_scene: Export) -> None:
    scene = scene_of(export_scene, "cloth_hanging", "mujoco-python.euler.newton")
    cloth = scene.triangle_models[0]
    x = np.array([p.position for p in scene.particles])
    k = 1000.0
    # A grid of n x n cells, one diagonal per cell: in the bulk each cell carries k a^2 (two
    # half-shared axis edges twice) + 2 k a^2 (its diagonal) over a^2, so E t = 4k/3; the
    # boundary edges count half (one triangle), which makes the sum exact for the whole sheet.
    assert flexes.membrane_stiffness(x, cloth.triangles, k) == pytest.approx(4 * k / 3, rel=1e-13)


def test_cloth_membrane_under_uniaxial_strain_pulls_like_the_spring_network(export_scene: Export) -> None:
    # The free cloth (cloth_on_sphere without its sphere) stretched along x by eps with y and z
    # held: the network's bulk stress is sigma_xx = (k + k/2) eps (the axis springs plus the
    # diagonals' x-share) = 1.5 k eps per metre of the edge x = max, and the membrane's
    # E t/(1 - nu^2) eps with E t = 4k/3, nu = 1/3 is the same. Linear triangles under a
    # homogeneous stress give the column x = max exactly sigma_xx L (L = 1 m), and St.
    # Venant-Kirchhoff's force F S with F = 1 + eps, S on the Green strain eps + eps^2/2 is that
    # times (1 + eps)(1 + eps/2).
    scene = scene_of(export_scene, "cloth_on_sphere", "mujoco-python.euler.newton", without_bodies)
    run = engine.MujocoRun(scene)
    x0 = run.layout.positions0
    eps, k, width = 1e-6, float(scene.triangle_models[0].material["stiffness"]), np.ptp(x0[:, 2])
    stretched = x0.copy()
    stretched[:, 0] = x0[:, 0].min() + (x0[:, 0] - x0[:, 0].min()) * (1 + eps)
    forces = elastic_forces(run, stretched)
    right = np.isclose(x0[run.layout.dynamic, 0], x0[:, 0].max())
    expected = 1.5 * k * eps * width * (1 + eps) * (1 + eps / 2)
    assert -forces[right, 0].sum() == pytest.approx(expected, rel=1e-8)  # round-off on 1e-3 N
    # Internal forces: no net force beyond round-off, far below 1e-9 of the column's force
    # (measured 4e-14 N: per-element terms of the shell's stresses cancel to ~1e-16 relative).
    assert np.abs(forces.sum(axis=0)).max() < 1e-9 * expected


#: The FEM cloth of the tests: the membrane of the cases' k = 1000 N/m spring network (E t = 4k/3),
#: nu = 0.3, isotropic (G = E/(1 + nu) in the seed's convention, flexes.fem_membrane).
FEM_STRETCH, FEM_POISSON = 4000.0 / 3.0, 0.3


def fem_cloth(document: dict[str, Any], young_y: float = FEM_STRETCH, shear: float = FEM_STRETCH / 1.3,
              bending: int = 0) -> None:
    """The document's first cloth as the seed's FEM cloth (method 2) with the moduli given."""
    document["triangleModels"][0].update(
        simulationMethod=2, methodName="fem", bendingMethod=bending,
        bendingMethodName={0: "none", 3: "isometric_xpbd"}[bending])
    document["triangleModels"][0]["material"].update(
        xxStiffness=FEM_STRETCH, yyStiffness=young_y, xyStiffness=shear,
        xyPoissonRatio=FEM_POISSON, yxPoissonRatio=FEM_POISSON)


def test_fem_cloth_is_the_isotropic_membrane_of_its_moduli(export_scene: Export) -> None:
    # The seed's FEM triangle with E_x = E_y = E_s, nu_xy = nu_yx = nu has the plane-stress normal
    # stiffness E_s/(1 - nu^2) and cross term E_s nu/(1 - nu^2) per unit area (C = A psi), and
    # shear G: MuJoCo's membrane with E t = E_s, poisson nu is it exactly when G = E_s/(1 + nu).
    # Stretched along x by eps with y and z held (uniaxial strain), the column x = max of the
    # free sheet pulls E_s/(1 - nu^2) eps L, times St. Venant-Kirchhoff's (1 + eps)(1 + eps/2).
    def free_fem_cloth(document: dict[str, Any]) -> None:
        without_bodies(document)
        fem_cloth(document)

    scene = scene_of(export_scene, "cloth_on_sphere", "mujoco-python.euler.newton", free_fem_cloth)
    membrane = flexes.fem_membrane(scene.triangle_models[0].material)
    assert (membrane.stretch, membrane.poisson) == (FEM_STRETCH, FEM_POISSON)
    assert membrane.shear_ratio == pytest.approx(1.0, rel=1e-15)  # E/(E/1.3 x 1.3): round-off
    run = engine.MujocoRun(scene)
    assert "): native" in str(run.settings["TriangleModels[0].membrane"])
    x0 = run.layout.positions0
    eps, width = 1e-6, np.ptp(x0[:, 2])
    stretched = x0.copy()
    stretched[:, 0] = x0[:, 0].min() + (x0[:, 0] - x0[:, 0].min()) * (1 + eps)
    forces = elastic_forces(run, stretched)
    right = np.isclose(x0[run.layout.dynamic, 0], x0[:, 0].max())
    expected = FEM_STRETCH / (1 - FEM_POISSON**2) * eps * width * (1 + eps) * (1 + eps / 2)
    assert -forces[right, 0].sum() == pytest.approx(expected, rel=1e-8)  # round-off on 1e-3 N


def test_fem_cloth_with_the_seeds_shear_modulus_is_recorded_as_approximated(export_scene: Export) -> None:
    # The seed's defaults E_x = E_y = G = 1, nu = 0.3: MuJoCo's shear stiffness E/(2(1 + nu)) is
    # E_s/(G (1 + nu)) = 1/1.3 of the seed's G/2.
    scene = scene_of(export_scene, "cloth_hanging", "mujoco-python.euler.newton",
                     lambda d: fem_cloth(d, shear=FEM_STRETCH))
    settings = engine.MujocoRun(scene).settings
    assert "shear stiffness 0.769231 x the seed's" in str(settings["TriangleModels[0].membrane"])
    assert "approximated" in str(settings["TriangleModels[0].membrane"])


def test_a_fem_curtain_settles_at_the_linear_membrane_fem_sag(export_scene: Export) -> None:
    # cloth_hanging turned upright (the sheet in the x-y plane, gravity in its plane) and pinned
    # along its top row, FEM cloth with E t = 4000/3 N/m, nu = 0.3, no bending: an in-plane load,
    # so linear plane-stress FEM of the same triangles, masses and pins (linear_fem, numpy only)
    # is the static solution at small strain. In `discrete`, whose backward Euler settles the
    # released sheet, the time-mean sag of the bottom edge over the second half of 4 s is that
    # solution's to St. Venant-Kirchhoff's geometric nonlinearity, of the order of the strain
    # (largest 3e-3): bound 5e-3 (measured 2.2e-3).
    def upright(document: dict[str, Any]) -> None:
        fem_cloth(document)
        for p in document["particles"]:
            x, y, z = p["position"]
            p["position"] = [x, 1.0 - z, y]  # 90 degrees about x: the row z = -0.5 on top
        top = max(p["position"][1] for p in document["particles"])
        pinned = [i for i, p in enumerate(document["particles"]) if p["position"][1] == top]
        for i in pinned:
            document["particles"][i]["mass"] = 0.0
        document["triangleModels"][0]["staticParticles"] = pinned

    scene = scene_of(export_scene, "cloth_hanging", "mujoco-python.discrete.newton", upright, duration=4.0)
    run = engine.MujocoRun(scene)
    x0 = run.layout.positions0
    masses = np.array([p.mass for p in scene.particles])
    cloth = scene.triangle_models[0]
    expected = linear_fem.membrane_static_displacement(
        x0, np.asarray(cloth.triangles), masses, np.flatnonzero(masses == 0), np.array(scene.gravity),
        FEM_STRETCH, FEM_POISSON)
    bottom = np.flatnonzero(np.isclose(x0[:, 1], x0[:, 1].min()))
    sags = []
    for n in range(1, scene.steps + 1):
        step(run)
        if n * scene.time_step_size > 2.0:
            sags.append((run.layout.state(run.data)[bottom, 1] - x0[bottom, 1]).mean())
    assert np.mean(sags) == pytest.approx(expected[bottom, 1].mean(), rel=5e-3)


def test_tets_under_uniaxial_strain_pull_with_lambda_plus_two_mu(export_scene: Export) -> None:
    # The tet bar stretched along its axis by eps, the cross-section held: uniaxial strain, so
    # the end face x = 1 m (A = 0.2 x 0.2 m^2) carries (lambda + 2 mu) eps A, times
    # (1 + eps)(1 + eps/2) for St. Venant-Kirchhoff (see the cloth test): E and nu native.
    scene = scene_of(export_scene, "tet_bar", "mujoco-python.euler.newton")
    run = engine.MujocoRun(scene)
    x0 = run.layout.positions0
    material = scene.tet_models[0].material
    E, nu = float(material["stiffness"]), float(material["poissonRatio"])
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    eps, area = 1e-6, np.ptp(x0[:, 1]) * np.ptp(x0[:, 2])
    stretched = x0.copy()
    stretched[:, 0] = x0[:, 0].min() + (x0[:, 0] - x0[:, 0].min()) * (1 + eps)
    forces = elastic_forces(run, stretched)
    end = np.isclose(x0[run.layout.dynamic, 0], x0[:, 0].max())
    expected = (lam + 2 * mu) * eps * area * (1 + eps) * (1 + eps / 2)
    assert -forces[end, 0].sum() == pytest.approx(expected, rel=1e-8)  # round-off on 0.05 N


@pytest.mark.parametrize("distance,fold", [(0.5, 0.3), (0.8, 1.0)])
def test_seed_bending_energy_of_a_symmetric_fold(distance: float, fold: float) -> None:
    # Two triangles on a unit edge, opposite vertices `distance` from it over one foot point,
    # folded symmetrically by `fold`: C = (6/d) sin^2(fold/2) (docs/methods.md, tested in
    # tests/pbd/test_isometric_bending.cpp), the XPBD potential (1/2) k C^2.
    rest = np.array([[0, 0, 0], [1, 0, 0], [0.4, distance, 0], [0.4, -distance, 0]], dtype=float)
    c, s = math.cos(fold / 2), math.sin(fold / 2)
    folded = np.array([[0, 0, 0], [1, 0, 0], [0.4, distance * c, distance * s],
                       [0.4, -distance * c, distance * s]])
    stencils = cloth_bending.bending_stencils(rest, np.array([[0, 1, 2], [1, 0, 3]]))
    assert len(stencils) == 1
    k = 2.0
    expected = 0.5 * k * (6 / distance * math.sin(fold / 2) ** 2) ** 2
    assert cloth_bending.isometric_xpbd_energy(stencils, folded, k) == pytest.approx(expected, rel=1e-13)


def test_mujoco_bending_of_a_cylinder_is_kirchhoffs_on_the_interior_hinges(export_scene: Export) -> None:
    # MuJoCo documents D kappa^2/2 per unit area for a sheet bent into a cylinder; on the 8 x 8
    # grid the curvature is carried by the 7 interior hinge lines across the bend, each for a
    # strip of one cell, so the measured work at D = 1 is (7/8) kappa^2 A/2 (A = 1 m^2). At
    # kappa = 0.01 /m the chords differ from the arcs by (kappa a)^2/24 ~ 1e-8: 1e-5 covers it
    # and the trapezoidal rule on the nonlinear rest.
    scene = scene_of(export_scene, "cloth_on_sphere", "mujoco-python.euler.newton", without_bodies)
    x = np.array([p.position for p in scene.particles])
    triangles = scene.triangle_models[0].triangles
    kappa = 0.01
    work = flexes.kirchhoff_energy_per_rigidity(x, triangles, cloth_bending.cylinder(x, triangles, kappa),
                                                flexes.NETWORK_POISSON)
    assert work == pytest.approx(7 / 8 * kappa**2 / 2, rel=1e-5)


# --- dynamics ------------------------------------------------------------------------------

@pytest.mark.parametrize("method", ["mujoco-python.euler.newton", "mujoco-python.discrete.newton",
                                    "mujoco-python.discrete.cg"])
def test_free_cloth_centre_of_mass_follows_the_discrete_parabola(export_scene: Export, method: str) -> None:
    # The cloth of cloth_on_sphere without the sphere, every particle thrown with its own random
    # velocity (0.5 m/s): the membrane works hard (strains of percents), but its forces are
    # internal, so the centre of mass moves as one particle under gravity in the integrator's
    # step, v_k = v0 + k h g, x_k = x0 + k h v0 + k (k + 1)/2 h^2 g (velocity first), with h the
    # internal step and k the internal steps taken.
    def thrown(document: dict[str, Any]) -> None:
        without_bodies(document)
        rng = np.random.default_rng(7)
        for p in document["particles"]:
            p["velocity"] = [float(v) for v in rng.normal(0.0, 0.5, 3)]

    scene = scene_of(export_scene, "cloth_on_sphere", method, thrown)
    run = engine.MujocoRun(scene)
    mass = np.array([p.mass for p in scene.particles])
    total = mass.sum()
    x0 = mass @ np.array([p.position for p in scene.particles]) / total
    v0 = mass @ np.array([p.velocity for p in scene.particles]) / total
    g, h = np.array(scene.gravity), scene.time_step_size / run.substeps
    worst_x = worst_v = strain = 0.0
    edges = run.model.flex_edge.reshape(-1, 2)
    for n in range(1, 101):  # 0.5 s
        step(run)
        state = run.layout.state(run.data)
        k = n * run.substeps
        worst_x = max(worst_x, np.abs(mass @ state[:, :3] / total
                                      - (x0 + k * h * v0 + k * (k + 1) / 2 * h * h * g)).max())
        worst_v = max(worst_v, np.abs(mass @ state[:, 3:] / total - (v0 + k * h * g)).max())
        lengths = np.linalg.norm(state[edges[:, 0], :3] - state[edges[:, 1], :3], axis=1)
        strain = max(strain, np.abs(lengths / run.model.flexedge_length0 - 1).max())
    assert strain > 1e-3  # the elastic forces did act
    if run.settings["integrator"] == "discrete":
        # The step solves (M + h^2 K) dv = h f iteratively to relative residual `tolerance`
        # (1e-8): the internal forces then cancel only to that fraction of the velocity
        # increments, at most h a ~ 5 ms x 3e3 m/s^2 (k eps/m at percent strains) = 15 m/s, so
        # over n = 100 steps |dv_com| <= n tol 15 m/s and |dx_com| <= n^2/2 h tol 15 m/s.
        tolerance, n, increment = 1e-8, 100, 15.0
        assert worst_v < n * tolerance * increment and worst_x < n * n / 2 * h * tolerance * increment
    else:
        # Round-off: the internal forces cancel to ~1e-16 relative over ~1000 steps below 2 m.
        assert worst_x < 1e-12 and worst_v < 1e-12


def test_explicit_integrators_substep_below_the_stability_limit(export_scene: Export) -> None:
    # Euler is stable for h omega < 2; the engine takes h_sub omega_max <= 1, omega_max of the
    # compiled model by power iteration. Rayleigh: omega_max^2 >= u.K u / u.M u for every u, so
    # it is at least sqrt(K_ii / m_i) for a single particle pushed along x, K_ii measured here
    # by central differences of the membrane force on that particle alone.
    scene = scene_of(export_scene, "cloth_hanging", "mujoco-python.euler.newton")
    run = engine.MujocoRun(scene)
    omega = float(run.settings["elasticOmegaMax"])
    h = scene.time_step_size
    assert run.substeps == math.ceil(omega * h) and run.substeps > 1
    assert run.model.opt.timestep == pytest.approx(h / run.substeps, rel=1e-15)
    x0, layout, delta = run.layout.positions0, run.layout, 1e-7
    single = 0.0
    for j, i in enumerate(layout.dynamic):
        pushed = [x0.copy(), x0.copy()]
        pushed[0][i, 0] += delta
        pushed[1][i, 0] -= delta
        k_ii = -(elastic_forces(run, pushed[0])[j, 0] - elastic_forces(run, pushed[1])[j, 0]) / (2 * delta)
        single = max(single, math.sqrt(k_ii / layout.masses[j]))
    # The power iteration converges from below: 1e-3 relative (60 iterations) is its slack.
    assert omega >= single * (1 - 1e-3)
    implicit = engine.MujocoRun(scene_of(export_scene, "cloth_hanging", "mujoco-python.discrete.newton"))
    assert implicit.substeps == 1  # implicit in position: no limit


def test_euler_with_too_few_substeps_blows_up_and_with_the_automatic_ones_does_not(
        export_scene: Export, run_engine: Run) -> None:
    # The reason for the substeps: one explicit step of 5 ms against omega_max ~ 1600 rad/s.
    status, _ = run_engine(MUJOCO, export_scene("cloth_hanging", method="mujoco-python.euler.newton",
                                                parameters={"substeps": 1}, duration=0.5))
    assert status["status"] == "diverged" and status["integratorStepsPerSceneStep"] == 1
    status, _ = run_engine(MUJOCO, export_scene("cloth_hanging", method="mujoco-python.euler.newton",
                                                duration=0.5))
    assert status["status"] == "ok", status["reason"]
    assert status["integratorStepsPerSceneStep"] == status["effectiveSettings"]["substeps"] > 1


# --- through the protocol ------------------------------------------------------------------

def test_pinned_particles_stay_and_the_particles_file_has_every_sample(export_scene: Export,
                                                                      run_engine: Run) -> None:
    scene_path = export_scene("cloth_hanging", method="mujoco-python.discrete.newton", duration=0.5)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(MUJOCO, scene_path)
    assert status["status"] == "ok", status["reason"]
    rows = np.load(out / "particles.npy")
    samples = scene.sample_steps()
    count = len(scene.particles)
    assert rows.shape == (len(samples) * count, 8)
    table = rows.reshape(len(samples), count, 8)
    assert np.allclose(table[:, 0, 0], np.array(samples) * scene.time_step_size, rtol=1e-12)
    assert np.array_equal(table[:, :, 1], np.tile(np.arange(count), (len(samples), 1)))
    cloth = scene.triangle_models[0]
    pinned = [cloth.first_particle + i for i in cloth.static_particles]
    assert len(pinned) == 2
    initial = np.array([scene.particles[i].position for i in pinned])
    # World-body vertices: exactly where they started, at rest, at every sample.
    assert np.array_equal(table[:, pinned, 2:5], np.broadcast_to(initial, (len(samples), 2, 3)))
    assert not table[:, pinned, 5:8].any()
    assert np.ptp(table[:, :, 3]) > 0.1  # while the rest of the cloth swings down


@pytest.mark.parametrize("case,method,edit,feature", [
    ("cloth_hanging", "mujoco-python.euler.newton",
     lambda d: d["triangleModels"][0].update(simulationMethod=3, methodName="strain"),
     "TriangleModels[0]: cloth method 3 (strain)"),
    ("cloth_hanging", "mujoco-python.euler.newton",
     lambda d: fem_cloth(d, young_y=2.0 * FEM_STRETCH),
     "TriangleModels[0]: cloth method 2 (fem) with orthotropic moduli"),
    ("cloth_hanging", "mujoco-python.euler.newton",
     lambda d: d["triangleModels"][0].update(bendingMethod=1, bendingMethodName="dihedral"),
     "TriangleModels[0]: bending method 1 (dihedral)"),
    ("tet_bar", "mujoco-python.euler.newton",
     lambda d: d["tetModels"][0].update(simulationMethod=6, methodName="xpbd_distance_volume"),
     "TetModels[0]: solid method 6 (xpbd_distance_volume)"),
    ("tet_bar", "mujoco-python.implicitfast.newton", None, "refuses flex elasticity under implicit"),
    ("cloth_hanging", "mujoco-python.discrete.pgs", None, "needs the Newton or CG solver"),
    ("rod_helix", "mujoco-python.euler.newton", None, "LineModels: rods"),
    ("fluid_dam_break", "mujoco-python.euler.newton", None, "FluidModels: fluids"),
])
def test_particle_features_without_a_mujoco_counterpart_are_named(
        export_scene: Export, run_engine: Run, case: str, method: str,
        edit: Callable[[dict[str, Any]], None] | None, feature: str) -> None:
    path = export_scene(case, method=method, duration=0.02)
    if edit is not None:
        document = json.loads(path.read_text())
        edit(document)
        path.write_text(json.dumps(document))
    status, out = run_engine(MUJOCO, path)
    assert status["status"] == "unsupported"
    assert any(feature in u for u in status["unsupported"]), status["unsupported"]
    assert not (out / "particles.npy").exists()


def test_pbdval_run_accepts_and_measures_the_particles(pbdval_binary: Path, tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = subprocess.run([str(pbdval_binary), "run", str(REPO / "cases" / "cloth_hanging.json"),
                             "--engines", "mujoco-python", "--methods", "mujoco-python.discrete.newton",
                             "--out", str(out), "--jobs", "1", "--quiet"],
                            capture_output=True, text=True, cwd=REPO, check=False, timeout=600)
    assert result.returncode == 0, result.stderr
    runs = json.loads((out / "results.json").read_text())["runs"]
    assert [(r["engine"], r["method"], r["status"]) for r in runs] == [
        ("mujoco-python", "mujoco-python.discrete.newton", "ok")], runs
    metrics = runs[0]["metrics"]
    # Measured from the particles the engine wrote: the cloth hangs from k = 1000 N/m edges,
    # strained by its weight (0.3 kg x 9.81 over a few edges: percents), not zero, not torn.
    assert 1e-3 < metrics["particle_stretch_max"] < 0.2
    assert runs[0]["facts"]["integratorStepsPerSceneStep"] == 1


# --- the cantilever against an independent static solve -----------------------------------

def test_cantilever_settles_at_the_linear_fem_deflection(export_scene: Export) -> None:
    # tet_cantilever (0.5 x 0.1 x 0.1 m, 1920 tets, E = 10 MPa, nu = 0, g = 0.981 m/s^2) in the
    # discrete integrator, whose backward-Euler dissipation settles the released beam: the
    # time-mean downward displacement of the tip face over the second half against the static
    # linear-FEM solution of the same mesh, masses and clamp (tests/python/linear_fem.py, numpy
    # only). MuJoCo's tets are St. Venant-Kirchhoff: at displacement gradients |grad u| ~
    # 3 delta/(2 L) = 2.4e-3 its Green strain departs from the linear one by |grad u|/2
    # relative, so 2.4e-3 bounds the difference of the static solutions; what is left of the
    # oscillation after 1 s averages out far below that.
    scene = scene_of(export_scene, "tet_cantilever", "mujoco-python.discrete.newton", duration=2.0)
    run = engine.MujocoRun(scene)
    model = scene.tet_models[0]
    x0 = run.layout.positions0
    masses = np.array([p.mass for p in scene.particles])
    assert len(scene.tet_models) == 1 and model.first_particle == 0  # local indices are global
    expected = linear_fem.static_displacement(x0, model.tets, masses, np.array(model.static_particles),
                                              np.array(scene.gravity), float(model.material["stiffness"]),
                                              float(model.material["poissonRatio"]))
    tip = np.flatnonzero(np.isclose(x0[:, 0], x0[:, 0].max()))
    sags = []
    for n in range(1, scene.steps + 1):
        step(run)
        if n * scene.time_step_size > 1.0:
            sags.append(-(run.layout.state(run.data)[tip, 1] - x0[tip, 1]).mean())
    assert run.data.warning[int(mujoco.mjtWarning.mjWARN_INERTIA)].number == 0  # solves converged
    assert np.mean(sags) == pytest.approx(-expected[tip, 1].mean(), rel=2.4e-3)
