"""pybullet in reduced coordinates (methods pybullet.multibody.*,
python/pbdval/external/pybullet/multibody.py, docs/external-engines.md#pybullet-in-reduced-coordinates):
run as the runner runs it, on the library's joint cases, against closed forms and the joints'
own definitions (docs/metrics.md#joints)."""

from __future__ import annotations

import json
import math
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_engines import (
    PYBULLET,
    assert_ok,
    complete_elliptic_k,
    measured_period,
    pendulum_period,
    trajectory,
    trajectory_written,
)

from conftest import REPO
from pbdval import protocol as pp

Export = Callable[..., Path]
Run = Callable[[str, Path], tuple[dict[str, Any], Path]]
METHOD = "pybullet.multibody.si"
EPSILON = np.finfo(float).eps


def run_case(export_scene: Export, run_engine: Run, case: str, **kwargs: Any
             ) -> tuple[pp.ResolvedScene, dict[str, Any], dict[int, np.ndarray]]:
    scene_path = export_scene(case, method=kwargs.pop("method", METHOD), **kwargs)
    status, out = run_engine(PYBULLET, scene_path)
    assert_ok(status)
    return pp.read_resolved_scene(scene_path), status, trajectory(out)


def rotations(rows: np.ndarray) -> np.ndarray:
    """The rotation matrices (scene frame → world) of trajectory rows (t, x, q, v, w)."""
    w, x, y, z = rows[:, 4], rows[:, 5], rows[:, 6], rows[:, 7]
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def carried_point(body: pp.Body, world0: pp.Vec3, rows: np.ndarray) -> np.ndarray:
    """A point fixed in the body, at world0 at t = 0, at every sample (as docs/metrics.md
    carries joint anchors: p(t) = x(t) + R(t) R(0)^-1 (p - x(0)))."""
    r = rotations(rows)
    local = r[0].T @ (np.array(world0) - rows[0, 1:4])
    points: np.ndarray = rows[:, 1:4] + r @ local
    return points


def carried_axis(axis0: pp.Vec3, rows: np.ndarray) -> np.ndarray:
    r = rotations(rows)
    axes: np.ndarray = r @ (r[0].T @ np.array(axis0))
    return axes


def static_rows(body: pp.Body, like: np.ndarray) -> np.ndarray:
    """A static body's rows: its initial pose at every sample."""
    rows = np.zeros_like(like)
    rows[:, 0] = like[:, 0]
    rows[:, 1:4] = body.position
    rows[:, 4:8] = body.rotation
    return rows


def body_rows(scene: pp.ResolvedScene, rows: dict[int, np.ndarray], body_id: int | None,
              like: np.ndarray) -> np.ndarray:
    body = scene.body_by_id(body_id)  # type: ignore[arg-type]
    return rows[body.id] if body.id in rows and body.dynamic else static_rows(body, like)


# --- the physical pendulum ------------------------------------------------------------------

def test_a_physical_pendulum_swings_with_the_closed_form_period(export_scene: Export,
                                                                run_engine: Run) -> None:
    scene, _, rows = run_case(export_scene, run_engine, "joint_hinge")
    period, omega0, pivot = pendulum_period(scene)
    measured = measured_period(rows[scene.joints[0].body2], pivot)  # type: ignore[index]
    # The hinge angle is the multibody's coordinate, integrated by semi-implicit Euler, whose
    # period on the linearised pendulum is shorter by (omega0 h)^2 / 24 (from
    # 2 - 2 cos(Omega h) = (omega0 h)^2); twice that leaves room for the amplitude's
    # higher-order terms and the interpolated crossings (10 ms samples). pybullet.si's two
    # point-to-point rows are off by 4.6e-3 here, Bullet C++'s btHingeConstraint by 1.6e-4.
    bound = (omega0 * scene.time_step_size) ** 2 / 12
    assert abs(measured / period - 1) <= bound, (measured, period, bound)


# --- the joints hold by construction ---------------------------------------------------------

