"""The dart engine (pbdval.external.dart, DART through dartpy) run as the runner runs it, against
closed forms and conservation; its feature table against its own refusals; its catalogue."""

from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_engines import assert_ok, measured_period, pendulum_period, trajectory, trajectory_written

from conftest import REPO, VENV_PYTHON
from pbdval import protocol as pp

DART = "dart"
METHODS = ["dart.dantzig", "dart.pgs"]
CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))

Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]


@pytest.mark.parametrize("method", METHODS)
def test_dart_projectile_follows_the_semi_implicit_euler_parabola(export_scene: Export, run_engine: Run,
                                                                  method: str) -> None:
    scene_path = export_scene("projectile", method=method)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(DART, scene_path)
    assert_ok(status)
    body = scene.bodies[0]
    rows = trajectory(out)[body.id]
    h, g = scene.time_step_size, np.array(scene.gravity)
    n = np.array(scene.sample_steps())[:, None]
    # DART's World::step: v_{n+1} = v_n + h g, then x_{n+1} = x_n + h v_{n+1}, so
    # x_n = x0 + n h v0 + n(n+1)/2 h^2 g: the first-order integrator's exact discrete solution.
    v = np.array(body.velocity) + n * h * g
    x = np.array(body.position) + n * h * np.array(body.velocity) + n * (n + 1) / 2 * h * h * g
    # Round-off: ~1e-16 relative per operation over 300 steps of values below 10 m (DART's
    # FreeJoint composes the pose with exp(h V) each step: a few more operations than a sum).
    assert np.max(np.abs(rows[:, 8:11] - v)) < 1e-11
    assert np.max(np.abs(rows[:, 1:4] - x)) < 1e-11
    # and the closed form x0 + v0 t + g t^2 / 2 is missed by exactly the scheme's first-order
    # term g h t / 2 (not more): a check of the integrator's order
    t = n * h
    exact = np.array(body.position) + t * np.array(body.velocity) + 0.5 * t * t * g
    assert np.allclose(rows[:, 1:4] - exact, 0.5 * h * t * g, atol=1e-11)


