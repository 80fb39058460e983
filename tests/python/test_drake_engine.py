"""The drake engine (python/pbdval/external/drake/, docs/engine-drake.md): closed forms, its
catalogue and feature table, and its errors. Scenes are written here as resolved-scene documents
(the protocol's input), so that every expected value follows from the numbers in the test."""

from __future__ import annotations

import importlib.metadata
import json
import math
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from conftest import REPO, engine_command, engine_environment
from pbdval import protocol as pp
from pbdval.external.drake import catalogue, engine
from pbdval.external.drake.features import FEATURES, JOINTS, SHAPES

IDENTITY = [1.0, 0.0, 0.0, 0.0]
G = 9.81
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]
Export = Callable[..., Path]


def body(index: int, *, dynamic: bool = True, mass: float = 1.0, inertia: tuple[float, float, float] = (0.1, 0.1, 0.1),
         position: tuple[float, float, float] = (0.0, 0.0, 0.0), velocity: tuple[float, float, float] = (0.0, 0.0, 0.0),
         shape: dict[str, Any] | None = None) -> dict[str, Any]:
    """A body whose scene frame is its principal frame (centre of mass at the scene origin)."""
    return {"id": index, "index": index, "jsonPath": f"RigidBodies[{index}]", "dynamic": dynamic,
            "mass": mass if dynamic else 0.0, "principalInertia": list(inertia),
            "principalFrame": {"centerOfMass": [0.0, 0.0, 0.0], "rotation": IDENTITY},
            "pose": {"position": list(position), "rotation": IDENTITY, "sceneOrigin": list(position),
                     "principalRotation": IDENTITY},
            "velocity": list(velocity), "angularVelocity": [0.0, 0.0, 0.0],
            "shape": shape or {"type": "none"}, "material": {"friction": 0.5, "restitution": 0.0}}


def joint(kind: str, body1: int, body2: int, index: int = 0, **axes: list[float]) -> dict[str, Any]:
    return {"type": kind, "block": "Joints", "jsonPath": f"Joints[{index}]", "body1": body1, "body2": body2,
            "points": {"anchor": {"world": [0.0, 0.0, 0.0], "body1": None, "body2": None}},
            "axes": {name: {"world": value, "body1": None, "body2": None} for name, value in axes.items()}}


def resolved(bodies: list[dict[str, Any]], joints: list[dict[str, Any]] | None = None, *, h: float = 0.01,
             steps: int = 100, stride: int = 1, method: str = "drake.rk3",
             parameters: dict[str, pp.ParameterValue] | None = None,
             pairs: list[dict[str, Any]] | None = None) -> dict[str, Any]:
    return {"format": "pbdval.resolved-scene", "version": 1, "source": "/test", "name": "test",
            "method": {"name": method, "parameters": parameters or {}}, "gravity": [0.0, -G, 0.0],
            "timeStepSize": h, "duration": h * steps, "sampleInterval": h * stride, "steps": steps,
            "sampleStride": stride, "contactTolerance": 0.0, "contactCombineRule": "average",
            "bodies": bodies, "joints": joints or [], "contactPairs": pairs or []}


def run(document: dict[str, Any], tmp_path: Path) -> tuple[pp.Status, np.ndarray]:
    """The engine's run in this process (its main's path minus the files): status and rows."""
    out = tmp_path / f"out{len(list(tmp_path.iterdir()))}"
    out.mkdir()
    status = engine.DrakeRun(pp.parse_resolved_scene(document)).run(out)
    return status, np.load(out / "trajectory.npy")


def write(document: dict[str, Any], tmp_path: Path) -> Path:
    path = tmp_path / f"scene{len(list(tmp_path.iterdir()))}.json"
    path.write_text(json.dumps(document))
    return path


# --- closed forms --------------------------------------------------------------------------------