def joint_geometry(scene: pp.ResolvedScene, rows: dict[int, np.ndarray], joint: pp.Joint
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Rows of body 1 and body 2, and the joint's anchor carried by each."""
    some = next(iter(rows.values()))
    rows1 = body_rows(scene, rows, joint.body1, some)
    rows2 = body_rows(scene, rows, joint.body2, some)
    anchor = joint.points["anchor"].world
    b1 = scene.body_by_id(joint.body1)  # type: ignore[arg-type]
    b2 = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    return rows1, rows2, carried_point(b1, anchor, rows1), carried_point(b2, anchor, rows2)


#: The joints are the multibody's coordinates: what separates their two sides is round-off in
#: forward kinematics and in carrying the anchor through the written quaternion, a few epsilon
#: per operation on metre-sized coordinates; 1e4 epsilon (2.2e-12 m, rad) bounds it with room.
ROUND_OFF = 1e4 * EPSILON


def test_hinges_stay_closed_to_round_off(export_scene: Export, run_engine: Run) -> None:
    scene, _, rows = run_case(export_scene, run_engine, "double_pendulum")
    for joint in scene.joints:
        rows1, rows2, p1, p2 = joint_geometry(scene, rows, joint)
        assert np.max(np.linalg.norm(p1 - p2, axis=1)) <= ROUND_OFF, joint.json_path
        a1 = carried_axis(joint.axes["axis"].world, rows1)
        a2 = carried_axis(joint.axes["axis"].world, rows2)
        assert np.max(np.linalg.norm(np.cross(a1, a2), axis=1)) <= ROUND_OFF, joint.json_path


def test_a_universal_joint_keeps_its_point_and_its_axes_perpendicular(
        export_scene: Export, run_engine: Run) -> None:
    scene, status, rows = run_case(export_scene, run_engine, "joint_universal")
    joint = scene.joints[0]
    assert "massless link" in status["effectiveSettings"][f"{joint.json_path}.links"]
    rows1, rows2, p1, p2 = joint_geometry(scene, rows, joint)
    assert np.max(np.linalg.norm(p1 - p2, axis=1)) <= ROUND_OFF
    a1 = carried_axis(joint.axes["axis1"].world, rows1)
    a2 = carried_axis(joint.axes["axis2"].world, rows2)
    assert np.max(np.abs(np.sum(a1 * a2, axis=1))) <= ROUND_OFF
    # ... and it moves: the massless link's joint turns (the swing is not about axis1 alone).
    assert np.max(np.abs(a2 - a2[0])) > 0.1


def test_a_ball_on_line_keeps_its_point_on_the_line(export_scene: Export, run_engine: Run) -> None:
    scene, _, rows = run_case(export_scene, run_engine, "joint_ball_on_line")
    joint = scene.joints[0]
    rows1, _, p1, p2 = joint_geometry(scene, rows, joint)
    axis = carried_axis(joint.axes["axis"].world, rows1)
    offset = p2 - p1
    off_line = offset - axis * np.sum(offset * axis, axis=1)[:, None]
    assert np.max(np.linalg.norm(off_line, axis=1)) <= ROUND_OFF
    assert np.max(np.abs(np.sum(offset * axis, axis=1))) > 1e-3  # it slides


@pytest.mark.parametrize("case", ["joint_slider", "joint_damper"])
def test_a_slider_moves_its_body_along_the_axis_without_turning(
        export_scene: Export, run_engine: Run, case: str) -> None:
    scene, _, rows = run_case(export_scene, run_engine, case)
    joint = scene.joints[0]
    rows1, rows2, _, _ = joint_geometry(scene, rows, joint)
    axis = carried_axis(joint.axes["axis"].world, rows1)
    body2 = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    start = carried_point(scene.body_by_id(joint.body1), body2.position, rows1)  # type: ignore[arg-type]
    d = rows2[:, 1:4] - start
    across = d - axis * np.sum(d * axis, axis=1)[:, None]
    assert np.max(np.linalg.norm(across, axis=1)) <= ROUND_OFF
    relative = np.einsum("nji,njk->nik", rotations(rows1), rotations(rows2))
    assert np.max(np.abs(relative - relative[0])) <= ROUND_OFF


def test_a_target_angle_motor_holds_its_set_point_at_every_step(export_scene: Export,
                                                                run_engine: Run) -> None:
    scene, _, rows = run_case(export_scene, run_engine, "joint_target_angle_motor_hinge")
    joint = scene.joints[0]
    assert joint.target is not None
    rows1, rows2, _, _ = joint_geometry(scene, rows, joint)
    axis = np.array(joint.axes["axis"].world)
    relative = np.einsum("nji,njk->nik", rotations(rows1), rotations(rows2))
    change = relative @ relative[0].T  # body 2's turn relative to body 1 since t = 0
    sine = np.einsum("i,nij->n", axis, np.stack([
        change[:, 2, 1] - change[:, 1, 2], change[:, 0, 2] - change[:, 2, 0],
        change[:, 1, 0] - change[:, 0, 1]], -1)[:, :, None] * np.eye(3)[None]) / 2
    cosine = (np.trace(change, axis1=1, axis2=2) - 1) / 2
    angle = np.arctan2(sine, cosine)
    targets = np.array([min(max(joint.target.value_at(t), -math.pi), math.pi)
                        for t in rows2[:, 0]])
    error = np.abs(np.remainder(angle[1:] - targets[1:] + math.pi, 2 * math.pi) - math.pi)
    # The motor's velocity (target - angle) / h is one unlimited row, solved exactly by the
    # first sweep: the angle lands on its set point at the end of every step, to round-off.
    assert np.max(error) <= ROUND_OFF, np.max(error)


def test_a_distance_joint_keeps_its_length_through_a_massless_rod(export_scene: Export,
                                                                   run_engine: Run) -> None:
    scene, status, rows = run_case(export_scene, run_engine, "joint_distance")
    joint = scene.joints[0]
    assert "massless link" in status["effectiveSettings"][f"{joint.json_path}.links"]
    some = next(iter(rows.values()))
    rows1 = body_rows(scene, rows, joint.body1, some)
    rows2 = body_rows(scene, rows, joint.body2, some)
    p1 = carried_point(scene.body_by_id(joint.body1), joint.points["anchor1"].world, rows1)  # type: ignore[arg-type]
    p2 = carried_point(scene.body_by_id(joint.body2), joint.points["anchor2"].world, rows2)  # type: ignore[arg-type]
    length = np.linalg.norm(p2 - p1, axis=1)
    assert joint.rest_length is not None
    assert np.max(np.abs(length - joint.rest_length)) <= ROUND_OFF
    # ... while the body turns about its end of the rod: not a rigid pendulum.
    relative = np.einsum("nij,nkj->nik", rotations(rows2), rotations(rows2)[:1].repeat(len(rows2), 0))
    directions = (p2 - p1) / length[:, None]
    swing = np.einsum("nij,j->ni", relative, directions[0])
    assert np.max(np.linalg.norm(swing - directions, axis=1)) > 0.01


# --- initial velocities ------------------------------------------------------------------------

def test_a_jointed_initial_velocity_is_projected_keeping_the_pivot_momentum(
        export_scene: Export, run_engine: Run) -> None:
    # joint_ball starts its bob with v = (0, 0, 0.8) m/s, which the ball joint does not allow;
    # the kinetic-energy projection keeps the angular momentum about the pivot.
    scene, status, rows = run_case(export_scene, run_engine, "joint_ball", duration=0.01)
    assert status["initialVelocitiesProjected"] is True
    bob = scene.bodies[1]
    first = rows[bob.id][0]
    v, w = first[8:11], first[11:14]
    r = np.array(bob.position) - np.array(scene.joints[0].points["anchor"].world)
    rotation = np.array([pp.quat_rotate(bob.world_principal_rotation, e)
                         for e in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))]).T
    inertia = rotation @ np.diag(bob.principal_inertia) @ rotation.T

    def pivot_momentum(v: np.ndarray, w: np.ndarray) -> np.ndarray:
        momentum: np.ndarray = inertia @ w + bob.mass * np.cross(r, v)
        return momentum

    expected = pivot_momentum(np.array(bob.velocity), np.array(bob.angular_velocity))
    assert np.allclose(v, np.cross(w, r), rtol=0, atol=1e-12)  # a rotation about the pivot
    assert np.allclose(pivot_momentum(v, w), expected, rtol=1e-9, atol=1e-12)  # round-off


