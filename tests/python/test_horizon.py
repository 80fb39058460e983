"""pbdval.horizon: the twin run that measures how a chaotic case amplifies a perturbation, and
the short-horizon copy of a case that the converged-reference sweeps use
(docs/convergence.md#orders-against-the-converged-reference)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pytest

from conftest import REPO
from pbdval.horizon import Growth, short_horizon_scene, turned_scene, twin_growth


def double_pendulum() -> dict[str, Any]:
    scene: dict[str, Any] = json.loads((REPO / "cases" / "double_pendulum.json").read_text())
    return scene


def test_turning_the_whole_pendulum_rotates_every_body_and_joint_rigidly_about_the_pivot() -> None:
    scene = double_pendulum()
    angle = 0.3
    turned = turned_scene(scene, angle)
    pivot = scene["HingeJoints"][0]["position"]
    for before, after in zip(scene["RigidBodies"], turned["RigidBodies"], strict=True):
        if not before.get("isDynamic", True):
            assert after == before  # the static anchor body stays
            continue
        dx, dy = before["translation"][0] - pivot[0], before["translation"][1] - pivot[1]
        # R(θ) (x − p) + p, the closed form of a rotation about z; round-off only (1e-15 m).
        expected = [pivot[0] + math.cos(angle) * dx - math.sin(angle) * dy,
                    pivot[1] + math.sin(angle) * dx + math.cos(angle) * dy]
        assert after["translation"][:2] == pytest.approx(expected, abs=1e-15)
        assert (after["rotationAxis"], after["rotationAngle"]) == ([0.0, 0.0, 1.0], angle)
    # The joints stay where the bodies put them: the second hinge turns with the bodies.
    second = turned["HingeJoints"][1]["position"]
    assert math.dist(second, pivot) == pytest.approx(0.5, abs=1e-15)
    assert math.atan2(second[1] - pivot[1], second[0] - pivot[0]) == pytest.approx(angle, abs=1e-15)


def test_turning_beyond_the_second_joint_leaves_the_first_link_where_it_was() -> None:
    scene = double_pendulum()
    turned = turned_scene(scene, 0.2, joint=1)
    bodies = {b["id"]: b for b in turned["RigidBodies"]}
    original = {b["id"]: b for b in scene["RigidBodies"]}
    assert bodies[1] == original[1]
    assert bodies[2]["rotationAngle"] == 0.2
    # the outer link's centre, 0.25 m beyond the second hinge, turned about that hinge
    hinge = scene["HingeJoints"][1]["position"]
    assert math.dist(bodies[2]["translation"], hinge) == pytest.approx(0.25, abs=1e-15)


def test_a_turned_body_with_a_rotation_of_its_own_is_refused() -> None:
    scene = double_pendulum()
    scene["RigidBodies"][1]["rotationAxis"] = [1, 0, 0]
    scene["RigidBodies"][1]["rotationAngle"] = 0.1
    with pytest.raises(ValueError, match="body 1 has a rotation"):
        turned_scene(scene, 0.1)


def test_the_short_horizon_copy_changes_the_duration_alone() -> None:
    scene = double_pendulum()
    short = short_horizon_scene(scene, 1.0)
    assert short["Validation"]["duration"] == 1.0
    short["Validation"]["duration"] = scene["Validation"]["duration"]
    assert short == scene
    with pytest.raises(ValueError, match="duration"):
        short_horizon_scene(scene, 0.0)


def test_the_finite_time_exponent_of_an_exponential_growth_is_its_rate() -> None:
    times = [0.01 * k for k in range(301)]
    growth = Growth(times, [math.exp(1.7 * t) for t in times])
    assert growth.exponent(0.5, 3.0) == pytest.approx(1.7, rel=1e-12)  # a straight line in log G
    assert growth.first_time_above(10.0) == pytest.approx(math.log(10) / 1.7, abs=0.01)  # sampled every 0.01 s
    assert growth.first_time_above(1e6) == math.inf


def test_the_twin_runs_start_one_perturbation_apart(pbdval_binary: Path) -> None:
    """G(0) = 1: the outer link's centre is moved by the chord 2 r sin(δ/2) = δ r (1 − δ²/24),
    and the twin run reads the perturbed scene, not the original."""
    growth = twin_growth(str(pbdval_binary), REPO / "cases" / "double_pendulum.json", 1e-7, 0.2,
                         ["--engine", "mujoco", "--method", "mujoco.rk4", "--set", "timeStepSize=0.001",
                          "--sample-interval", "0.01"])
    # δ²/24 ~ 4e-16, and double round-off of 2 m coordinates over the separation δ r = 7.5e-8 m
    # is 6e-9 relative: 1e-6 is far above both.
    assert growth.growth[0] == pytest.approx(1.0, abs=1e-6)
    # Over 0.2 s of a release from rest the perturbation neither vanishes nor explodes (the
    # measured G stays within 0.95–1 for the first 0.2 s; the bound only says it was simulated).
    assert 0.1 < growth.growth[-1] < 10
