"""The external engines run as the runner runs them (the catalogue command, `--scene X --out D`)
on exported cases, against closed forms; and their catalogues (engines/*.json)."""

from __future__ import annotations

import csv
import dataclasses
import importlib.util
import json
import math
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import REPO, VENV_PYTHON
from pbdval import protocol as pp

# The engines by catalogue name (run_engine runs engines/<name>.json's command).
EXAMPLE = "example-euler"
PYBULLET = "pybullet"
MUJOCO = "mujoco-python"
CATALOGUES = sorted((REPO / "engines").glob("*.json"))

Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]


def trajectory_written(out: Path) -> bool:
    """Whether the engine wrote its trajectory (trajectory.npy, or trajectory.csv)."""
    return (out / pp.TRAJECTORY_NPY_FILE).exists() or (out / pp.TRAJECTORY_FILE).exists()


def trajectory(out: Path) -> dict[int, np.ndarray]:
    """body id → array of rows (t, x, y, z, qw, qx, qy, qz, vx, vy, vz, wx, wy, wz)."""
    if (out / pp.TRAJECTORY_NPY_FILE).exists():
        table = np.load(out / pp.TRAJECTORY_NPY_FILE)
    else:
        with open(out / pp.TRAJECTORY_FILE, newline="") as f:
            reader = csv.reader(f)
            assert next(reader) == pp.TRAJECTORY_HEADER.split(",")
            table = np.array([[float(v) for v in row] for row in reader])
    ids = table[:, 1].astype(int)
    return {int(k): table[ids == k][:, [0, *range(2, 15)]] for k in dict.fromkeys(ids)}


def assert_ok(status: dict[str, Any]) -> None:
    assert status["status"] == "ok", status["reason"]
    assert status["protocol"] == 1 and status["engineVersion"]


# --- free fall -----------------------------------------------------------------------------

SEMI_IMPLICIT = [(EXAMPLE, ""), (PYBULLET, "pybullet.si"), (MUJOCO, "mujoco-python.euler.newton"),
                 (MUJOCO, "mujoco-python.implicit.newton"), (MUJOCO, "mujoco-python.implicitfast.cg")]


@pytest.mark.parametrize("engine,method", SEMI_IMPLICIT)
def test_projectile_follows_the_semi_implicit_euler_parabola(export_scene: Export, run_engine: Run,
                                                             engine: str, method: str) -> None:
    scene_path = export_scene("projectile", method=method)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(engine, scene_path)
    assert_ok(status)
    body = scene.bodies[0]
    rows = trajectory(out)[body.id]
    h, g = scene.time_step_size, np.array(scene.gravity)
    steps = np.array(scene.sample_steps())
    assert len(rows) == len(steps)
    assert np.allclose(rows[:, 0], steps * h, rtol=1e-11)  # times to the CSV's 12 digits
    # v_n = v0 + n h g, x_n = x0 + n h v0 + n(n+1)/2 h^2 g (velocity first, then position).
    n = steps[:, None]
    v = np.array(body.velocity) + n * h * g
    x = np.array(body.position) + n * h * np.array(body.velocity) + n * (n + 1) / 2 * h * h * g
    # Round-off: ~1e-16 relative per operation over 300 steps of values below 10 m.
    assert np.max(np.abs(rows[:, 8:11] - v)) < 1e-11
    assert np.max(np.abs(rows[:, 1:4] - x)) < 1e-11


