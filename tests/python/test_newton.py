"""The newton engine (pbdval.external.newton, NVIDIA Newton on Warp's CPU kernels) run as the
runner runs it, against closed forms and conservation, with tolerances that carry Warp's float32
state; its feature table against its own refusals; its catalogue and its opt-in."""

from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_dart import pendulum_energy
from test_engines import assert_ok, measured_period, pendulum_period, trajectory, trajectory_written

from conftest import REPO, VENV_PYTHON
from pbdval import protocol as pp

NEWTON = "newton"
#: Warp's float32 unit round-off (2^-24).
FLOAT32_EPSILON = 2.0**-24
CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))
METHODS = ["newton.xpbd", "newton.featherstone", "newton.semiImplicit"]

Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]


@pytest.mark.parametrize("method,substeps", [("newton.xpbd", 1), ("newton.featherstone", 10),
                                             ("newton.semiImplicit", 10)])
def test_newton_projectile_follows_the_semi_implicit_euler_parabola_to_float32_round_off(
        export_scene: Export, run_engine: Run, method: str, substeps: int) -> None:
    scene_path = export_scene("projectile", method=method)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    assert status["integratorStepsPerSceneStep"] == substeps  # the catalogue's default
    body = scene.bodies[0]
    rows = trajectory(out)[body.id]
    h, g = scene.time_step_size / substeps, np.array(scene.gravity)
    n = np.array(scene.sample_steps())[:, None] * substeps
    # Every solver's free body: v += h g, then x += h v (XPBD's velocity is then (x - x_old)/h,
    # the same value up to round-off): x_n = x0 + n h v0 + n(n+1)/2 h^2 g.
    v = np.array(body.velocity) + n * h * g
    x = np.array(body.position) + n * h * np.array(body.velocity) + n * (n + 1) / 2 * h * h * g
    # float32: each internal step rounds the position sum (2^-24 |x|) and the velocity sum, whose
    # error reaches x through h v over the steps (at most as much again): 2 N 2^-24 max|x|, and
    # likewise for v (XPBD's difference quotient adds 2^-24 |x| / h per step, not accumulated).
    steps = scene.steps * substeps
    x_bound = 2 * steps * FLOAT32_EPSILON * float(np.max(np.abs(x)))
    v_bound = 2 * steps * FLOAT32_EPSILON * float(np.max(np.abs(v))) + (
        2 * FLOAT32_EPSILON * float(np.max(np.abs(x))) / h if method == "newton.xpbd" else 0.0)
    assert float(np.max(np.abs(rows[1:, 1:4] - x[1:]))) < x_bound
    assert float(np.max(np.abs(rows[1:, 8:11] - v[1:]))) < v_bound
    # the first sample is the scene's state exactly (the engine writes it, not Newton's float32 copy)
    assert np.array_equal(rows[0, 1:4], np.array(body.position))