# --- what it cannot represent, and pybullet's limits --------------------------------------------

@pytest.mark.parametrize("case,feature", [
    ("joint_rigid_body_particle_ball", "RigidBodyParticleBallJoints[0]: joint rigid_body_particle_ball"),
    ("stiff_rod_cantilever", "CosseratJoints[0]: joint stiff_rod"),
    ("cloth_hanging", "TriangleModels[0]: the multibody family has rigid bodies only"),
])
def test_joints_it_cannot_represent_are_named_by_json_path(
        export_scene: Export, run_engine: Run, case: str, feature: str) -> None:
    status, out = run_engine(PYBULLET, export_scene(case, method=METHOD))
    assert status["status"] == "unsupported"
    assert any(u.startswith(feature) for u in status["unsupported"]), status["unsupported"]
    assert not trajectory_written(out)


def test_a_chain_beyond_pybullets_state_is_cut_at_ball_joints_into_multibodies(
        export_scene: Export, run_engine: Run) -> None:
    # 100 ball joints need 7 + 4 x 100 position coordinates; pybullet 3.2.7 transfers 128 (more
    # corrupt the state it reads: a link read at the origin, the base moving at (0, 0, 1)).
    # 7 + 4 x 30 <= 128: the fixed-base multibody takes 30 links, each cut one a free base and
    # 30 links, so 100 links need cuts after links 30, 61 and 92.
    scene, status, rows = run_case(export_scene, run_engine, "chain_100", duration=0.02)
    settings = status["effectiveSettings"]
    cuts = [k for k, v in settings.items() if k.endswith(".links") and "loop closure" in v]
    assert cuts == [f"BallJoints[{i}].links" for i in (30, 61, 92)]
    for b in scene.bodies:
        if b.dynamic:
            assert np.allclose(rows[b.id][0, 1:4], b.position, rtol=0, atol=1e-12), b.json_path