def test_projectile_in_rk4_is_the_exact_parabola(export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("projectile", method="mujoco-python.rk4.newton")
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(MUJOCO, scene_path)
    assert_ok(status)
    body = scene.bodies[0]
    rows = trajectory(out)[body.id]
    t = rows[:, :1]
    exact = np.array(body.position) + t * np.array(body.velocity) + 0.5 * t * t * np.array(scene.gravity)
    # RK4 integrates a quadratic exactly: round-off only.
    assert np.max(np.abs(rows[:, 1:4] - exact)) < 1e-11


# --- the hinge pendulum's period -------------------------------------------------------------

def complete_elliptic_k(k: float) -> float:
    """K(k) = pi / (2 AGM(1, sqrt(1 - k^2)))."""
    a, b = 1.0, math.sqrt(1 - k * k)
    for _ in range(40):  # quadratic convergence: 6 iterations reach round-off for k < 0.9
        a, b = (a + b) / 2, math.sqrt(a * b)
    return math.pi / (2 * a)


def test_elliptic_k_matches_known_values() -> None:
    assert complete_elliptic_k(0.0) == pytest.approx(math.pi / 2, rel=1e-15)
    # K(1/sqrt(2)) = Gamma(1/4)^2 / (4 sqrt(pi))
    assert complete_elliptic_k(math.sqrt(0.5)) == pytest.approx(
        math.gamma(0.25) ** 2 / (4 * math.sqrt(math.pi)), rel=1e-14)


def pendulum_period(scene: pp.ResolvedScene) -> tuple[float, float, np.ndarray]:
    """The exact period of the physical pendulum of joint_hinge, its omega0, and the pivot."""
    joint = scene.joints[0]
    bob = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    pivot = np.array(joint.points["anchor"].world)
    axis = np.array(joint.axes["axis"].world)
    r = np.array(bob.position) - pivot
    d = np.linalg.norm(r - axis * (axis @ r))
    # inertia about the axis through the centre of mass, from the principal moments
    axis_principal = np.array(joint.axes["axis"].body2.principal)  # type: ignore[union-attr]
    inertia_com = float(np.sum(np.array(bob.principal_inertia) * axis_principal**2))
    g = np.linalg.norm(scene.gravity)
    omega0 = math.sqrt(bob.mass * g * d / (inertia_com + bob.mass * d * d))
    down = np.array(scene.gravity) / g
    amplitude = math.acos(float(r @ down) / np.linalg.norm(r))
    period = 4 * complete_elliptic_k(math.sin(amplitude / 2)) / omega0
    return period, omega0, pivot


def measured_period(rows: np.ndarray, pivot: np.ndarray) -> float:
    """From the upward zero crossings of the swing angle (x of the bob relative to the pivot),
    interpolated linearly between samples."""
    t, x = rows[:, 0], rows[:, 1] - pivot[0]
    crossings = [t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
                 for i in range(len(t) - 1) if x[i] < 0 <= x[i + 1]]
    assert len(crossings) >= 2, "fewer than one full swing"
    return float(crossings[-1] - crossings[0]) / (len(crossings) - 1)


@pytest.mark.parametrize("engine,method,parameters", [
    # 1000 iterations: the hinge's two point constraints solved to convergence (the default 10
    # leave 0.4 mm of joint error here, docs/external-engines.md#pybullet)
    (PYBULLET, "pybullet.si", {"solverIterations": 1000}),
    (MUJOCO, "mujoco-python.euler.newton", {}),
    (MUJOCO, "mujoco-python.implicitfast.newton", {}),
])
def test_hinge_pendulum_period_matches_the_elliptic_integral(
        export_scene: Export, run_engine: Run, engine: str, method: str,
        parameters: dict[str, Any]) -> None:
    scene_path = export_scene("joint_hinge", method=method, parameters=parameters)
    scene = pp.read_resolved_scene(scene_path)
    period, omega0, pivot = pendulum_period(scene)
    status, out = run_engine(engine, scene_path)
    assert_ok(status)
    rows = trajectory(out)[scene.joints[0].body2]  # type: ignore[index]
    # A first-order method at step h has a relative period error of order omega0 h
    # (2.5e-2 here); the sampling (10 ms, interpolated) adds far less.
    assert measured_period(rows, pivot) == pytest.approx(period, rel=omega0 * scene.time_step_size)


def pybullet_engine_module() -> Any:
    """pbdval.external.pybullet.engine, imported here (pybullet loads with it)."""
    from pbdval.external.pybullet import engine

    return engine


def test_a_hinge_through_a_spheres_centre_separates_its_points_by_twice_the_radius_of_gyration(
        export_scene: Export) -> None:
    # A uniform sphere (I = 2/5 m R^2 about every axis) hinged at its centre: N = 1/m and
    # D = 1/I on the plane normal to the axis, so d^2 = I/m = 2/5 R^2.
    scene = pp.read_resolved_scene(export_scene("contact_sphere_drop"))
    sphere = next(b for b in scene.bodies if b.dynamic)
    radius, mass = 0.3, 2.0
    body = dataclasses.replace(sphere, mass=mass, principal_inertia=(0.4 * mass * radius**2,) * 3)
    engine = pybullet_engine_module()
    for axis in ((0.0, 0.0, 1.0), (0.6, 0.0, 0.8), (1.0, 2.0, 3.0)):
        half = engine.hinge_half_length([body], body.position, axis)
        assert half == pytest.approx(math.sqrt(0.4) * radius, rel=1e-12)  # round-off
    static = dataclasses.replace(sphere, dynamic=False)
    assert engine.hinge_half_length([static], sphere.position, (0.0, 0.0, 1.0)) == engine.STATIC_HINGE_HALF_LENGTH


def anchor_world(body: pp.Body, local: pp.Vec3, rows: np.ndarray) -> np.ndarray:
    """A point given in the body's scene frame, in world coordinates at every sample."""
    out = []
    for row in rows:
        rotation = np.array(pybullet_engine_module()._rotation_matrix(tuple(row[4:8])))
        origin = row[1:4] - rotation @ np.array(body.principal_com)
        out.append(origin + rotation @ np.array(local))
    return np.array(out)


def test_pybullet_hinges_hold_a_double_pendulum_with_the_default_ten_sweeps(
        export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("double_pendulum", method="pybullet.si")
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(PYBULLET, scene_path)
    assert_ok(status)
    rows = trajectory(out)
    h, dt = scene.time_step_size, scene.sample_interval
    # The parity suite's bound (tests/adapters/parity_profiles.h): 10 h^2 a_max, the drift ten
    # steps of the largest acceleration can cause (a_max: of the links' centres of mass, from
    # second differences of their samples).
    acceleration = max(
        float(np.max(np.linalg.norm(x[2:] - 2 * x[1:-1] + x[:-2], axis=1))) / dt**2
        for x in (rows[b.id][:, 1:4] for b in scene.bodies if b.dynamic))
    for joint in scene.joints:
        body1, body2 = scene.body_by_id(joint.body1), scene.body_by_id(joint.body2)  # type: ignore[arg-type]
        a1 = anchor_world(body1, joint.points["anchor"].body1.scene, rows[body1.id])  # type: ignore[union-attr]
        a2 = anchor_world(body2, joint.points["anchor"].body2.scene, rows[body2.id])  # type: ignore[union-attr]
        error = float(np.max(np.linalg.norm(a1 - a2, axis=1)))
        assert error < 10 * h * h * acceleration, (joint.json_path, error, acceleration)


# --- the rebound of a dropped sphere -------------------------------------------------------

def rebound_ratio(rows: np.ndarray, contact_height: float, drop: float) -> float:
    y = rows[:, 2]
    first_contact = int(np.argmin(y[: np.argmax(rows[:, 9] > 0) + 1]))  # lowest point of the fall
    return (float(np.max(y[first_contact:])) - contact_height) / drop


@pytest.mark.parametrize("engine,method", [(PYBULLET, "pybullet.si"), (MUJOCO, "mujoco-python.euler.newton")])
def test_sphere_drop_rebounds_to_e_squared(export_scene: Export, run_engine: Run, engine: str, method: str) -> None:
    scene_path = export_scene("contact_sphere_drop", method=method, duration=1.2)
    scene = pp.read_resolved_scene(scene_path)
    ground, ball = scene.bodies
    e = scene.pair(ground.id, ball.id).restitution  # type: ignore[union-attr]
    contact_height = ground.position[1] + ground.shape.half_extents[1] + ball.shape.radius  # type: ignore[index, operator]
    drop = ball.position[1] - contact_height
    status, out = run_engine(engine, scene_path)
    assert_ok(status)
    ratio = rebound_ratio(trajectory(out)[ball.id], contact_height, drop)
    h, g = scene.time_step_size, abs(scene.gravity[1])
    impact_speed = math.sqrt(2 * g * drop)
    if engine == PYBULLET:
        # The impact is resolved within one step: the speeds in and out are each off by at most
        # g h, so (v_out / v_in)^2 is off by at most 2 (1 + e) e g h / v.
        tolerance = 2 * (1 + e) * e * g * h / impact_speed
    else:
        # A soft Kelvin-Voigt contact lasting pi tau (tau = 4h) under gravity: during it gravity
        # changes the speed by up to g pi tau, so the ratio moves by up to 2 (1 + e) e g pi tau / v.
        tolerance = 2 * (1 + e) * e * g * math.pi * 4 * h / impact_speed
    assert ratio == pytest.approx(e * e, abs=tolerance)


# --- what an engine cannot do, it names ----------------------------------------------------

@pytest.mark.parametrize("engine,case,method,feature", [
    (EXAMPLE, "joint_hinge", "", "joint:hinge"),
    (EXAMPLE, "contact_sphere_drop", "", "contacts"),
    (PYBULLET, "joint_slider", "pybullet.si", "SliderJoints[0]: joint slider"),
    (PYBULLET, "contact_sphere_pile", "pybullet.si", "RigidBodies[0]: shape hollowBox"),
    (MUJOCO, "contact_sphere_pile", "mujoco-python.euler.newton",
     "RigidBodies[0]: hollow box (collisionObjectType 7)"),
    # Its constraint-free cloth is a flex (test_mujoco_flex.py); the particle joint is not: the
    # built-in engine's feature table names it (the rigid part is that engine's model).
    (MUJOCO, "joint_rigid_body_particle_ball", "mujoco-python.euler.newton",
     "RigidBodyParticleBallJoints[0]: rigid body–particle ball joint"),
    (PYBULLET, "projectile", "pybullet.nosuch", "method pybullet.nosuch"),
    (MUJOCO, "projectile", "mujoco-python.verlet.newton", "method mujoco-python.verlet.newton"),
])
def test_unsupported_features_are_reported_by_name(export_scene: Export, run_engine: Run, engine: str,
                                                   case: str, method: str, feature: str) -> None:
    status, out = run_engine(engine, export_scene(case, method=method))
    assert status["status"] == "unsupported"
    assert any(feature in u for u in status["unsupported"]), status["unsupported"]
    assert feature in status["reason"]
    assert not trajectory_written(out)


def test_a_broken_scene_gives_status_error_naming_the_path(run_engine: Run, tmp_path: Path) -> None:
    scene = tmp_path / "broken.json"
    scene.write_text(json.dumps({"format": "pbdval.resolved-scene", "version": 1}))
    for engine in (EXAMPLE, PYBULLET, MUJOCO):
        status, _ = run_engine(engine, scene)
        assert status["status"] == "error"
        assert "broken.json" in status["reason"] and "method" in status["reason"]


def test_method_parameters_reach_the_engine(export_scene: Export, run_engine: Run) -> None:
    status, _ = run_engine(PYBULLET, export_scene("projectile", method="pybullet.pgs",
                                                  parameters={"solverIterations": 7, "erp": 0.5}))
    assert_ok(status)
    settings = status["effectiveSettings"]
    assert settings["method"] == "pybullet.pgs" and settings["solverIterations"] == 7 and settings["erp"] == 0.5
    status, _ = run_engine(MUJOCO, export_scene("projectile", method="mujoco-python.rk4.pgs",
                                                parameters={"iterations": 12, "cone": "pyramidal"}))
    assert_ok(status)
    settings = status["effectiveSettings"]
    assert (settings["integrator"], settings["solver"], settings["iterations"], settings["cone"]) == (
        "rk4", "pgs", 12, "pyramidal")


# --- the catalogues ------------------------------------------------------------------------

def test_there_is_a_catalogue_per_engine() -> None:
    assert sorted(p.stem for p in CATALOGUES) == ["dart", "drake", "example-euler", "mujoco-python", "newton",
                                                  "pybullet"]


@pytest.mark.parametrize("path", CATALOGUES, ids=lambda p: p.stem)
def test_catalogue_is_well_formed(path: Path) -> None:
    c = json.loads(path.read_text())
    assert c["protocol"] == 1 and c["name"] == path.stem
    assert c["command"][0] == "{python}"
    if c["command"][1] == "-m":  # a module of the package: importable as named
        assert len(c["command"]) == 3 and importlib.util.find_spec(c["command"][2]) is not None
    else:  # a script, relative to the catalogue file (docs/external-engines.md#the-catalogue)
        assert (path.parent / c["command"][1]).is_file()
    if "serve" in c:  # the persistent process: the same module, served
        serve = dict(c["serve"])
        runs_per_child = serve.pop("runsPerChild", 1)  # children that serve several runs in turn
        assert serve == {"protocol": 1, "command": [*c["command"], "--serve"]}
        assert isinstance(runs_per_child, int) and runs_per_child >= 1
    names = [m["name"] for m in c["methods"]]
    assert c["defaultMethod"] in names and len(set(names)) == len(names)
    assert all(n.startswith(c["name"] + ".") for n in names)
    for m in c["methods"]:
        assert m["description"]
        for p in m["parameters"]:
            assert p["kind"] in ("real", "integer", "bool", "choice") and p["description"]
            if p["kind"] == "choice":
                assert p["default"] in p["choices"]
            elif p["kind"] == "bool":
                assert isinstance(p["default"], bool)
            else:
                kind = int if p["kind"] == "integer" else float
                assert isinstance(p["default"], kind) and not isinstance(p["default"], bool)
                assert p["min"] <= p["default"] <= p["max"]


@pytest.mark.parametrize("engine,method", [
    (p.stem, m["name"])
    for p in CATALOGUES for m in json.loads(p.read_text())["methods"]])
def test_every_catalogue_method_runs_the_projectile(export_scene: Export, run_engine: Run,
                                                    engine: str, method: str) -> None:
    status, out = run_engine(engine, export_scene("projectile", method=method, duration=0.1))
    assert_ok(status)
    assert len(trajectory(out)[1]) == 11  # t = 0 and every 10 ms to 0.1 s


def test_mujoco_projects_a_jointed_initial_velocity_keeping_the_pivot_momentum(
        export_scene: Export, run_engine: Run) -> None:
    # joint_ball starts its bob with v = (0, 0, 0.8) m/s, not a rotation about the pivot; the
    # nearest joint motion in the kinetic-energy norm keeps the angular momentum about the pivot.
    scene_path = export_scene("joint_ball", method="mujoco-python.euler.newton", duration=0.01)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(MUJOCO, scene_path)
    assert_ok(status)
    bob = scene.bodies[1]
    first = trajectory(out)[bob.id][0]
    v, w = first[8:11], first[11:14]
    r = np.array(bob.position) - np.array(scene.joints[0].points["anchor"].world)
    q = bob.world_principal_rotation
    rotation = np.array([pp.quat_rotate(q, tuple(e)) for e in np.eye(3)]).T
    inertia = rotation @ np.diag(bob.principal_inertia) @ rotation.T
    def pivot_momentum(v: np.ndarray, w: np.ndarray) -> np.ndarray:
        momentum: np.ndarray = inertia @ w + bob.mass * np.cross(r, v)
        return momentum
    expected = pivot_momentum(np.array(bob.velocity), np.array(bob.angular_velocity))
    assert np.allclose(v, np.cross(w, r), atol=1e-12)  # a rotation about the pivot
    assert np.allclose(pivot_momentum(v, w), expected, rtol=1e-9, atol=1e-12)  # round-off
    assert "projected" in status["effectiveSettings"]["RigidBodies[1].initialVelocity"]


CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))