def test_newton_featherstone_pendulum_period_matches_the_elliptic_integral(
        export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("joint_hinge", method="newton.featherstone")
    scene = pp.read_resolved_scene(scene_path)
    period, omega0, pivot = pendulum_period(scene)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    rows = trajectory(out)[scene.joints[0].body2]  # type: ignore[index]
    # First-order (semi-implicit Euler) at the internal step h/10: relative period error of
    # order omega0 h / 10; float32 (1e-7) and the 10 ms sampling add far less.
    assert measured_period(rows, pivot) == pytest.approx(period, rel=omega0 * scene.time_step_size / 10)


@pytest.mark.parametrize("linear,angular", [(0.4, 0.4), (0.7, 0.4)])
def test_newton_xpbd_pendulum_swings_with_its_inertia_scaled_by_the_relaxation_ratio(
        export_scene: Export, run_engine: Run, linear: float, angular: float) -> None:
    """SolverXPBD scales a positional joint row's translational correction by the linear
    relaxation and its rotational one by the angular relaxation (xpbd/kernels.py,
    solve_body_joints): the joint's torque about the centre of mass is applied as if the inertia
    there were I·linear/angular. Equal factors (the engine's default 0.4) give the scene's pendulum;
    Newton's defaults 0.7 and 0.4 give one with 1.75 I about the centre of mass, 19 % more about
    the pivot (docs/engine-newton.md#relaxation)."""
    substeps = 4
    scene_path = export_scene("joint_hinge", method="newton.xpbd", parameters={
        "substeps": substeps, "jointLinearRelaxation": linear, "jointAngularRelaxation": angular})
    scene = pp.read_resolved_scene(scene_path)
    period, omega0, pivot = pendulum_period(scene)
    joint = scene.joints[0]
    bob = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    d = float(np.linalg.norm(np.array(bob.position) - pivot))  # the axis is z, r lies in xy
    pivot_inertia = bob.mass * float(np.linalg.norm(scene.gravity)) * d / omega0**2
    com_inertia = pivot_inertia - bob.mass * d * d
    # the same amplitude: the period scales as 1/omega0, i.e. as the root of the pivot inertia
    expected = period * math.sqrt((com_inertia * linear / angular + bob.mass * d * d) / pivot_inertia)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    rows = trajectory(out)[joint.body2]  # type: ignore[index]
    h = scene.time_step_size / substeps
    # First order in h: a relative period error of order omega0 h (1.0 omega0 h measured at
    # h = 1 ms with equal factors, docs/engine-newton.md#relaxation), 2 omega0 h allowed; the two
    # expectations differ by 9 % (12 omega0 h), so the test tells them apart.
    assert measured_period(rows, pivot) == pytest.approx(expected, rel=2 * omega0 * h)


def test_newton_featherstone_pendulum_energy_stays_within_the_symplectic_euler_bound(
        export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("joint_hinge", method="newton.featherstone")
    scene = pp.read_resolved_scene(scene_path)
    _, omega0, _ = pendulum_period(scene)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    rows = trajectory(out)[scene.joints[0].body2]  # type: ignore[index]
    energy = pendulum_energy(scene, rows)
    bob = scene.body_by_id(scene.joints[0].body2)  # type: ignore[arg-type]
    lowest = float(np.min(-bob.mass * (rows[:, 1:4] @ np.array(scene.gravity))))
    swing = energy[0] - lowest
    # Symplectic Euler at h/10 keeps H within (h/10) omega0 E of its start (test_dart.py's
    # bound); float32 positions (2^-24 of ~2 m, times m g) add a negligible 1e-6 J.
    bound = scene.time_step_size / 10 * omega0 * swing + bob.mass * 9.81 * 2.0 * 2 * FLOAT32_EPSILON * scene.steps
    assert float(np.max(np.abs(energy - energy[0]))) < bound


@pytest.mark.parametrize("method,substeps", [("newton.xpbd", 1), ("newton.featherstone", 10)])
def test_newton_slider_slides_along_its_oblique_axis_as_semi_implicit_euler(
        export_scene: Export, run_engine: Run, method: str, substeps: int) -> None:
    """joint_slider's axis is (1, -1, 0)/√2. SolverXPBD bounds a joint's coordinates by a box
    per component of the axis in the joint frame, so the axis given in world axes freed both x
    and y and the box fell 3.2 m straight down in 1 s (docs/engine-newton.md); given as the x of
    a joint frame turned onto it, the box slides along the line. SolverXPBD runs at relaxation 1
    here: the engine's 0.4 leaves 0.6² of each step's drift off the line after two iterations
    (1e-4 m), which is the solver's convergence, not the frame this test checks."""
    parameters: dict[str, pp.ParameterValue] = (
        {"jointLinearRelaxation": 1.0, "jointAngularRelaxation": 1.0} if method == "newton.xpbd" else {})
    scene_path = export_scene("joint_slider", method=method, parameters=parameters)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(NEWTON, scene_path)
    assert_ok(status)
    joint = scene.joints[0]
    body = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    rows = trajectory(out)[body.id]
    axis = np.array(joint.axes["axis"].world)
    axis /= np.linalg.norm(axis)
    h, n = scene.time_step_size / substeps, np.array(scene.sample_steps()) * substeps
    # From rest, frictionless: semi-implicit Euler of the acceleration g·u along the axis u
    # (XPBD: the predicted x + h v + h² g projected on the line, v = Δx/h; Featherstone: the
    # joint coordinate), s_n = n(n+1)/2 h² g·u.
    along = n * (n + 1) / 2 * h * h * float(np.dot(scene.gravity, axis))
    offset = rows[:, 1:4] - np.array(body.position)
    # float32 state: each internal step rounds the position (2^-24 |x|), N steps at most
    # 2 N 2^-24 max|x| (the projectile test's bound); the XPBD projection onto a straight line at
    # relaxation 1 is exact up to the same round-off.
    bound = 2 * scene.steps * substeps * FLOAT32_EPSILON * float(np.max(np.abs(rows[:, 1:4])))
    assert float(np.max(np.abs(offset @ axis - along))) < bound
    off_line = offset - np.outer(offset @ axis, axis)
    assert float(np.max(np.linalg.norm(off_line, axis=1))) < bound


def test_newton_mujoco_warp_method_is_unsupported_with_its_measured_reason(export_scene: Export,
                                                                           run_engine: Run) -> None:
    status, out = run_engine(NEWTON, export_scene("projectile", method="newton.mujoco"))
    assert status["status"] == "unsupported"
    assert "mujoco-warp~=3.17.0" in status["reason"] and "mujoco-core 4.0.0" in status["reason"]
    assert not trajectory_written(out)


@pytest.mark.parametrize("case,feature", [
    ("joint_damper", "DamperJoints[0]: joint damper"),
    ("contact_sphere_pile", "RigidBodies[0]: shape hollowBox"),
    ("tet_cantilever", "TetModels[0]: solid method 3 (fem_xpbd)"),
    ("joint_rigid_body_particle_ball", "RigidBodyParticleBallJoints[0]"),
])
def test_newton_names_what_it_cannot_run(export_scene: Export, run_engine: Run, case: str, feature: str) -> None:
    status, out = run_engine(NEWTON, export_scene(case, method="newton.xpbd"))
    assert status["status"] == "unsupported"
    assert any(feature in u for u in status["unsupported"]), status["unsupported"]
    assert not trajectory_written(out)


def test_newton_reports_a_bad_parameter_as_an_error_naming_it(export_scene: Export, run_engine: Run) -> None:
    status, _ = run_engine(NEWTON, export_scene("projectile", method="newton.xpbd", parameters={"substeps": 0}))
    assert status["status"] == "error" and "substeps" in status["reason"]


def test_newton_compiles_its_kernels_under_the_build_folder(export_scene: Export, run_engine: Run) -> None:
    status, _ = run_engine(NEWTON, export_scene("projectile", method="newton.xpbd", duration=0.05))
    assert_ok(status)
    cache = Path(str(status["effectiveSettings"]["kernelCache"]))
    assert cache == REPO / "build" / "cache" / "warp"
    assert any(cache.rglob("*.o")) or any(cache.rglob("*.so")) or any(cache.rglob("*.meta"))


def test_newton_feature_table_and_own_check_agree_on_every_case_and_method() -> None:
    """As test_dart.py's: the engine refuses a run exactly when engines/newton.json's table
    declares a feature of it unsupported, but for loop-closing joints and pair materials."""
    from pbdval.api import _core
    from pbdval.external.newton.engine import unsupported_features

    core = _core()
    registry = core._Registry()
    disagreements = []
    for case in CASES:
        scene = core._load_scene(str(REPO / "cases" / f"{case}.json"), False)
        for method in METHODS:
            table = [u["message"] for u in core._feature_support(registry, scene, method)["table_unsupported"]]
            resolved = pp.parse_resolved_scene(core._resolved_scene(registry, scene, method, {}, 0.1, -1.0), case)
            own = unsupported_features(resolved)
            extra_only = own and not table and all("closes a kinematic loop" in m or m.startswith("contact ")
                                                    for m in own)
            if bool(own) != bool(table) and not extra_only:
                disagreements.append(f"{case} {method}: engine {own or 'runs'}; table {table or 'runs'}")
    assert not disagreements, "\n".join(disagreements)


def test_the_shipped_newton_catalogue_is_the_generators() -> None:
    result = subprocess.run([str(VENV_PYTHON), "-m", "pbdval.external.newton", "--catalogue"],
                            capture_output=True, text=True, cwd=REPO, check=True,
                            env={"PYTHONPATH": str(REPO / "python"), "PATH": "/usr/bin:/bin"})
    assert result.stdout == (REPO / "engines" / "newton.json").read_text(), (
        "engines/newton.json is stale: regenerate it with "
        ".venv/bin/python -m pbdval.external.newton --catalogue > engines/newton.json")


def test_the_newton_catalogue_announces_the_installed_newton_and_warp() -> None:
    from importlib.metadata import version

    from pbdval.external.newton.catalogue import NEWTON_VERSION, WARP_VERSION

    assert (version("newton"), version("warp-lang")) == (NEWTON_VERSION, WARP_VERSION)


def test_newton_runs_only_when_named(pbdval_binary: Path, tmp_path: Path) -> None:
    """runByDefault false: registered (its methods are listed) but not in the default plan; a
    runByDefault that is not a boolean is refused naming the file and the key."""
    plan = subprocess.run([str(pbdval_binary), "run", "--list-plan"], capture_output=True, text=True,
                          cwd=REPO, check=True)
    assert all(run["engine"] != NEWTON for run in json.loads(plan.stdout)["runs"])
    methods = subprocess.run([str(pbdval_binary), "methods"], capture_output=True, text=True, check=True)
    assert "newton.xpbd" in methods.stdout
    named = subprocess.run([str(pbdval_binary), "run", "--list-plan", "--engines", NEWTON, "cases/projectile.json"],
                           capture_output=True, text=True, cwd=REPO, check=True)
    assert [run["engine"] for run in json.loads(named.stdout)["runs"]] == [NEWTON]
    document = json.loads((REPO / "engines" / "newton.json").read_text())
    document.update(name="probe", defaultMethod="probe.xpbd", runByDefault="no")
    document["methods"] = [{"name": "probe.xpbd"}]
    document["features"] = [f for f in document["features"] if "methods" not in f]  # newton.* only
    (tmp_path / "probe.json").write_text(json.dumps(document))
    result = subprocess.run([str(pbdval_binary), "methods"], capture_output=True, text=True, check=False,
                            env={"PBDVAL_ENGINE_CATALOGUE": str(tmp_path), "PATH": "/usr/bin:/bin"})
    assert result.returncode != 0
    assert "probe.json" in result.stderr and "runByDefault" in result.stderr, result.stderr
