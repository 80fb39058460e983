"""The engines' array path through the protocol (python/pbdval/protocol.py): state arrays
instead of BodyStates, the row-wise quaternion product, the preallocated trajectory. Each is
checked against the per-body path it replaces, to the bit: the engines' trajectories must not
change when they take it (docs/benchmarks.md#persistent-engines)."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
from test_protocol import minimal_document

from pbdval import protocol as pp


def awkward_quaternions(count: int, seed: int) -> np.ndarray:
    """Random quaternions of mixed scales, then rows with signed zeros and exact ones: where a
    product order or a subtraction written as an addition could change a bit."""
    rng = np.random.default_rng(seed)
    random_rows = rng.normal(size=(count, 4)) * 10.0 ** rng.integers(-8, 8, size=(count, 1))
    special = np.array([[1.0, 0.0, 0.0, 0.0], [-0.0, 0.0, -0.0, 1.0], [0.0, -1.0, 0.0, -0.0],
                        [0.5, -0.5, 0.5, -0.5], [-1.0, -0.0, -0.0, -0.0]])
    return np.vstack([random_rows, special])


def test_the_row_wise_quaternion_product_is_quat_multiply_to_the_bit() -> None:
    a = awkward_quaternions(500, seed=1)
    b = awkward_quaternions(500, seed=2)[::-1].copy()
    expected = np.array([pp.quat_multiply(x, y) for x, y in zip(a, b)])
    got = pp.quat_multiply_rows(a, pp.quat_right_factors(b))
    assert got.tobytes() == expected.tobytes()  # signed zeros included


def test_state_array_rows_are_state_rows_to_the_bit() -> None:
    rng = np.random.default_rng(3)
    quaternions = awkward_quaternions(6, seed=4)  # 11 rows, some with w < 0 or w = -0
    states = np.hstack([rng.normal(size=(len(quaternions), 3)), quaternions,
                        rng.normal(size=(len(quaternions), 6))])
    ids = [4, 9, 2, 7, 1, 3, 5, 6, 8, 10, 11]
    bodies = [pp.BodyState(i, s[0:3], s[3:7], s[7:10], s[10:13]) for i, s in zip(ids, states)]
    expected = pp.state_rows(0.1 + 0.2, bodies)
    got = pp.state_array_rows(0.1 + 0.2, np.array(ids, dtype=np.float64), states)
    assert got.tobytes() == expected.tobytes()
    assert (got[:, 5] >= 0).all()  # flipped to w >= 0 as state_rows flips


def test_a_state_array_of_the_wrong_shape_is_refused_naming_both_shapes() -> None:
    with pytest.raises(ValueError, match=r"shape \(2, 13\), got \(2, 12\)"):
        pp.state_array_rows(0.0, np.array([1.0, 2.0]), np.zeros((2, 12)))


def test_pybullets_principal_frames_become_scene_frames_as_per_body() -> None:
    rng = np.random.default_rng(5)
    principal = awkward_quaternions(3, seed=6)
    principal /= np.linalg.norm(principal, axis=1, keepdims=True)
    count = len(principal)
    read = np.hstack([rng.normal(size=(count, 3)), awkward_quaternions(3, seed=7)[:, [1, 2, 3, 0]],
                      rng.normal(size=(count, 6))])  # x, (qx qy qz qw), v, w: pybullet's order
    factors = pp.quat_right_factors(pp.quat_conjugates(principal))
    got = pp.principal_to_scene_states(read, factors)
    for row, r, p in zip(got, read, principal):
        q_read = (r[6], r[3], r[4], r[5])
        expected = [*r[0:3], *pp.quat_multiply(q_read, pp.quat_conjugate(p)), *r[7:13]]
        assert row.tobytes() == np.array(expected).tobytes()


def two_body_scene(steps: int = 10) -> pp.ResolvedScene:
    document = minimal_document()
    document["steps"] = steps
    second = copy.deepcopy(document["bodies"][0])
    second.update({"id": 9, "index": 1, "jsonPath": "RigidBodies[1]"})
    document["bodies"].append(second)
    return pp.parse_resolved_scene(document)


def toy_state(t: float, blow_up_at: float | None = None) -> np.ndarray:
    """Two bodies' states at t (state array columns), one quaternion with w < 0; from
    `blow_up_at` on the second body is past the divergence limit."""
    q = (-math.cos(t), 0.0, math.sin(t), 0.0)
    states = np.array([[t, 1.0 - t * t, 0.0, *q, 1.0, -2.0 * t, 0.0, 0.0, 0.3, 0.0],
                       [0.0, t / 3.0, -t, 1.0, 0.0, 0.0, 0.0, 0.0, 0.1 * t, 0.0, 0.0, 0.0, 1.0]])
    if blow_up_at is not None and t >= blow_up_at:
        states[1, 7] = 2.0 * pp.DIVERGENCE_LIMIT
    return states


def as_body_states(scene: pp.ResolvedScene, states: np.ndarray) -> list[pp.BodyState]:
    return [pp.BodyState(b.id, tuple(s[0:3]), tuple(s[3:7]), tuple(s[7:10]), tuple(s[10:13]))
            for b, s in zip(scene.bodies, states)]


@pytest.mark.parametrize("blow_up_at", [None, 0.05])
def test_simulate_writes_the_same_file_and_status_from_state_arrays_as_from_body_states(
        tmp_path: Path, blow_up_at: float | None) -> None:
    scene = two_body_scene()
    outcomes = {}
    for form in ("arrays", "bodies"):
        out = tmp_path / form
        out.mkdir()

        def states(t: float, form: str = form) -> list[pp.BodyState] | np.ndarray:
            array = toy_state(t, blow_up_at)
            return array if form == "arrays" else as_body_states(scene, array)

        status = pp.simulate(scene, out, lambda: None, states)
        outcomes[form] = (status, (out / pp.TRAJECTORY_NPY_FILE).read_bytes())
    assert outcomes["arrays"] == outcomes["bodies"]
    status, _ = outcomes["arrays"]
    if blow_up_at is None:
        assert status.status == "ok"
    else:  # found at the first sample from 0.05 s on: samples every 3 steps of h, step 6
        assert status.status == "diverged" and status.diverged_at == 6 * scene.time_step_size
        assert "body 9 blew up" in status.reason


def test_the_preallocated_trajectory_keeps_every_row_in_order_past_its_capacity(
        tmp_path: Path) -> None:
    samples = [np.full((2, 15), float(k)) for k in range(5)]
    for capacity in (0, 4, 10, 20):  # none, less than the rows, exactly, more
        out = tmp_path / str(capacity)
        out.mkdir()
        with pp.TrajectoryWriter(out, capacity=capacity) as writer:
            for rows in samples:
                writer.write_rows(rows)
        written = np.load(out / pp.TRAJECTORY_NPY_FILE)
        assert written.tobytes() == np.vstack(samples).tobytes(), capacity


@pytest.mark.parametrize("blow_up", [None, "speed", "nan-quaternion"])
def test_a_frame_change_made_once_after_the_run_writes_what_one_made_per_sample_writes(
        tmp_path: Path, blow_up: str | None) -> None:
    """pybullet's path: `states` gives the principal frames (pybullet's quaternion order) and
    `finish_states` turns the whole trajectory into scene frames when the run ends; the file and
    the status (divergence found on the states as read: same time, same reason) are those of
    the per-sample frame change."""
    scene = two_body_scene(steps=12)
    principal = awkward_quaternions(2, seed=8)[-2:]  # two unit quaternions, one with w < 0
    factors = pp.quat_right_factors(pp.quat_conjugates(principal))

    def read(t: float) -> np.ndarray:
        states = toy_state(t)
        raw = states.copy()
        raw[:, 3:7] = states[:, [4, 5, 6, 3]]  # x y z w: pybullet's order
        if blow_up == "speed" and t >= 0.05:
            raw[1, 8] = 3.0 * pp.DIVERGENCE_LIMIT
        if blow_up == "nan-quaternion" and t >= 0.05:
            raw[0, 4] = math.nan
        return raw

    outcomes = {}
    for form in ("per-sample", "after-the-run"):
        out = tmp_path / form
        out.mkdir()
        if form == "per-sample":
            status = pp.simulate(scene, out, lambda: None,
                                 lambda t: pp.principal_to_scene_states(read(t), factors))
        else:
            status = pp.simulate(scene, out, lambda: None, read,
                                 finish_states=lambda s: pp.principal_to_scene_states(s, factors))
        outcomes[form] = (status, (out / pp.TRAJECTORY_NPY_FILE).read_bytes())
    assert outcomes["per-sample"] == outcomes["after-the-run"]
    status, _ = outcomes["after-the-run"]
    expected_reason = {None: None, "speed": "body 9 blew up", "nan-quaternion": "non-finite state of body 4"}[blow_up]
    if expected_reason is None:
        assert status.status == "ok"
    else:  # the first sample from 0.05 s on: samples every 3 steps of h, step 6
        assert status.status == "diverged" and status.diverged_at == 6 * scene.time_step_size
        assert expected_reason in status.reason


def test_finish_states_with_body_states_is_refused(tmp_path: Path) -> None:
    scene = two_body_scene()
    with pytest.raises(TypeError, match="finish_states"):
        pp.simulate(scene, tmp_path, lambda: None, lambda t: as_body_states(scene, toy_state(t)),
                    finish_states=lambda s: s)
