"""`import pbdval`: the C++ core from Python (python/pbdval/api.py, results.py, bindings/core.cpp).

The expected values come from three independent places: the pbdval command itself (the binding
must give bit-identical trajectories and metrics, since it calls the same code: any difference is
a binding bug), closed forms (free fall under the integrator's own update), and conservation
(unit quaternions, the energy identity).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
VENV_PYTHON = REPO / ".venv" / "bin" / "python"

import pbdval  # conftest puts python/ on the path; the .pth adds the build

NON_MEASURED = {"wall_time_s", "steps", "real_time_factor"}  # timings, not metrics of states


def binary() -> Path:
    from pbdval.results import pbdval_binary

    return pbdval_binary()


def test_import_pbdval_works_from_the_venv_without_sys_path_tricks(tmp_path: Path) -> None:
    # The venv's .pth (scripts/install-deps) must be enough: run from another folder.
    code = f"import pbdval; s = pbdval.load_scene({str(REPO / 'cases/chain_10.json')!r}); print(s.body_count)"
    out = subprocess.run([str(VENV_PYTHON), "-c", code], cwd=tmp_path, capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    bodies = len(json.loads((REPO / "cases/chain_10.json").read_text())["RigidBodies"])
    assert out.stdout.strip() == str(bodies)  # one per RigidBodies entry of the file


def test_scene_error_carries_file_json_path_and_message(tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"RigidBodies": [{"id": 1, "collisionObjectScale": "abc"}]}))
    with pytest.raises(pbdval.SceneError) as caught:
        pbdval.load_scene(bad)
    error = caught.value
    assert error.file == str(bad)
    assert error.json_path == "RigidBodies[0].collisionObjectScale"
    assert "expected" in error.message
    assert str(error).startswith(f"{bad}: RigidBodies[0].collisionObjectScale: ")
    assert isinstance(error, ValueError)


def test_missing_scene_file_is_a_scene_error(tmp_path: Path) -> None:
    with pytest.raises(pbdval.SceneError, match="missing.json"):
        pbdval.load_scene(tmp_path / "missing.json")


def test_engines_and_methods_list_built_in_and_external_engines() -> None:
    engines = pbdval.engines()
    names = engines.names()
    for expected in ("pbd", "bullet", "ode", "mujoco", "pybullet", "mujoco-python"):
        assert expected in names
    xpbd = engines.method("pbd.xpbd")
    substeps = {p.name: p for p in xpbd.parameters}["substeps"]
    assert substeps.kind == "integer" and substeps.default == "20"
    assert engines.method("ode").name == engines.engine("ode").default_method
    with pytest.raises(ValueError, match="unknown method"):
        engines.method("no-such-method")


def test_resolved_scene_is_what_export_scene_writes(tmp_path: Path) -> None:
    case = REPO / "cases/joint_hinge.json"
    scene = pbdval.load_scene(case)
    resolved = scene.resolved("ode.quickstep")
    out = tmp_path / "hinge.resolved.json"
    subprocess.run([str(binary()), "export-scene", str(case), "--method", "ode.quickstep", "--out", str(out)],
                   check=True, capture_output=True)
    assert resolved == json.loads(out.read_text())


def test_stepping_matches_pbdval_simulate_bit_for_bit(tmp_path: Path) -> None:
    # Same engine, same scene, same steps: the binding must hand back exactly the CSV's numbers
    # (the CSV round-trips doubles exactly, validation/io/trajectory.h).
    case = REPO / "cases/chain_10.json"
    scene = pbdval.load_scene(case)
    h = scene.time_step
    steps = 50
    csv = tmp_path / "chain.csv"
    subprocess.run([str(binary()), "simulate", str(case), "--engine", "pbd", "--duration", repr(steps * h),
                    "--out", str(csv)], check=True, capture_output=True)
    recorded = pbdval.Trajectory.read_csv(csv)
    sim = pbdval.Simulation(scene, "pbd")
    sim.step(steps)
    state = sim.state()
    assert state.time == recorded.times[-1]
    np.testing.assert_array_equal(state.positions, recorded.positions[-1])
    np.testing.assert_array_equal(state.quaternions, recorded.quaternions[-1])
    np.testing.assert_array_equal(state.velocities, recorded.velocities[-1])
    np.testing.assert_array_equal(state.angular_velocities, recorded.angular_velocities[-1])
    np.testing.assert_array_equal(state.ids, scene.body_ids)


def test_free_fall_follows_the_symplectic_euler_closed_form() -> None:
    # projectile: free bodies under gravity. PBD's update per substep of size s = h/subSteps is
    # v += s g, x += s v, so after N substeps x = x0 + N s v0 + s^2 g N(N+1)/2 exactly in real
    # arithmetic. Tolerance: 1e-9 m, far above the round-off of a few thousand additions of
    # O(1 m) numbers (~1e-13 m) and far below the O(s g t) = 1e-4 m gap to the exact parabola,
    # so the test tells the integrator's update from the continuous solution.
    scene = pbdval.load_scene(REPO / "cases/projectile.json")
    sim = pbdval.Simulation(scene, "pbd")
    start = sim.state()
    x0, v0 = start.positions.copy(), start.velocities.copy()
    substeps = int(sim.facts["integrator_steps_per_scene_step"])
    steps = 200
    sim.step(steps)
    s = scene.time_step / substeps
    n = steps * substeps
    expected = x0 + n * s * v0 + s * s * scene.gravity * n * (n + 1) / 2
    np.testing.assert_allclose(sim.state().positions, expected, rtol=0, atol=1e-9)


def test_read_into_reuses_the_arrays_and_quaternions_are_unit() -> None:
    scene = pbdval.load_scene(REPO / "cases/free_tumbling_box.json")
    sim = pbdval.Simulation(scene, "pbd")
    buffer = pbdval.BodyStates(scene.body_count)
    before = buffer.packed.ctypes.data
    sim.step(10)
    sim.read(buffer)
    assert buffer.packed.ctypes.data == before
    assert buffer.time == pytest.approx(10 * scene.time_step, rel=1e-12)  # the accumulated clock
    # |q| = 1 to round-off: the engine renormalises every substep (4 ulp of 1 ≈ 1e-15).
    np.testing.assert_allclose(np.linalg.norm(buffer.quaternions, axis=1), 1.0, atol=1e-14)
    with pytest.raises(ValueError, match=r"shape \(1, 14\)"):
        sim._stepper.read_into(np.zeros((2, 14)))


def test_parameters_and_settings_are_checked_like_set() -> None:
    scene = pbdval.load_scene(REPO / "cases/joint_hinge.json")
    with pytest.raises(ValueError, match="substeps"):
        pbdval.Simulation(scene, "pbd.xpbd", {"substeps": 0})
    with pytest.raises(ValueError, match="timeStepSize"):
        pbdval.Simulation(scene, "pbd", {"timeStepSize": -1.0})
    sim = pbdval.Simulation(scene, "pbd.xpbd", {"substeps": 7, "timeStepSize": 0.002})
    assert sim.facts["parameters"]["substeps"] == "7"
    assert sim.facts["integrator_steps_per_scene_step"] == 7


def test_unsupported_scene_and_external_stepping_are_clear_errors() -> None:
    with pytest.raises(pbdval.UnsupportedError, match="bullet.si"):
        pbdval.Simulation(pbdval.load_scene(REPO / "cases/joint_distance.json"), "bullet.si")
    with pytest.raises(ValueError, match="another process"):
        pbdval.Simulation(pbdval.load_scene(REPO / "cases/joint_hinge.json"), "pybullet")


def test_simulate_runs_external_engines_through_their_protocol() -> None:
    scene = pbdval.load_scene(REPO / "cases/joint_hinge.json")
    info, trajectory = pbdval.simulate(scene, "pybullet", duration=0.5)
    assert info.ok, info.reason
    assert info.engine == "pybullet"
    h = scene.time_step
    assert len(trajectory) >= 2 and trajectory.times[-1] == pytest.approx(0.5, abs=h)
    assert trajectory.positions.shape == (len(trajectory), scene.body_count, 3)


def test_measure_gives_exactly_the_metrics_of_pbdval_run(tmp_path: Path) -> None:
    # One measurement path: the metrics a notebook computes from the run's CSV equal the ones
    # results.json holds, bit for bit (analytic reference at the engine's integrator step,
    # penetration with the engine's margin, as the runner does).
    cases = [REPO / "cases/joint_hinge.json", REPO / "cases/contact_resting_box.json"]
    results = pbdval.run(cases, engines=["pbd", "bullet"], out=tmp_path / "out", jobs=1)
    assert len(results) == 6  # 2 cases x (pbd's two run methods, pbd and pbd.xpbd, + bullet.si)
    # A rod too: the run writes its particles and segments beside the trajectory and
    # run.trajectory() attaches them, so the segments' kinetic energy is measured alike
    # (tests/python/test_rod_energy.py does the same for an XPBD rod's elastic energy).
    rods = pbdval.run([REPO / "cases/rod_helix.json"], engines=["pbd"], out=tmp_path / "rods", jobs=1)
    assert len(rods) == 2 and all(r.segments_path is not None for r in rods)
    for run in [*results, *rods]:
        assert run.ok, (run.case, run.label, run.reason)
        scene = pbdval.load_scene(REPO / "cases" / f"{run.case}.json")
        substeps = int(run.facts["integratorStepsPerSceneStep"])
        metrics = pbdval.measure(scene, run.trajectory(), contact_margin=float(run.facts["contactMargin"]),
                                 integration_step=scene.time_step / substeps)
        expected = {k: v for k, v in run.metrics.items() if k not in NON_MEASURED}
        assert metrics.values == expected, (run.case, run.label)
        assert metrics.reference == run.reference


def test_measure_against_another_trajectory_and_the_energy_series() -> None:
    scene = pbdval.load_scene(REPO / "cases/chain_10.json")
    _, coarse = pbdval.simulate(scene, "pbd", duration=0.2)
    # A trajectory compared with itself has zero error (resampling at identical times is exact).
    self_metrics = pbdval.measure(scene, coarse, reference=coarse)
    assert self_metrics["trajectory_error_max"] == 0.0
    assert pbdval.measure(scene, coarse, reference=False).get("trajectory_error_max") is None
    e = pbdval.energy(scene, coarse)
    np.testing.assert_allclose(e.total, e.translational + e.rotational + e.gravitational + e.spring,
                               rtol=1e-12)  # the sum of the terms, to round-off
    metrics = pbdval.measure(scene, coarse, reference=False)
    # energy_drift_final is the last relative drift (docs/metrics.md); same doubles, same
    # formula up to the order of two operations: 1e-12 relative.
    assert metrics["energy_drift_final"] == pytest.approx(e.relative_drift[-1], rel=1e-12, abs=1e-15)
    assert metrics["energy_drift_max"] == pytest.approx(np.max(np.abs(e.relative_drift)), rel=1e-12, abs=1e-15)


def test_measure_series_are_the_values_behind_the_metrics() -> None:
    # The summaries are the series' maxima, computed in the same loop: equal exactly.
    for case, method in (("joint_target_velocity_motor_hinge", "pbd"), ("contact_seed_bounce", "pbd"),
                         ("double_pendulum", "pbd.xpbd")):
        scene = pbdval.load_scene(REPO / "cases" / f"{case}.json")
        _, trajectory = pbdval.simulate(scene, method, duration=0.5)
        metrics = pbdval.measure(scene, trajectory)
        series = metrics.series
        assert np.array_equal(series["times"], trajectory.times)
        for name, values in series.items():
            assert values.shape == trajectory.times.shape, (case, name)
        assert np.max(np.abs(series["energy_drift"])) == metrics["energy_drift_max"]
        if "trajectory_error_max" in metrics:
            assert np.nanmax(series["trajectory_error"]) == metrics["trajectory_error_max"]
            assert np.nanmax(series["rotation_error"]) == metrics["rotation_error_max"]
        if "penetration_max" in metrics:
            assert np.max(series["penetration"]) == metrics["penetration_max"]
        for joint_type, summary in metrics.joint_error_by_type.items():
            assert np.max(series[f"joint_error_linear/{joint_type}"]) == summary["joint_error_linear_max"]
        for quantity in ("angle", "angular_velocity", "position", "velocity"):
            name = f"motor_tracking_{quantity}_max"
            if name in metrics:
                tracking = series[f"motor_tracking/{quantity}"]
                assert np.isnan(tracking[0])  # the set point at t_0 is not yet tracked
                assert np.nanmax(tracking) == metrics[name]
    assert "motor_tracking/angular_velocity" in pbdval.measure(
        pbdval.load_scene(REPO / "cases/joint_target_velocity_motor_hinge.json"),
        pbdval.simulate(pbdval.load_scene(REPO / "cases/joint_target_velocity_motor_hinge.json"), "pbd",
                        duration=0.1)[1]).series


def test_measure_rejects_arrays_of_the_wrong_shape() -> None:
    scene = pbdval.load_scene(REPO / "cases/chain_10.json")
    _, t = pbdval.simulate(scene, "pbd", duration=0.05)
    t.positions = t.positions[:, :3, :]
    with pytest.raises(ValueError, match="positions: expected an array of shape"):
        pbdval.measure(scene, t)


def test_load_results_errors_name_the_path(tmp_path: Path) -> None:
    with pytest.raises(pbdval.ResultsError, match="expected a results folder"):
        pbdval.load_results(tmp_path)
    (tmp_path / "results.json").write_text('{"schema": "pbdval-results", "schemaVersion": 99, "runs": []}')
    with pytest.raises(pbdval.ResultsError, match="schemaVersion 99"):
        pbdval.load_results(tmp_path)
    (tmp_path / "results.json").write_text("{not json")
    with pytest.raises(pbdval.ResultsError, match="cannot be read as JSON"):
        pbdval.load_results(tmp_path)


def test_results_table_puts_nan_where_a_run_failed(tmp_path: Path) -> None:
    results = pbdval.run(REPO / "cases/joint_distance.json", engines=["pbd", "bullet"], out=tmp_path / "o", jobs=1)
    cases, labels, values = results.table("energy_drift_max")
    assert cases == ["joint_distance"]
    by_label = dict(zip(labels, values[0]))
    assert math.isnan(by_label["bullet/bullet.si"])  # unsupported: no value
    assert math.isfinite(by_label["pbd/pbd"])


def test_the_example_prints_the_energy_drift_of_three_engines() -> None:
    out = subprocess.run([str(VENV_PYTHON), str(REPO / "examples/energy_drift.py"), "--duration", "1"],
                         capture_output=True, text=True, env={**os.environ, "PYTHONPATH": ""}, check=False)
    assert out.returncode == 0, out.stderr
    for engine in ("pbd", "pybullet", "mujoco-python"):
        assert engine in out.stdout


def test_runs_compare_particle_by_particle(tmp_path: Path) -> None:
    # pbdval run writes each run's particles beside its trajectory; RunResult.trajectory()
    # attaches them, and measure against another run gives particle_trajectory_error_*.
    results = pbdval.run([REPO / "cases" / "tet_bar.json"], engines=["pbd"], out=tmp_path / "out")
    runs = {r.method: r for r in results.select(case="tet_bar")}
    assert set(runs) == {"pbd", "pbd.xpbd"}
    a, b = runs["pbd"].trajectory(), runs["pbd.xpbd"].trajectory()
    assert a.particle_positions is not None and a.particle_positions.shape == (201, 99, 3)
    assert b.particle_positions is not None
    scene = pbdval.load_scene(REPO / "cases" / "tet_bar.json")
    # Against itself: exactly 0 (the same doubles).
    assert pbdval.measure(scene, a, reference=a)["particle_trajectory_error_max"] == 0
    # Against the other method: the largest particle distance over samples, computed here
    # from the arrays alone (the same subtraction and norm: equal to round-off).
    expected = np.linalg.norm(a.particle_positions - b.particle_positions, axis=2).max()
    assert pbdval.measure(scene, a, reference=b)["particle_trajectory_error_max"] == pytest.approx(expected, rel=1e-12)
    out = subprocess.run([str(VENV_PYTHON), str(REPO / "examples/deformables_across_engines.py"),
                          str(tmp_path / "out")], capture_output=True, text=True,
                         env={**os.environ, "PYTHONPATH": ""}, check=False)
    assert out.returncode == 0, out.stderr
    assert "| tet_bar | pbd/pbd | pbd/pbd.xpbd |" in out.stdout
