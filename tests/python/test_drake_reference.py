"""The converged reference: `pbdval run` and `pbdval sweep` with `--reference METHOD[:KEY=VALUE,...]`
measure every run against that engine's run of the same scene (docs/convergence.md#a-converged-reference),
through the one trajectory-error path (validation/metrics)."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

from conftest import REPO

REFERENCE = "drake.rk3:targetAccuracy=1e-10"


def pbdval(binary: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(binary), *args], capture_output=True, text=True, cwd=REPO, check=False, timeout=900)


def run_records(binary: Path, out: Path, *args: str) -> list[dict[str, Any]]:
    result = pbdval(binary, "run", *args, "--out", str(out), "--jobs", "2", "--quiet", "--no-trajectories")
    assert result.returncode == 0, result.stderr
    runs: list[dict[str, Any]] = json.loads((out / "results.json").read_text())["runs"]
    return runs


def test_a_run_against_the_converged_reference_agrees_with_its_error_against_the_analytic_one(
        pbdval_binary: Path, tmp_path: Path) -> None:
    """On the hinge pendulum, whose case reference is analytic (a), the error of a run (x)
    against Drake's converged run (d) obeys the triangle inequality
    | max|x − d| − max|x − a| | ≤ max|d − a|, with max|d − a| Drake's own error measured on the
    same samples by the same metric."""
    case = "cases/joint_hinge.json"
    drake = run_records(pbdval_binary, tmp_path / "drake", case, "--methods", "drake.rk3",
                        "--set", "targetAccuracy=1e-10")
    own_error = drake[0]["metrics"]["trajectory_error_max"]
    # pybullet runs through its persistent server: the reference engine's server is started
    # beside it in every worker.
    methods = "mujoco.euler,pbd,pybullet.si"
    against_analytic = run_records(pbdval_binary, tmp_path / "a", case, "--methods", methods)
    against_drake = run_records(pbdval_binary, tmp_path / "d", case, "--methods", methods, "--reference", REFERENCE)
    for a, d in zip(against_analytic, against_drake, strict=True):
        assert (a["method"], d["status"]) == (d["method"], "ok"), d
        assert "drake/drake.rk3" in d["reference"] and "targetAccuracy=1e-10" in d["reference"], d["reference"]
        x_a, x_d = a["metrics"]["trajectory_error_max"], d["metrics"]["trajectory_error_max"]
        # The triangle inequality, plus the round-off of three maxima of ~1e-3 m (1e-12).
        assert abs(x_d - x_a) <= own_error + 1e-12, (a["method"], x_a, x_d, own_error)
        assert x_d > 10 * own_error  # the methods' errors are far above the reference's


def test_a_bad_reference_is_a_usage_error_naming_it(pbdval_binary: Path, tmp_path: Path) -> None:
    for reference, expected in (("drake.rk9", "drake.rk9"), ("drake.rk3:targetAccuracy=-1", "targetAccuracy"),
                                ("drake.rk3:tolerance=1e-9", "'tolerance' is not a parameter of drake.rk3"),
                                ("drake.rk3:targetAccuracy", "expected key=value")):
        for command in (["run", "cases/joint_hinge.json", "--engines", "pbd"],
                        ["sweep", "cases/joint_hinge.json", "--param", "timeStepSize=0.01,0.005", "--methods", "pbd"]):
            result = pbdval(pbdval_binary, *command, "--reference", reference, "--out", str(tmp_path / "o"))
            assert result.returncode == 2, (command, reference, result.stderr)
            assert "--reference" in result.stderr and expected in result.stderr, result.stderr


def test_a_sweep_against_the_converged_reference_fits_semi_implicit_eulers_first_order(
        pbdval_binary: Path, tmp_path: Path) -> None:
    # MuJoCo's semi-implicit Euler on the hinge pendulum converges at first order to the exact
    # solution, which the converged reference stands for to 1e-10 per step.
    out = tmp_path / "sweep"
    result = pbdval(pbdval_binary, "sweep", "cases/joint_hinge.json", "--param", "timeStepSize=0.004,0.002,0.001",
                    "--methods", "mujoco.euler", "--reference", REFERENCE, "--repeat", "1", "--jobs", "2",
                    "--quiet", "--out", str(out))
    assert result.returncode == 0, result.stderr
    sweep = json.loads((out / "sweep.json").read_text())
    assert sweep["metric"] == "trajectory_error_max"
    order = sweep["fits"][0]["orders"]["timeStepSize"]["order"]
    assert abs(order - 1.0) < 0.1, order  # first order; the pendulum's fits are within 0.06 of 1


def test_a_case_reference_of_type_engine_runs_its_served_engine_beside_a_served_engine(
        pbdval_binary: Path, tmp_path: Path) -> None:
    """A case whose Validation.reference is {"type": "engine", "method": "drake.rk3"}, run in
    pybullet (a served engine): the worker starts Drake's server too, as for `--reference
    drake.rk3`. Without it the reference run found no Drake socket in the worker's server folder
    and the run had no reference. Both routes run the same reference (drake.rk3 at its default
    targetAccuracy, at the run's step), so they measure the same error, bit for bit."""
    scene = json.loads((REPO / "cases" / "joint_hinge.json").read_text())
    scene["Validation"]["reference"] = {"type": "engine", "method": "drake.rk3"}
    scene["Validation"]["duration"] = 0.5
    case = tmp_path / "case" / "joint_hinge.json"
    case.parent.mkdir()
    case.write_text(json.dumps(scene))
    (case.parent / "models").symlink_to(REPO / "cases" / "models")
    from_case = run_records(pbdval_binary, tmp_path / "c", str(case), "--methods", "pybullet.si,mujoco.euler")
    from_option = run_records(pbdval_binary, tmp_path / "o", str(case), "--methods", "pybullet.si,mujoco.euler",
                              "--reference", "drake.rk3")
    for c, o in zip(from_case, from_option, strict=True):
        assert c["status"] == "ok" and "drake/drake.rk3" in c["reference"], c
        assert c["metrics"]["trajectory_error_max"] == o["metrics"]["trajectory_error_max"], (c, o)