def test_dart_hinge_pendulum_period_matches_the_elliptic_integral(export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("joint_hinge", method="dart.dantzig")
    scene = pp.read_resolved_scene(scene_path)
    period, omega0, pivot = pendulum_period(scene)
    status, out = run_engine(DART, scene_path)
    assert_ok(status)
    rows = trajectory(out)[scene.joints[0].body2]  # type: ignore[index]
    # A first-order method at step h has a relative period error of order omega0 h (the same
    # bound as the other engines', tests/python/test_engines.py); sampling adds far less.
    assert measured_period(rows, pivot) == pytest.approx(period, rel=omega0 * scene.time_step_size)


def pendulum_energy(scene: pp.ResolvedScene, rows: np.ndarray) -> np.ndarray:
    """The hinge pendulum's energy at every sample: translational + rotational about the
    centre of mass (the axis is fixed, so w is along it) + potential."""
    joint = scene.joints[0]
    bob = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    axis_principal = np.array(joint.axes["axis"].body2.principal)  # type: ignore[union-attr]
    inertia = float(np.sum(np.array(bob.principal_inertia) * axis_principal**2))
    v, w, x = rows[:, 8:11], rows[:, 11:14], rows[:, 1:4]
    kinetic = 0.5 * bob.mass * np.sum(v * v, axis=1) + 0.5 * inertia * np.sum(w * w, axis=1)
    potential = -bob.mass * (x @ np.array(scene.gravity))
    energy: np.ndarray = kinetic + potential
    return energy


def test_dart_pendulum_energy_stays_within_the_symplectic_euler_bound(export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("joint_hinge", method="dart.dantzig")
    scene = pp.read_resolved_scene(scene_path)
    _, omega0, _ = pendulum_period(scene)
    status, out = run_engine(DART, scene_path)
    assert_ok(status)
    rows = trajectory(out)[scene.joints[0].body2]  # type: ignore[index]
    energy = pendulum_energy(scene, rows)
    bob = scene.body_by_id(scene.joints[0].body2)  # type: ignore[arg-type]
    lowest = float(np.min(-bob.mass * (rows[:, 1:4] @ np.array(scene.gravity))))
    swing = energy[0] - lowest  # the energy of the swing, above the lowest potential reached
    # Symplectic (semi-implicit) Euler conserves H~ = H - (h/2) V'(q) p/m exactly for a linear
    # oscillator; |V'(q) p/m| <= omega0 E, so H stays within h omega0 E of its start (without a
    # drift: conservative, no contact, no joint error in reduced coordinates).
    assert float(np.max(np.abs(energy - energy[0]))) < scene.time_step_size * omega0 * swing


def test_dart_joints_hold_to_round_off_in_reduced_coordinates(export_scene: Export, run_engine: Run) -> None:
    scene_path = export_scene("double_pendulum", method="dart.dantzig", duration=1.0)
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(DART, scene_path)
    assert_ok(status)
    rows = trajectory(out)
    for joint in scene.joints:
        anchors = []
        for body_id, side in ((joint.body1, "body1"), (joint.body2, "body2")):
            body = scene.body_by_id(body_id)  # type: ignore[arg-type]
            local = np.array(getattr(joint.points["anchor"], side).scene)
            points = []
            for row in rows[body.id]:
                w, x, y, z = row[4:8]
                r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                              [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                              [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
                points.append(row[1:4] + r @ (local - np.array(body.principal_com)))
            anchors.append(np.array(points))
        # A tree joint has no error coordinate: only the round-off of composing poses over 1 s
        # (1e-16 per operation, a few hundred operations per step on 1 m levers) remains.
        assert float(np.max(np.linalg.norm(anchors[0] - anchors[1], axis=1))) < 1e-9, joint.json_path


@pytest.mark.parametrize("case,feature", [
    ("joint_ball_on_line", "BallOnLineJoints[0]: joint ball_on_line"),
    ("contact_sphere_pile", "RigidBodies[0]: shape hollowBox"),
    ("cloth_hanging", "particles"),
    ("joint_target_velocity_motor_hinge", "TargetVelocityMotorHingeJoints[0]"),
])
def test_dart_names_what_it_cannot_run(export_scene: Export, run_engine: Run, case: str, feature: str) -> None:
    status, out = run_engine(DART, export_scene(case, method="dart.dantzig"))
    assert status["status"] == "unsupported"
    assert any(feature in u for u in status["unsupported"]), status["unsupported"]
    assert not trajectory_written(out)


def test_dart_reports_a_bad_parameter_and_a_bad_scene_as_errors_naming_them(
        export_scene: Export, run_engine: Run, tmp_path: Path) -> None:
    status, _ = run_engine(DART, export_scene("projectile", method="dart.dantzig",
                                              parameters={"collisionDetector": "havok"}))
    assert status["status"] == "error"
    assert "collisionDetector" in status["reason"] and "havok" in status["reason"]
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"format": "pbdval.resolved-scene", "version": 1}))
    status, _ = run_engine(DART, broken)
    assert status["status"] == "error" and "broken.json" in status["reason"]


def test_dart_method_parameters_reach_the_engine(export_scene: Export, run_engine: Run) -> None:
    status, _ = run_engine(DART, export_scene("contact_sphere_drop", method="dart.pgs", duration=0.1,
                                              parameters={"iterations": 37, "collisionDetector": "bullet"}))
    assert_ok(status)
    settings = status["effectiveSettings"]
    assert settings["iterations"] == 37 and settings["collisionDetector"] == "BulletCollisionDetector"
    assert settings["boxedLcpSolver"] == "PgsBoxedLcpSolver" and settings["secondaryBoxedLcpSolver"] == "none"


def test_dart_feature_table_and_own_check_agree_on_every_case_and_method() -> None:
    """On every case of the library and both methods, the engine's own check refuses a run
    exactly when the catalogue's table (engines/dart.json, as the runner reads it) declares a
    feature of it unsupported; the only refusals a table cannot see are the loop-closing joints
    of the spanning forest (joint_trees) and pair materials that no per-body values give
    (contact.nonSeparableMaterials), which the engine adds."""
    from pbdval.api import _core
    from pbdval.external.dart.engine import unsupported_features

    core = _core()
    registry = core._Registry()
    disagreements = []
    for case in CASES:
        case_file = str(REPO / "cases" / f"{case}.json")
        scene = core._load_scene(case_file, False)
        for method in METHODS:
            table = [u["message"] for u in core._feature_support(registry, scene, method)["table_unsupported"]]
            resolved = pp.parse_resolved_scene(core._resolved_scene(registry, scene, method, {}, 0.1, -1.0), case)
            own = unsupported_features(resolved)
            extra_only = own and not table and all("closes a kinematic loop" in m or m.startswith("contact ")
                                                    for m in own)
            if bool(own) != bool(table) and not extra_only:
                disagreements.append(f"{case} {method}: engine {own or 'runs'}; table {table or 'runs'}")
    assert not disagreements, "\n".join(disagreements)


def test_the_shipped_dart_catalogue_is_the_generators(tmp_path: Path) -> None:
    result = subprocess.run([str(VENV_PYTHON), "-m", "pbdval.external.dart", "--catalogue"],
                            capture_output=True, text=True, cwd=REPO, check=True,
                            env={"PYTHONPATH": str(REPO / "python"), "PATH": "/usr/bin:/bin"})
    assert result.stdout == (REPO / "engines" / "dart.json").read_text(), (
        "engines/dart.json is stale: regenerate it with "
        ".venv/bin/python -m pbdval.external.dart --catalogue > engines/dart.json")


def test_the_dart_catalogue_announces_the_installed_dartpy() -> None:
    import dartpy

    from pbdval.external.dart.catalogue import DART_VERSION

    assert dartpy.__version__ == DART_VERSION
    requirements = (REPO / "python" / "requirements.txt").read_text()
    assert f"dartpy=={DART_VERSION}" in requirements


def test_dart_friction_per_body_reproduces_every_pairs_minimum(export_scene: Export) -> None:
    from pbdval.external.dart.engine import friction_per_body

    for case in ("contact_pyramid", "contact_incline_slide", "xpbd_stack_10"):
        scene = pp.read_resolved_scene(export_scene(case))
        values = friction_per_body(scene)
        assert values is not None
        assert all(math.isfinite(v) for v in values)
        index = {b.id: b.index for b in scene.bodies}
        for p in scene.contact_pairs:
            # min of two stored values is one of them: exact
            assert min(values[index[p.bodies[0]]], values[index[p.bodies[1]]]) == p.friction


@pytest.mark.parametrize("case", CASES)
def test_dart_ends_ok_or_unsupported_on_every_case(export_scene: Export, run_engine: Run, case: str) -> None:
    """A short run of every case ends ok or unsupported, never in an error."""
    status, out = run_engine(DART, export_scene(case, method="dart.dantzig", duration=0.02))
    assert status["status"] in ("ok", "unsupported"), status["reason"]
    assert (status["status"] == "ok") == trajectory_written(out)


def test_the_joint_forest_orients_trees_from_the_world_flags_flipped_joints_and_finds_loops(
        export_scene: Export) -> None:
    import dataclasses

    from pbdval.external import joint_trees

    scene = pp.read_resolved_scene(export_scene("double_pendulum"))
    first, second = scene.joints  # static base - link 1, link 1 - link 2
    forest = joint_trees.plan_forest(scene, ["hinge"])
    links = [b.index for b in scene.bodies if b.dynamic]
    assert forest.order == links and forest.loops == [] and forest.free_roots() == []
    assert forest.parent_joint[links[0]].parent == joint_trees.WORLD
    assert forest.parent_joint[links[1]] == joint_trees.TreeJoint(1, links[0], links[1], flipped=False)
    # the second joint written the other way round: the same tree, the joint flipped
    swapped = dataclasses.replace(second, body1=second.body2, body2=second.body1)
    flipped = joint_trees.plan_forest(dataclasses.replace(scene, joints=(first, swapped)), ["hinge"])
    assert flipped.parent_joint[links[1]].flipped
    # a third joint between the same links closes a loop; without tree joints every link is free
    looped = dataclasses.replace(scene, joints=(first, second, second))
    assert joint_trees.plan_forest(looped, ["hinge"]).loops == [2]
    assert "closes a kinematic loop" in joint_trees.loop_messages(looped, joint_trees.plan_forest(looped, ["hinge"]),
                                                                   "DART")[0]
    assert joint_trees.plan_forest(scene, []).free_roots() == links