@pytest.mark.parametrize("method", ["drake.rk3", "drake.radau", "drake.implicit_euler"])
def test_a_free_body_falls_on_the_parabola_under_the_continuous_methods(method: str, tmp_path: Path) -> None:
    v0 = (1.0, 2.0, -0.5)
    status, rows = run(resolved([body(0, velocity=v0)], steps=100, stride=10, method=method,
                                parameters={"targetAccuracy": 1e-6}), tmp_path)
    assert status.status == "ok", status.reason
    t = rows[:, 0]
    expected = np.column_stack([v0[0] * t, v0[1] * t - 0.5 * G * t * t, v0[2] * t])
    error = np.abs(rows[:, 2:5] - expected).max()
    if method == "drake.implicit_euler":
        # First order: each step of size h_i misses g h_i^2 / 2, a local error the controller
        # holds below the accuracy; the global error is at most their sum.
        assert error < int(status.effective_settings["integrator.stepsTaken"]) * 1e-6
    else:
        # RK3 and two-stage Radau IIA are third order, exact on a quadratic: round-off only, a
        # few ulps of |x| ~ 5 m per step over about a hundred steps.
        assert error < 1e-11
        assert np.abs(rows[:, 9:12] - np.column_stack([np.full_like(t, v0[0]), v0[1] - G * t,
                                                       np.full_like(t, v0[2])])).max() < 1e-11


def test_implicit_euler_at_fixed_steps_takes_the_scene_steps_on_its_own_parabola(tmp_path: Path) -> None:
    """stepControl=fixed: no error control, the scene's step h taken as is. Drake's implicit Euler
    propagates its step-doubling solution, two implicit Euler half steps (its one Newton
    iteration is exact on this linear system): after n steps, 2n half steps of h/2,
    x_n = v0 n h + g (h/2)^2 (2n)(2n+1)/2. Any other step sequence misses this by ~g h^2."""
    v0, h, steps = (1.0, 2.0, -0.5), 0.01, 100
    status, rows = run(resolved([body(0, velocity=v0)], h=h, steps=steps, stride=10, method="drake.implicit_euler",
                                parameters={"stepControl": "fixed"}), tmp_path)
    assert status.status == "ok", status.reason
    assert status.effective_settings["stepControl"] == "fixed"
    assert "integrator.smallestStep" not in status.effective_settings  # no step was adapted
    m = 2 * np.round(rows[:, 0] / h)  # half steps
    half = h / 2
    expected = np.column_stack([v0[0] * m * half, v0[1] * m * half - G * half * half * m * (m + 1) / 2,
                                v0[2] * m * half])
    # Round-off only: a few ulps of |x| ~ 5 m per step over two hundred half steps.
    assert np.abs(rows[:, 2:5] - expected).max() < 1e-11
    # Under error control the same method picks its own steps, and lands elsewhere.
    status, controlled = run(resolved([body(0, velocity=v0)], h=h, steps=steps, stride=10,
                                      method="drake.implicit_euler"), tmp_path)
    assert np.abs(controlled[:, 2:5] - expected).max() > 1e-6


def test_a_step_control_that_is_neither_error_nor_fixed_is_an_error_naming_it(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="parameter stepControl: expected error or fixed, got 'adaptive'"):
        run(resolved([body(0)], parameters={"stepControl": "adaptive"}), tmp_path)


@pytest.mark.parametrize("method", ["drake.sap", "drake.tamsi"])
def test_a_free_body_under_the_discrete_methods_is_the_semi_implicit_euler_parabola(
        method: str, tmp_path: Path) -> None:
    # The discrete plant updates v first, then x with the new v: after n steps
    # y_n = y_0 + v_0 n h - g h^2 n (n + 1) / 2 (the closed form of semi-implicit Euler).
    h, v0 = 0.01, 2.0
    status, rows = run(resolved([body(0, velocity=(0.0, v0, 0.0))], h=h, steps=100, method=method), tmp_path)
    assert status.status == "ok", status.reason
    n = np.round(rows[:, 0] / h)
    # Round-off: n ≤ 100 additions of numbers ≤ 5 m.
    assert np.abs(rows[:, 3] - (v0 * n * h - G * h * h * n * (n + 1) / 2)).max() < 1e-12
    assert np.abs(rows[:, 10] - (v0 - G * n * h)).max() < 1e-12


def agm(a: float, b: float) -> float:
    while abs(a - b) > 1e-15 * a:
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return a