def four_bar(folder: Path) -> Path:
    """A parallelogram four-bar: two 0.5 m cranks hinged 1 m apart on a static body, a 1 m
    coupler hinged to both; released 30 degrees off vertical. Its four hinges form a loop."""
    s, c = math.sin(math.radians(30)), math.cos(math.radians(30))
    a, d = [0.0, 2.0, 0.0], [1.0, 2.0, 0.0]
    b, e = [0.5 * s, 2 - 0.5 * c, 0.0], [1 + 0.5 * s, 2 - 0.5 * c, 0.0]

    def box(i: int, at: list[float], scale: list[float], angle: float = 0.0) -> dict[str, Any]:
        body: dict[str, Any] = {"id": i, "geometryFile": str(REPO / "cases/models/cube.obj"),
                                "translation": at, "scale": scale, "collisionObjectType": 0,
                                "isDynamic": i != 0}
        if i != 0:
            body["density"] = 1000
        if angle:
            body.update(rotationAxis=[0, 0, 1], rotationAngle=angle)
        return body

    crank = math.radians(30)
    document = {
        "Name": "four_bar",
        "Simulation": {"timeStepSize": 0.005, "gravitation": [0, -9.81, 0]},
        "RigidBodies": [
            box(0, [0.5, 2.0, 0.0], [0.1, 0.1, 0.1]),
            box(1, [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, 0.0], [0.05, 0.5, 0.05], crank),
            box(2, [(b[0] + e[0]) / 2, b[1], 0.0], [1.0, 0.05, 0.05]),
            box(3, [(d[0] + e[0]) / 2, (d[1] + e[1]) / 2, 0.0], [0.05, 0.5, 0.05], crank)],
        "HingeJoints": [{"bodyID1": i, "bodyID2": j, "position": p, "axis": [0, 0, 1]}
                        for i, j, p in ((0, 1, a), (1, 2, b), (2, 3, e), (0, 3, d))],
        "Validation": {"schema": 1, "duration": 3.0, "sampleInterval": 0.01},
    }
    path = folder / "four_bar.json"
    path.write_text(json.dumps(document))
    return path


