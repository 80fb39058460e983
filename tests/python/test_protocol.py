"""The protocol helpers (python/pbdval/protocol.py) and the engines' pure-Python parts."""

from __future__ import annotations

import json
import math
import os
import random
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pbdval import protocol as pp
from pbdval.external.mujoco import contact_law
from pbdval.external.pybullet import materials


def minimal_document() -> dict[str, Any]:
    return {
        "format": "pbdval.resolved-scene", "version": 1, "source": "/x/s.json", "name": "s",
        "method": {"name": "m", "parameters": {"iterations": 7, "flag": True, "cone": "elliptic"}},
        "gravity": [0, -9.81, 0], "timeStepSize": 0.01, "duration": 0.1, "sampleInterval": 0.03,
        "steps": 10, "sampleStride": 3, "contactTolerance": 0.01, "contactCombineRule": "seed",
        "bodies": [{
            "id": 4, "index": 0, "jsonPath": "RigidBodies[0]", "dynamic": True, "mass": 2.0,
            "principalInertia": [1, 2, 3],
            "principalFrame": {"centerOfMass": [0, 0, 0], "rotation": [1, 0, 0, 0]},
            "pose": {"position": [0, 1, 0], "rotation": [1, 0, 0, 0], "sceneOrigin": [0, 1, 0],
                     "principalRotation": [1, 0, 0, 0]},
            "velocity": [0, 0, 0], "angularVelocity": [0, 0, 0],
            "shape": {"type": "sphere", "collisionObjectType": 1, "inverted": False, "radius": 0.5},
            "material": {"friction": 0.2, "restitution": 0.6}}],
        "joints": [], "contactPairs": [], "particles": [],
        "deformables": {"triangleModels": 0, "tetModels": 0},
    }


def test_format_number_round_trips_every_double() -> None:
    rng = random.Random(1)
    values = [rng.uniform(-1e3, 1e3) for _ in range(2000)] + [
        rng.lognormvariate(0, 30) for _ in range(2000)] + [0.1, 1e-300, 5e-324, 1e300, -0.0]
    for v in values:
        assert float(pp.format_number(v)) == v
    assert pp.format_number(2.0) == "2"  # as std::to_chars writes an integral double
    assert pp.format_time(0.1 + 0.2) == "0.3"  # 12 significant digits


def test_sample_steps_follow_the_stride_and_include_the_last_step() -> None:
    scene = pp.parse_resolved_scene(minimal_document())
    assert scene.sample_steps() == [0, 3, 6, 9, 10]
    assert scene.parameter("iterations", 1) == 7
    assert scene.parameter("missing", 5) == 5


def test_sample_steps_are_every_stride_th_step_and_the_last_for_any_stride() -> None:
    # The definition, one step at a time (validation/run/simulation.cpp), against the list made
    # from a range: the same steps for strides that divide the run and strides that do not.
    for steps in (1, 2, 9, 10, 16000):  # the reader takes steps >= 1
        for stride in (1, 2, 3, 7, 16, 10, 20000):
            doc = minimal_document()
            doc["steps"], doc["sampleStride"] = steps, stride
            scene = pp.parse_resolved_scene(doc)
            assert scene.sample_steps() == [n for n in range(steps + 1)
                                            if n == 0 or n % stride == 0 or n == steps]


def test_the_serve_command_line_reads_as_its_parser_reads_it() -> None:
    # The runner's own forms (either option first) read without the parser; anything else goes
    # to argparse, which rejects what is wrong with exit status 2.
    read = pp._serve_arguments
    assert read(["--socket", "/s"], "t") == ("/s", 1)
    assert read(["--socket", "/s", "--runs-per-child", "50"], "t") == ("/s", 50)
    assert read(["--runs-per-child", "7", "--socket", "/s"], "t") == ("/s", 7)
    assert read(["--socket", "/a", "--socket", "/b"], "t") == ("/b", 1)  # argparse: the last
    for bad in (["--socket"], [], ["--socket", "/s", "--runs-per-child", "0"],
                ["--socket", "/s", "--runs-per-child", "x"], ["--socket", "/s", "--other", "1"]):
        with pytest.raises(SystemExit) as stopped:
            read(bad, "t")
        assert stopped.value.code == 2, bad


def test_temporary_files_beside_a_target_are_new_private_and_distinct(tmp_path: Path) -> None:
    target = tmp_path / "status.json"
    made = [pp._new_file_beside(target) for _ in range(3)]
    try:
        paths = [path for _, path in made]
        assert len(set(paths)) == 3
        for path in paths:
            assert path.parent == tmp_path and path.name.startswith("status.json.")
            assert path.stat().st_size == 0
            assert path.stat().st_mode & 0o777 == 0o600
    finally:
        for fd, _ in made:
            os.close(fd)
    assert not target.exists()