def pendulum(theta0: float, accuracy: float, method: str = "drake.rk3") -> tuple[dict[str, Any], float]:
    """A compound pendulum on a hinge about z through the origin (bob of 1 kg at 1 m, central
    inertia 1e-4 kg m²), released at rest from theta0, run for one period of the finite-amplitude
    pendulum T = 2π / (AGM(1, cos(θ₀/2)) ω₀), ω₀² = m g L / (I + m L²), in 200 steps."""
    length, mass, central = 1.0, 1.0, 1e-4
    omega = math.sqrt(mass * G * length / (central + mass * length * length))
    period = 2 * math.pi / (agm(1.0, math.cos(theta0 / 2)) * omega)
    bob = body(1, mass=mass, inertia=(central, central, central),
               position=(length * math.sin(theta0), -length * math.cos(theta0), 0.0))
    document = resolved([body(0, dynamic=False), bob], [joint("hinge", 0, 1, axis=[0.0, 0.0, 1.0])],
                        h=period / 200, steps=200, stride=200, method=method,
                        parameters={"targetAccuracy": accuracy})
    return document, period


@pytest.mark.parametrize("method", ["drake.rk3", "drake.radau"])
def test_a_hinge_pendulum_returns_to_its_release_angle_after_the_elliptic_period(method: str, tmp_path: Path) -> None:
    theta0 = 0.5
    errors = {}
    for accuracy in (1e-7, 1e-9):
        document, _ = pendulum(theta0, accuracy, method)
        status, rows = run(document, tmp_path)
        assert status.status == "ok", status.reason
        x, y = rows[-1, 2], rows[-1, 3]
        errors[accuracy] = abs(math.atan2(x, -y) - theta0)
        steps = int(status.effective_settings["integrator.stepsTaken"])
        # Each accepted step's local error is held below `accuracy` (relative to a state of
        # order 1: |θ| < 1 rad, |θ'| < 2 rad/s); without amplification the global error is at
        # most their sum.
        assert errors[accuracy] < steps * accuracy, (accuracy, errors[accuracy], steps)
    # Tighter accuracy gives a smaller error: the step-size control with an error estimate of
    # order p = 2 takes h ∝ a^(1/3), a third-order method's error then falls ∝ h^3 ∝ a; at
    # least a^(2/3) for any order ≥ 2 of the solution: 100^(2/3) = 21.5 for 100× tighter.
    assert errors[1e-9] < errors[1e-7] / 20, errors


def test_the_converged_reference_is_within_1e_9_rad_of_the_analytic_pendulum(tmp_path: Path) -> None:
    # The converged reference (drake.rk3 at targetAccuracy 1e-10, docs/engine-drake.md): its
    # error bound is steps × 1e-10 (previous test's argument); with under 1e4 steps, 1e-6 rad.
    document, _ = pendulum(1.0, 1e-10)
    status, rows = run(document, tmp_path)
    assert status.status == "ok", status.reason
    error = abs(math.atan2(rows[-1, 2], -rows[-1, 3]) - 1.0)
    assert error < int(status.effective_settings["integrator.stepsTaken"]) * 1e-10


def test_a_jointed_initial_velocity_is_projected_keeping_the_momentum_about_the_pivot(tmp_path: Path) -> None:
    # A bob on a hinge about z at (1, 0, 0) given v = (1, 1, 0): the hinge allows only v ⊥ r,
    # so the projection (kinetic-energy norm) keeps the angular momentum about the pivot:
    # I_pivot ω = m (r × v)_z → ω = 1 / (1e-4 + 1), v = ω × r = (0, ω, 0).
    bob = body(1, mass=1.0, inertia=(1e-4, 1e-4, 1e-4), position=(1.0, 0.0, 0.0), velocity=(1.0, 1.0, 0.0))
    document = resolved([body(0, dynamic=False), bob], [joint("hinge", 0, 1, axis=[0.0, 0.0, 1.0])], steps=1)
    status, rows = run(document, tmp_path)
    omega = 1.0 / (1e-4 + 1.0)
    assert np.allclose(rows[1, 9:12], [0.0, omega, 0.0], atol=1e-14)  # round-off of one solve
    assert np.allclose(rows[1, 12:15], [0.0, 0.0, omega], atol=1e-14)
    assert "projected" in str(status.effective_settings["RigidBodies[1].initialVelocity"])