def test_a_four_bar_loop_closed_by_a_hinge_swings_with_the_parallelogram_period(
        pbdval_binary: Path, run_engine: Run, tmp_path: Path) -> None:
    exported = subprocess.run([str(pbdval_binary), "export-scene", str(four_bar(tmp_path)),
                               "--quiet"], capture_output=True, text=True, check=True)
    document = json.loads(exported.stdout)
    document["method"] = {"name": METHOD, "parameters": {}}
    scene_path = tmp_path / "resolved.json"
    scene_path.write_text(json.dumps(document))
    scene = pp.read_resolved_scene(scene_path)
    status, out = run_engine(PYBULLET, scene_path)
    assert_ok(status)
    rows = trajectory(out)
    loop = scene.joints[3]  # the last hinge finds its bodies already connected
    assert "loop closure" in status["effectiveSettings"][f"{loop.json_path}.links"]
    for joint in scene.joints[:3]:
        _, _, p1, p2 = joint_geometry(scene, rows, joint)
        assert np.max(np.linalg.norm(p1 - p2, axis=1)) <= ROUND_OFF, joint.json_path
    # The loop's two point-to-point rows are solved by the 10 sweeps: the parity suite's bound,
    # 10 h^2 a_max (as test_engines holds pybullet.si's hinges; a_max from the samples).
    dt, h = scene.sample_interval, scene.time_step_size
    acceleration = max(
        float(np.max(np.linalg.norm(x[2:] - 2 * x[1:-1] + x[:-2], axis=1))) / dt**2
        for x in (rows[b.id][:, 1:4] for b in scene.bodies if b.dynamic))
    _, _, p1, p2 = joint_geometry(scene, rows, loop)
    assert np.max(np.linalg.norm(p1 - p2, axis=1)) <= 10 * h * h * acceleration
    # The coupler translates on a circle of the crank's length L: one coordinate theta with
    # inertia I = sum over cranks of (I_z + m r^2) + m_coupler L^2 and gravity moment
    # g (sum of m r + m_coupler L) sin(theta): a physical pendulum.
    pivots = [np.array(scene.joints[k].points["anchor"].world) for k in (0, 3)]
    length = float(np.linalg.norm(np.array(scene.joints[1].points["anchor"].world) - pivots[0]))
    inertia = moment = 0.0
    for crank, pivot, joint in zip((scene.bodies[1], scene.bodies[3]), pivots,
                                   (scene.joints[0], scene.joints[3])):
        axis = np.array(joint.axes["axis"].body2.principal)  # type: ignore[union-attr]
        r = float(np.linalg.norm(np.array(crank.position) - pivot))
        inertia += float(np.sum(np.array(crank.principal_inertia) * axis**2)) + crank.mass * r * r
        moment += crank.mass * r
    coupler = scene.bodies[2]
    inertia += coupler.mass * length**2
    moment += coupler.mass * length
    omega0 = math.sqrt(float(np.linalg.norm(scene.gravity)) * moment / inertia)
    period = 4 * complete_elliptic_k(math.sin(math.radians(30) / 2)) / omega0
    measured = measured_period(rows[1], pivots[0])
    # As the single pendulum's: twice semi-implicit Euler's (omega0 h)^2 / 24.
    assert abs(measured / period - 1) <= (omega0 * h) ** 2 / 12, (measured, period)


CASES = sorted(p.stem for p in (REPO / "cases").glob("*.json"))


@pytest.mark.parametrize("case", CASES)
def test_every_case_runs_or_is_unsupported_in_reduced_coordinates(
        export_scene: Export, run_engine: Run, case: str) -> None:
    status, out = run_engine(PYBULLET, export_scene(case, method=METHOD, duration=0.02))
    assert status["status"] in ("ok", "unsupported"), status["reason"]
    assert (status["status"] == "ok") == trajectory_written(out)


# --- the state reads ------------------------------------------------------------------------

@pytest.mark.parametrize(("case", "method"), [("chain_10", METHOD), ("double_pendulum_boxes", METHOD),
                                              ("contact_stack_5", METHOD),
                                              ("contact_stack_5", "pybullet.si"),
                                              ("double_pendulum_boxes", "pybullet.si")])
def test_the_state_reads_are_pybullets_per_body_calls_bit_for_bit(export_scene: Export, case: str,
                                                                  method: str) -> None:
    # `states` reads every multibody's links in one getLinkStates call and fills one array
    # made when the run starts (docs/benchmarks.md#sixth-pass): each row must be what
    # pybullet's per-body calls give, bit for bit (getLinkState per link, with the same
    # velocity and forward-kinematics flags; getBasePositionAndOrientation and getBaseVelocity
    # for a base or a maximal-coordinate body), read in the same moving world.
    import pybullet as pb

    from pbdval.external.pybullet import engine, multibody

    scene = pp.read_resolved_scene(export_scene(case, method=method))
    run = (multibody.MultibodyRun(scene) if method.startswith(engine.MULTIBODY_PREFIX)
           else engine.PybulletRun(scene))
    try:
        handles = getattr(run, "handles", [multibody._Link(body, -1) for body in run.ids])
        # Links (getLinkStates) exactly where joints make trees in reduced coordinates.
        assert any(h.link >= 0 for h in handles) == (
            method.startswith(engine.MULTIBODY_PREFIX) and bool(scene.joints))
        for _ in range(3):
            for _ in range(17):  # a moving world: bodies and links away from their start
                pb.stepSimulation(physicsClientId=run.client)
            read = run.states(0.0).copy()
            for b in scene.bodies:
                h = handles[b.index]
                if h.link < 0:
                    expected = (pb.getBasePositionAndOrientation(h.body, physicsClientId=run.client)
                                + pb.getBaseVelocity(h.body, physicsClientId=run.client))
                else:
                    s = pb.getLinkState(h.body, h.link, computeLinkVelocity=1,
                                        computeForwardKinematics=1, physicsClientId=run.client)
                    expected = (s[0], s[1], s[6], s[7])
                values = [v for part in expected for v in part]
                assert read[b.index].tolist() == values, b.json_path
    finally:
        pb.disconnect(physicsClientId=run.client)