@pytest.mark.parametrize("case", CASES)
def test_no_engine_fails_on_any_case(export_scene: Export, run_engine: Run, case: str) -> None:
    """A short run of every case in every engine ends ok or unsupported, never in an error."""
    for engine, method in ((EXAMPLE, ""), (PYBULLET, "pybullet.si"), (MUJOCO, "mujoco-python.euler.newton")):
        status, out = run_engine(engine, export_scene(case, method=method, duration=0.02))
        assert status["status"] in ("ok", "unsupported"), (engine, status["reason"])
        assert (status["status"] == "ok") == trajectory_written(out)


# --- mujoco-python's catalogue, generated from pbdval.external.mujoco.catalogue ------------------

def test_the_shipped_mujoco_python_catalogue_is_the_one_the_module_generates() -> None:
    from conftest import engine_environment

    result = subprocess.run([str(VENV_PYTHON), "-m", "pbdval.external.mujoco", "--catalogue"],
                            capture_output=True, text=True, cwd=REPO, env=engine_environment(),
                            check=False, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout == (REPO / "engines" / "mujoco-python.json").read_text(), (
        "engines/mujoco-python.json is stale: regenerate it with "
        ".venv/bin/python -m pbdval.external.mujoco --catalogue > engines/mujoco-python.json")


def test_the_mujoco_catalogue_declares_exactly_the_integrators_and_solvers_the_engine_maps() -> None:
    import mujoco

    from pbdval.external.mujoco import catalogue, engine

    assert list(catalogue.INTEGRATORS) == list(engine.INTEGRATORS)
    assert list(catalogue.SOLVERS) == list(engine.SOLVERS)
    assert catalogue.MUJOCO_VERSION == mujoco.__version__
    methods = catalogue.catalogue()["methods"]
    assert len(methods) == len(engine.INTEGRATORS) * len(engine.SOLVERS)
    assert all(engine.method_parts(m["name"]) is not None for m in methods)