def test_a_rigid_body_spring_oscillates_at_the_two_body_frequency(tmp_path: Path) -> None:
    # Two free 1 kg bodies without gravity on a spring k = 100 N/m whose rest length is the
    # anchors' initial distance, 1 m (the seed's), moving apart at 1 m/s: the anchors'
    # separation is 1 + (1/ω) sin ωt with ω = sqrt(k / μ), μ = 1/2 kg the reduced mass.
    k = 100.0
    bodies = [body(0, position=(-0.55, 0.0, 0.0), velocity=(-0.5, 0.0, 0.0)),
              body(1, position=(0.55, 0.0, 0.0), velocity=(0.5, 0.0, 0.0))]
    spring = {"type": "rigid_body_spring", "block": "RigidBodySprings", "jsonPath": "RigidBodySprings[0]",
              "body1": 0, "body2": 1, "restLength": 1.0, "stiffness": k, "axes": {},
              "points": {"anchor1": {"world": [-0.5, 0.0, 0.0], "body1": {"scene": [0.05, 0.0, 0.0],
                                                                           "principal": [0.05, 0.0, 0.0]},
                                     "body2": None},
                         "anchor2": {"world": [0.5, 0.0, 0.0], "body1": None,
                                     "body2": {"scene": [-0.05, 0.0, 0.0], "principal": [-0.05, 0.0, 0.0]}}}}
    document = resolved(bodies, [spring], steps=100, stride=10, parameters={"targetAccuracy": 1e-10})
    document["gravity"] = [0.0, 0.0, 0.0]
    status, rows = run(document, tmp_path)
    assert status.status == "ok", status.reason
    t = rows[0::2, 0]
    separation = rows[1::2, 2] - rows[0::2, 2] - 0.1  # between the anchors
    omega = math.sqrt(k / 0.5)
    expected = 1.0 + np.sin(omega * t) / omega
    # The sum of local errors (previous tests' argument): stepsTaken × 1e-10.
    bound = int(status.effective_settings["integrator.stepsTaken"]) * 1e-10
    assert np.abs(separation - expected).max() < bound


# --- feature table, catalogue, errors ------------------------------------------------------------

def test_the_shipped_catalogue_is_the_one_the_module_generates() -> None:
    assert (REPO / "engines" / "drake.json").read_text(encoding="utf-8") == catalogue.catalogue_text(), (
        "engines/drake.json is stale: .venv/bin/python -m pbdval.external.drake --catalogue > engines/drake.json")
    assert importlib.metadata.version("drake") == catalogue.DRAKE_VERSION


def test_the_catalogue_names_every_discrete_solver_and_continuous_integrator_the_engine_maps() -> None:
    names = [m["name"] for m in catalogue.catalogue()["methods"]]
    assert names == [f"drake.{n}" for n in (*catalogue.DISCRETE, *catalogue.CONTINUOUS)]
    for m in catalogue.catalogue()["methods"]:
        has_accuracy = any(p["name"] == "targetAccuracy" for p in m["parameters"])
        assert has_accuracy == (m["name"].split(".")[1] in catalogue.CONTINUOUS)


def table_support(feature: str) -> str:
    """The table's support for a feature key: its longest covering entry (features.cpp's rule)."""
    covering = [e for e in FEATURES if "methods" not in e
                and (feature == e["feature"] or feature.startswith(e["feature"] + "."))]
    return str(max(covering, key=lambda e: len(e["feature"]))["support"])


SHAPE_FEATURES = {"none": "shape.none", "sphere": "shape.sphere", "box": "shape.box", "cylinder": "shape.cylinder",
                  "torus": "shape.torus.mesh", "sdf": "shape.sdf.mesh", "hollowSphere": "shape.hollowSphere",
                  "hollowBox": "shape.hollowBox"}