def test_an_engine_server_imports_no_argparse_tempfile_traceback_or_subprocess() -> None:
    # What pbdval's side adds to an engine server's start (docs/benchmarks.md, seventh pass):
    # these are imported only where a run needs them (a bad command line, a failure).
    code = ("import sys, pbdval.protocol, pbdval.external.pybullet.engine, "
            "pbdval.external.pybullet.multibody; "
            "print(sorted(m for m in ('argparse', 'tempfile', 'traceback', 'subprocess') "
            "if m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            env={**os.environ, "PYTHONPATH": str(Path(pp.__file__).parents[1])})
    assert result.stdout.strip() == "[]", result.stderr


def test_parse_errors_name_the_file_and_the_json_path() -> None:
    doc = minimal_document()
    doc["timeStepSize"] = "fast"
    with pytest.raises(pp.SceneError, match=r"^scene\.json: timeStepSize: expected a finite number"):
        pp.parse_resolved_scene(doc, "scene.json")
    doc = minimal_document()
    doc["bodies"][0]["pose"]["rotation"] = [1, 0, 0]
    with pytest.raises(pp.SceneError, match=r"bodies\[0\]\.pose\.rotation: expected an array of 4"):
        pp.parse_resolved_scene(doc, "scene.json")
    doc = minimal_document()
    doc["format"] = "something else"
    with pytest.raises(pp.SceneError, match=r"format: expected \"pbdval.resolved-scene\""):
        pp.parse_resolved_scene(doc, "scene.json")
    doc = minimal_document()
    doc["method"]["parameters"]["bad"] = [1, 2]
    with pytest.raises(pp.SceneError, match=r"method\.parameters\.bad: expected a number"):
        pp.parse_resolved_scene(doc, "scene.json")


def test_read_resolved_scene_reports_unreadable_and_malformed_files(tmp_path: Path) -> None:
    with pytest.raises(pp.SceneError, match="cannot read"):
        pp.read_resolved_scene(tmp_path / "absent.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{\n  nope")
    with pytest.raises(pp.SceneError, match=r"bad\.json: line 2: not JSON"):
        pp.read_resolved_scene(bad)


def test_trajectory_writer_writes_the_simulate_csv(tmp_path: Path) -> None:
    with pp.TrajectoryWriter(tmp_path, binary=False) as writer:
        writer.write(0.0, [pp.BodyState(3, (1.0, 2.5, -0.0), (-1.0, 0.0, 0.0, 0.0), (0, 0, 0), (0, 0, 0))])
        writer.write(0.1 + 0.2, [pp.BodyState(3, (0.1, 2.0, 3.0), (0.5, -0.5, 0.5, -0.5), (1, 2, 3), (4, 5, 6))])
    lines = (tmp_path / "trajectory.csv").read_text().splitlines()
    assert lines[0] == "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"
    # w < 0 is flipped to the equivalent quaternion with w >= 0 (q and -q are one rotation).
    assert lines[1] == "0,3,1,2.5,-0,1,-0,-0,-0,0,0,0,0,0,0"
    assert lines[2] == "0.3,3,0.1,2,3,0.5,-0.5,0.5,-0.5,1,2,3,4,5,6"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["trajectory.csv"]  # no temporary left


def test_trajectory_writer_writes_the_same_rows_as_npy(tmp_path: Path) -> None:
    bodies0 = [pp.BodyState(3, (1.0, 2.5, -0.0), (-1.0, 0.0, 0.0, 0.0), (0, 0, 0), (0, 0, 0)),
               pp.BodyState(7, (0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0), (0, 0, -1), (0, 0, 0))]
    with pp.TrajectoryWriter(tmp_path) as writer:
        writer.write(0.0, bodies0)
        writer.write(0.1 + 0.2, [pp.BodyState(3, (0.1, 2.0, 3.0), (0.5, -0.5, 0.5, -0.5), (1, 2, 3), (4, 5, 6)),
                                 bodies0[1]])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["trajectory.npy"]  # no temporary left
    rows = np.load(tmp_path / "trajectory.npy")
    assert rows.dtype == np.dtype("<f8") and rows.shape == (4, 15)
    np.testing.assert_array_equal(rows[0], [0, 3, 1, 2.5, -0.0, 1, -0.0, -0.0, -0.0, 0, 0, 0, 0, 0, 0])
    assert rows[2, 0] == 0.1 + 0.2  # the time exactly, not rounded to 0.3
    np.testing.assert_array_equal(rows[:, 1], [3, 7, 3, 7])


def test_divergence_is_found_in_the_rows() -> None:
    fine = pp.BodyState(1, (0, 0, 0), (1, 0, 0, 0), (0, 0, 0), (0, 0, 0))
    assert pp.divergence_reason(0.5, [fine]) is None
    nan = pp.BodyState(2, (0, float("nan"), 0), (1, 0, 0, 0), (0, 0, 0), (0, 0, 0))
    assert pp.divergence_reason(0.5, [fine, nan]) == "non-finite state of body 2 at t = 0.5 s"
    fast = pp.BodyState(4, (0, 0, 0), (1, 0, 0, 0), (0, 2e6, 0), (0, 0, 0))
    reason = pp.divergence_reason(0.5, [fine, fast])
    assert reason is not None and reason.startswith("body 4 blew up at t = 0.5 s")


def test_status_json_has_exactly_the_protocol_fields(tmp_path: Path) -> None:
    pp.write_status(tmp_path, pp.Status("diverged", reason="r", diverged_at=0.25, engine_version="e 1",
                                        effective_settings={"a": 1}, integrator_steps_per_scene_step=4,
                                        contact_margin=0.001, initial_velocities_projected=True))
    status = json.loads((tmp_path / "status.json").read_text())
    assert status == {"protocol": 1, "status": "diverged", "reason": "r", "unsupported": [],
                      "divergedAt": 0.25, "engineVersion": "e 1", "effectiveSettings": {"a": 1},
                      "integratorStepsPerSceneStep": 4, "contactMargin": 0.001,
                      "initialVelocitiesProjected": True}
    with pytest.raises(ValueError, match="status"):
        pp.Status("fine").to_json()


def test_status_is_never_written_over_a_directory(tmp_path: Path) -> None:
    (tmp_path / "status.json").mkdir()
    with pytest.raises(OSError, match="not a regular file"):
        pp.write_status(tmp_path, pp.Status("ok"))


def test_argument_parser_requires_an_existing_out_directory(tmp_path: Path) -> None:
    args = pp.parse_arguments(["--scene", "s.json", "--out", str(tmp_path)], "d")
    assert args.out == tmp_path and args.scene == Path("s.json")
    with pytest.raises(SystemExit) as e:
        pp.parse_arguments(["--scene", "s.json", "--out", str(tmp_path / "none")], "d")
    assert e.value.code == 2


def test_motor_target_interpolates_holds_and_repeats() -> None:
    t = pp.MotorTarget(constant=0, times=(1.0, 2.0, 3.0), values=(0.0, 10.0, 0.0), repeat=True)
    assert t.value_at(0.5) == 0.0  # held before the first sample
    assert t.value_at(1.5) == pytest.approx(5.0, abs=1e-12)
    assert t.value_at(2.0) == pytest.approx(10.0, abs=1e-12)
    assert t.value_at(4.5) == pytest.approx(5.0, abs=1e-12)  # period t_last - t_first = 2
    assert pp.MotorTarget(constant=3, times=(), values=(), repeat=False).value_at(7) == 3


def test_quaternion_helpers_rotate_like_a_matrix() -> None:
    half = math.pi / 4  # 90 degrees about z
    q = (math.cos(half), 0.0, 0.0, math.sin(half))
    assert pp.quat_rotate(q, (1.0, 0.0, 0.0)) == pytest.approx((0.0, 1.0, 0.0), abs=1e-15)
    qq = pp.quat_multiply(q, q)  # 180 degrees
    assert pp.quat_rotate(qq, (1.0, 0.0, 0.0)) == pytest.approx((-1.0, 0.0, 0.0), abs=1e-15)


def test_divergence_uses_the_runner_limits() -> None:
    ok = pp.BodyState(0, (1e5, 0, 0), (1, 0, 0, 0), (0, 0, 0), (0, 0, 0))
    far = pp.BodyState(1, (2e6, 0, 0), (1, 0, 0, 0), (0, 0, 0), (0, 0, 0))
    nan = pp.BodyState(2, (0, 0, 0), (1, 0, 0, 0), (math.nan, 0, 0), (0, 0, 0))
    assert pp.divergence_reason(1.0, [ok]) is None
    assert "body 1 blew up" in (pp.divergence_reason(1.0, [ok, far]) or "")
    assert "non-finite state of body 2" in (pp.divergence_reason(1.0, [nan]) or "")


def test_divergence_is_decided_by_the_norms_not_by_the_components() -> None:
    # Components past the cheap look's half limit are judged by |x| and |v| exactly: 6e5 on
    # each axis is |x| = 1.04e6 (over), 5.7e5 is 0.987e6 (within); 0.9e6 on one axis is within,
    # (0, 8e5, -8e5) is |v| = 1.13e6 (over).
    def body(position: tuple[float, float, float], velocity: tuple[float, float, float]) -> pp.BodyState:
        return pp.BodyState(0, position, (1, 0, 0, 0), velocity, (0, 0, 0))
    assert "blew up" in (pp.divergence_reason(0.0, [body((6e5, 6e5, 6e5), (0, 0, 0))]) or "")
    assert pp.divergence_reason(0.0, [body((5.7e5, 5.7e5, 5.7e5), (0, 0, 0))]) is None
    assert pp.divergence_reason(0.0, [body((0, 0, 0), (9e5, 0, 0))]) is None
    assert "blew up" in (pp.divergence_reason(0.0, [body((0, 0, 0), (0, 8e5, -8e5))]) or "")
    assert "non-finite" in (pp.divergence_reason(0.0, [body((math.inf, 0, 0), (0, 0, 0))]) or "")


def test_divergence_cheap_look_at_the_sum_of_squares_never_decides_a_divergence() -> None:
    # The first look sums the squares of every value; a sum past (limit/2)^2 only sends the
    # state to the exact test. 1000 bodies at |x| = 3e5 m (each within the limit, the sum of
    # squares 9e13 past 2.5e11) are fine; one at 1e200 m, whose square overflows, blew up.
    def body(i: int, x: float) -> pp.BodyState:
        return pp.BodyState(i, (x, 0, 0), (1, 0, 0, 0), (0, 0, 0), (0, 0, 0))
    assert pp.divergence_reason(0.0, [body(i, 3e5) for i in range(1000)]) is None
    assert "body 7 blew up" in (pp.divergence_reason(0.0, [body(3, 0.0), body(7, 1e200)]) or "")


# --- pybullet's per-body material factors (pbdval.external.pybullet.materials)

def test_material_factors_reproduce_a_star_of_pairs() -> None:
    # ground 0 touching bodies 1..3 with different values: always a product (ground 1 · value)
    pairs = [(0, 1, 0.3), (0, 2, 0.5), (0, 3, 0.7)]
    f = materials.per_body_factors(4, pairs)
    assert f is not None
    for i, j, v in pairs:
        assert f[i] * f[j] == pytest.approx(v, rel=1e-12)


def test_material_factors_reject_pairs_that_are_no_product() -> None:
    # An even cycle: m0 m1 · m2 m3 = m1 m2 · m3 m0 must hold, here 1 · 1 != 1 · 0.25. (An odd
    # cycle, a triangle, always has a solution.)
    assert materials.per_body_factors(4, [(0, 1, 1.0), (1, 2, 1.0), (2, 3, 1.0), (3, 0, 0.25)]) is None
    triangle = materials.per_body_factors(3, [(0, 1, 1.0), (1, 2, 1.0), (0, 2, 0.25)])
    assert triangle is not None and triangle[0] * triangle[2] == pytest.approx(0.25, rel=1e-12)
    # a zero pair between bodies that also have positive pairs
    assert materials.per_body_factors(3, [(0, 1, 0.0), (1, 2, 0.5), (0, 2, 0.5)]) is None


def test_material_factors_handle_all_zero_bodies() -> None:
    f = materials.per_body_factors(3, [(0, 1, 0.0), (0, 2, 0.0), (1, 2, 0.49)])
    assert f is not None and f[0] == 0.0 and f[1] * f[2] == pytest.approx(0.49, rel=1e-12)


# --- the MuJoCo contact law (pbdval.external.mujoco.contact_law)

def test_contact_law_inverts_the_kelvin_voigt_restitution() -> None:
    assert contact_law.restitution_of_damping_ratio(0.0) == 1.0
    assert contact_law.restitution_of_damping_ratio(1.0) == pytest.approx(math.exp(-2), rel=1e-15)
    # e(zeta) is continuous at zeta = 1 from both sides
    assert contact_law.restitution_of_damping_ratio(1 - 1e-7) == pytest.approx(math.exp(-2), rel=1e-5)
    assert contact_law.restitution_of_damping_ratio(1 + 1e-7) == pytest.approx(math.exp(-2), rel=1e-5)
    for e in (0.9, 0.8, 0.5, 0.2, 0.1):
        zeta = contact_law.damping_ratio_for_restitution(e, 2.0)
        assert contact_law.restitution_of_damping_ratio(zeta) == pytest.approx(e, rel=1e-12)
    # below e(zeta_max) the ratio is clamped to zeta_max = tau / (2h)
    law = contact_law.contact_solref(0.004, 0.001, 0.0)
    assert law.damping_ratio == 2.0 and law.stiffness == pytest.approx(1 / 0.004**2)