JOINT_FEATURES = {"ball": "joint.ball", "ball_on_line": "joint.ballOnLine", "hinge": "joint.hinge",
                  "universal": "joint.universal", "slider": "joint.slider", "distance": "joint.distance",
                  "rigid_body_spring": "joint.rigidBodySpring", "damper": "joint.damper",
                  "target_angle_motor_hinge": "joint.targetAngleMotorHinge",
                  "target_velocity_motor_hinge": "joint.targetVelocityMotorHinge",
                  "target_position_motor_slider": "joint.targetPositionMotorSlider",
                  "target_velocity_motor_slider": "joint.targetVelocityMotorSlider"}


@pytest.mark.parametrize("kind", sorted(SHAPE_FEATURES))
def test_the_engine_refuses_a_shape_exactly_when_the_table_declares_it_unsupported(kind: str) -> None:
    shapes: dict[str, dict[str, Any]] = {
        "none": {}, "sphere": {"radius": 0.1}, "box": {"halfExtents": [0.1, 0.1, 0.1]},
        "cylinder": {"radius": 0.1, "height": 0.2, "axis": [0.0, 1.0, 0.0]},
        "torus": {"majorRadius": 0.2, "minorRadius": 0.05, "axis": [0.0, 1.0, 0.0]},
        "sdf": {"meshFile": "/m.obj", "meshScale": [1.0, 1.0, 1.0]},
        "hollowSphere": {"radius": 0.1, "wallHalfThickness": 0.01},
        "hollowBox": {"halfExtents": [0.1, 0.1, 0.1], "wallHalfThickness": 0.01}}
    document = resolved([body(0, shape={"type": kind, **shapes[kind]})])
    refused = engine.unsupported_features(pp.parse_resolved_scene(document))
    assert bool(refused) == (table_support(SHAPE_FEATURES[kind]) == "unsupported"), refused
    assert (kind in SHAPES) == (not refused)
    if refused:
        assert refused[0].startswith("RigidBodies[0]: shape " + kind)


@pytest.mark.parametrize("kind", sorted(JOINT_FEATURES))
def test_the_engine_refuses_a_joint_exactly_when_the_table_declares_it_unsupported(kind: str) -> None:
    document = resolved([body(0, dynamic=False), body(1, position=(0.0, -1.0, 0.0))],
                        [joint(kind, 0, 1, axis=[0.0, 0.0, 1.0])])
    refused = engine.unsupported_features(pp.parse_resolved_scene(document))
    assert bool(refused) == (table_support(JOINT_FEATURES[kind]) == "unsupported"), refused
    assert (kind in JOINTS) == (not refused)


def test_a_joint_that_closes_a_loop_is_refused_naming_it() -> None:
    bodies = [body(0, dynamic=False), body(1, position=(1.0, 0.0, 0.0)), body(2, position=(2.0, 0.0, 0.0))]
    joints = [joint("hinge", 0, 1, 0, axis=[0.0, 0.0, 1.0]), joint("hinge", 1, 2, 1, axis=[0.0, 0.0, 1.0]),
              joint("ball", 2, 0, 2)]
    refused = engine.unsupported_features(pp.parse_resolved_scene(resolved(bodies, joints)))
    # Breadth first from the static body: joints 0 and 2 reach bodies 1 and 2, joint 1 closes.
    assert refused == ["Joints[1]: the hinge joint closes a kinematic loop (MultibodyPlant is a tree)"]
    assert table_support("joint.closingLoop.ballOrHinge") == "unsupported"


def test_pair_friction_is_split_into_geometry_values_whose_harmonic_combination_it_is() -> None:
    ball = {"type": "sphere", "radius": 0.1}
    bodies = [body(0, dynamic=False, shape={"type": "box", "halfExtents": [1.0, 0.1, 1.0]}),
              body(1, position=(0.0, 0.5, 0.0), shape=ball), body(2, position=(0.5, 0.5, 0.0), shape=ball)]
    # 1/a + 1/b = 2/μ for the pairs (0,1): 0.5, (0,2): 0.8, (1,2): μ12 — separable exactly when
    # 2/μ12 = 2/0.5 + 2/0.8 - 2 · (1/a), a = body 0's value: one free value, any μ12 that
    # keeps every reciprocal positive is reachable; the solve must reproduce each pair.
    pairs = [{"bodies": [0, 1], "friction": 0.5, "restitution": 0.0},
             {"bodies": [0, 2], "friction": 0.8, "restitution": 0.0},
             {"bodies": [1, 2], "friction": 0.6, "restitution": 0.0}]
    scene = pp.parse_resolved_scene(resolved(bodies, pairs=pairs))
    friction = engine.geometry_friction(scene)
    assert friction is not None
    for p in scene.contact_pairs:
        a, b = friction[p.bodies[0]], friction[p.bodies[1]]
        assert 2 * a * b / (a + b) == pytest.approx(p.friction, rel=1e-12)  # round-off of one solve
    # Four bodies in a cycle of four pairs: 1/a+1/b, 1/b+1/c, 1/c+1/d, 1/d+1/a must alternate
    # to equal sums; friction 0.5, 0.5, 0.5, 0.25 cannot.
    bodies.append(body(3, position=(1.0, 0.5, 0.0), shape=ball))
    cycle = [{"bodies": [0, 1], "friction": 0.5, "restitution": 0.0},
             {"bodies": [1, 2], "friction": 0.5, "restitution": 0.0},
             {"bodies": [2, 3], "friction": 0.5, "restitution": 0.0},
             {"bodies": [3, 0], "friction": 0.25, "restitution": 0.0}]
    refused = engine.unsupported_features(pp.parse_resolved_scene(resolved(bodies, pairs=cycle)))
    assert refused and refused[-1].startswith("contact friction:")
    assert table_support("contact.nonSeparableMaterials") == "unsupported"


def test_a_bad_parameter_and_a_bad_joint_give_status_error_naming_them(tmp_path: Path, run_engine: Run) -> None:
    bad_parameter = resolved([body(0)], parameters={"penetrationAllowance": -1.0})
    status, _ = run_engine("drake", write(bad_parameter, tmp_path))
    assert status["status"] == "error" and "penetrationAllowance" in status["reason"], status
    skewed = resolved([body(0, dynamic=False), body(1, position=(0.0, -1.0, 0.0))],
                      [joint("universal", 0, 1, axis1=[1.0, 0.0, 0.0], axis2=[1.0, 1.0, 0.0])])
    status, _ = run_engine("drake", write(skewed, tmp_path))
    assert status["status"] == "error", status
    assert "Joints[0]" in status["reason"] and "not perpendicular" in status["reason"], status


def test_a_scene_that_is_not_a_resolved_scene_gives_status_error_naming_the_json_path(
        tmp_path: Path, run_engine: Run) -> None:
    document = resolved([body(0)])
    document["timeStepSize"] = -0.01
    status, out = run_engine("drake", write(document, tmp_path))
    assert status["status"] == "error" and "timeStepSize" in status["reason"], status
    assert not (out / "trajectory.npy").exists()


def test_an_unsupported_scene_is_reported_without_running(tmp_path: Path, run_engine: Run) -> None:
    document = resolved([body(0, shape={"type": "hollowSphere", "radius": 0.1, "wallHalfThickness": 0.01})])
    status, out = run_engine("drake", write(document, tmp_path))
    assert status["status"] == "unsupported" and status["unsupported"][0].startswith("RigidBodies[0]: shape")
    assert not (out / "trajectory.npy").exists()


def test_importing_the_engine_does_not_import_matplotlib() -> None:
    # pydrake.all imports matplotlib (about 1 s); the engine imports only what it uses.
    result = subprocess.run([*engine_command("drake")[:1], "-c",
                             "import sys, pbdval.external.drake.engine; print('matplotlib' in sys.modules)"],
                            capture_output=True, text=True, env=engine_environment(), check=True)
    assert result.stdout.strip() == "False"


CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))


@pytest.mark.parametrize("case", CASES)
def test_every_case_runs_or_is_refused_by_name_in_drake(export_scene: Export, run_engine: Run, case: str) -> None:
    status, out = run_engine("drake", export_scene(case, method="drake.sap", duration=0.02))
    assert status["status"] in ("ok", "unsupported"), status["reason"]
    assert (status["status"] == "ok") == (out / "trajectory.npy").exists()
