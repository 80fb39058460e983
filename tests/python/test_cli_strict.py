"""The pbdval command accepts nothing silently and never loses results (issues 24 and 25,
docs/cli.md#results-folders): unknown names are usage errors with a "did you mean", a --set that
a run would ignore is refused, results folders are locked while a command writes them and
replaced as one transaction, another plan's results are not replaced without --force, and no
output may overwrite an input of the same command."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import time
from collections.abc import Callable
from pathlib import Path

import pytest

import pbdval

REPO = Path(__file__).resolve().parents[2]
# The build under test (as the conftest's pbdval_binary fixture); pbdval.run uses the build its
# C++ core was loaded from.
BINARY = Path(os.environ.get("PBDVAL_BUILD_DIR", REPO / "build" / "release")) / "bin" / "pbdval"
QUICK = str(REPO / "cases" / "projectile.json")  # 0.1 s of work in pbd
OTHER = str(REPO / "cases" / "joint_hinge.json")
# A run that takes seconds in pbd (100 bodies at a tenth of the case's step), so that a second
# command or a signal reliably arrives while it is going.
SLOW = [str(REPO / "cases" / "chain_100.json"), "--set", "timeStepSize=0.0005"]


def pbdval_command(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(BINARY), *args], capture_output=True, text=True, check=False)


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under `folder` but the lock file, by relative path."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and p.name != ".pbdval.lock"}


def wait_for(condition: Callable[[], bool], seconds: float = 60.0) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {seconds} s waiting for {condition}")
        time.sleep(0.02)


def expect_usage_error(result: subprocess.CompletedProcess[str], *texts: str) -> None:
    assert result.returncode == 2, result.stderr
    for text in texts:
        assert text in result.stderr, result.stderr


# ---- Task 1: no silent acceptance ------------------------------------------------------------


def test_sweep_with_an_unknown_parameter_is_a_usage_error_naming_the_accepted_ones(tmp_path: Path) -> None:
    result = pbdval_command("sweep", QUICK, "--param", "dt=0.01,0.005", "--methods", "pbd",
                            "--out", str(tmp_path / "s"))
    expect_usage_error(result, "unknown setting 'dt'", "timeStepSize", "subSteps")
    assert not (tmp_path / "s").exists()  # nothing written, no empty folder
    typo = pbdval_command("sweep", QUICK, "--param", "timeStepsize=0.01,0.005", "--methods", "pbd",
                          "--out", str(tmp_path / "s"))
    expect_usage_error(typo, 'did you mean "timeStepSize"?')


def test_sweep_with_an_unknown_metric_suggests_the_closest(tmp_path: Path) -> None:
    result = pbdval_command("sweep", QUICK, "--param", "timeStepSize=0.01,0.005", "--methods", "pbd",
                            "--metric", "energy_drift", "--out", str(tmp_path / "s"))
    expect_usage_error(result, "--metric: 'energy_drift' is not a metric", "trajectory_error_max",
                       'did you mean "energy_drift_max"?')


def test_sweep_fine_divisor_out_of_range_or_without_a_fine_reference_is_refused(tmp_path: Path) -> None:
    base = ["sweep", QUICK, "--param", "timeStepSize=0.01,0.005", "--methods", "pbd",
            "--out", str(tmp_path / "s")]
    expect_usage_error(pbdval_command(*base, "--reference", "fine", "--fine-divisor", "1000000000"),
                       "--fine-divisor: expected an integer from 2 to 1024, got '1000000000'")
    expect_usage_error(pbdval_command(*base, "--fine-divisor", "8"), "--fine-divisor sets the step of --reference fine")


def test_sweep_over_a_parameter_a_named_method_ignores_is_refused(tmp_path: Path) -> None:
    result = pbdval_command("sweep", QUICK, "--param", "subSteps=1,2", "--methods", "pbd,ode.quickstep",
                            "--out", str(tmp_path / "s"))
    expect_usage_error(result, "--param subSteps: has no effect in ode.quickstep", "it applies to pbd")


def test_a_set_key_the_engine_does_not_honour_is_refused_by_simulate_and_run(tmp_path: Path) -> None:
    simulate = pbdval_command("simulate", QUICK, "--engine", "ode", "--set", "subSteps=10",
                              "--out", str(tmp_path / "x.csv"))
    expect_usage_error(simulate, "subSteps has no effect in ode/ode.quickstep", "ode honours timeStepSize, gravitation")
    assert not (tmp_path / "x.csv").exists()
    mixed = pbdval_command("run", QUICK, "--engines", "pbd,ode", "--set", "subSteps=2", "--out", str(tmp_path / "r"))
    expect_usage_error(mixed, "subSteps has no effect in ode/ode.quickstep", "it applies to pbd/pbd",
                       "restrict --engines or --methods")
    assert not (tmp_path / "r").exists()


def test_run_with_a_set_value_the_loader_rejects_exits_2_like_simulate(tmp_path: Path) -> None:
    run = pbdval_command("run", QUICK, "--engines", "pbd", "--set", "subSteps=zero", "--out", str(tmp_path / "r"))
    simulate = pbdval_command("simulate", QUICK, "--set", "subSteps=zero", "--out", str(tmp_path / "x.csv"))
    expect_usage_error(run, "subSteps")
    expect_usage_error(simulate, "subSteps")
    assert not (tmp_path / "r").exists()


def test_jobs_beyond_the_range_does_not_wrap_around(tmp_path: Path) -> None:
    # 4294967297 = 2^32 + 1 would wrap to 1 in a 32-bit int.
    expect_usage_error(pbdval_command("run", QUICK, "--engines", "pbd", "--jobs", "4294967297",
                                      "--out", str(tmp_path / "r")),
                       "--jobs: expected an integer from 1 to 1024, got '4294967297'")
    expect_usage_error(pbdval_command("sweep", QUICK, "--param", "timeStepSize=0.01,0.005", "--jobs", "0"),
                       "--jobs: expected an integer from 1 to 1024")


def test_engines_and_methods_listed_twice_are_refused(tmp_path: Path) -> None:
    expect_usage_error(pbdval_command("run", QUICK, "--engines", "pbd,pbd", "--out", str(tmp_path / "r")),
                       "--engines: 'pbd' is listed twice")
    expect_usage_error(pbdval_command("run", QUICK, "--methods", "pbd,pbd", "--out", str(tmp_path / "r")),
                       "--methods: 'pbd' is listed twice")


def test_unknown_engines_methods_and_options_get_a_did_you_mean(tmp_path: Path) -> None:
    expect_usage_error(pbdval_command("run", QUICK, "--engines", "pdb", "--out", str(tmp_path / "r")),
                       "unknown engine 'pdb'", 'did you mean "pbd"?')
    expect_usage_error(pbdval_command("simulate", QUICK, "--method", "ode.quickstp"),
                       "unknown method 'ode.quickstp'", 'did you mean "ode.quickstep"?')
    expect_usage_error(pbdval_command("run", QUICK, "--engine", "pbd"), 'did you mean "--engines"?')
    expect_usage_error(pbdval_command("sweeep", QUICK), "unknown command 'sweeep'", 'did you mean "sweep"?')
    expect_usage_error(pbdval_command("simulate", QUICK, "--engine", "ode", "--set", "iteration=5"),
                       "unknown setting 'iteration'", 'did you mean "iterations"?')


def test_an_interrupted_sweep_exits_128_plus_the_signal_and_leaves_no_folder(tmp_path: Path) -> None:
    out = tmp_path / "new" / "sweep"
    process = subprocess.Popen([str(BINARY), "sweep", SLOW[0], "--param", "timeStepSize=0.0005,0.00025",
                                "--methods", "pbd", "--jobs", "1", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(lambda: any(out.glob(".pbdval-staging-*")))
    time.sleep(0.3)
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 128 + signal.SIGINT, stderr
    assert "interrupted by SIGINT" in stderr
    assert not (tmp_path / "new").exists()  # the folders it created are gone again


# ---- Task 2: results folders -------------------------------------------------------------------


def test_a_second_run_into_a_folder_being_written_is_refused_naming_the_first(tmp_path: Path) -> None:
    out = tmp_path / "out"
    first = subprocess.Popen([str(BINARY), "run", *SLOW, "--engines", "pbd", "--jobs", "1",
                              "--out", str(out), "--quiet"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        wait_for(lambda: any(out.glob(".pbdval-staging-*")))
        second = pbdval_command("run", QUICK, "--engines", "pbd", "--out", str(out))
        expect_usage_error(second, f"another pbdval run is writing here (pid {first.pid})")
    finally:
        first.send_signal(signal.SIGINT)
        first.communicate(timeout=60)
    assert not (out / "results.json").exists()  # neither wrote results


def test_an_interrupted_run_leaves_the_previous_results_and_trajectories_as_they_were(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert pbdval_command("run", QUICK, "--engines", "pbd", "--out", str(out)).returncode == 0
    before = snapshot(out)
    # Another plan over the same folder (--force): its first run (projectile at another step) would
    # write a trajectory of the same name, then the slow one is interrupted.
    started = time.time()
    process = subprocess.Popen([str(BINARY), "run", QUICK, SLOW[0], "--set", "timeStepSize=0.0005",
                                "--engines", "pbd", "--jobs", "1", "--force", "--out", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(lambda: any(p.stat().st_mtime >= started for p in out.rglob("pbd-pbd.csv")))
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=60)
    assert process.returncode == 128 + signal.SIGINT, stderr
    assert snapshot(out) == before  # results.json and every trajectory it lists, byte for byte
    assert not any(out.glob(".pbdval-staging-*"))


def test_a_run_into_a_folder_of_another_plan_is_refused_without_force(tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert pbdval_command("run", QUICK, "--engines", "pbd", "--out", str(out)).returncode == 0
    before = snapshot(out)
    refused = pbdval_command("run", OTHER, "--engines", "pbd", "--out", str(out))
    # --engines pbd runs both PBD methods (pbd, pbd.xpbd): two runs each.
    expect_usage_error(refused, "holds 2 runs of another plan (this command makes 2)",
                       "projectile pbd/pbd is not in this command's plan", "--force")
    assert snapshot(out) == before
    # The same plan again replaces its own results; --force replaces another plan's, trajectories
    # included (no trajectory of the old plan stays unlisted).
    assert pbdval_command("run", QUICK, "--engines", "pbd", "--out", str(out)).returncode == 0
    forced = pbdval_command("run", OTHER, "--engines", "pbd", "--out", str(out), "--force")
    assert forced.returncode == 0, forced.stderr
    document = json.loads((out / "results.json").read_text())
    assert {r["case"] for r in document["runs"]} == {"joint_hinge"}
    assert {p.parent.name for p in (out / "trajectories").rglob("*.csv")} == {"joint_hinge"}


def test_a_sweep_into_a_folder_holding_another_sweep_is_refused_without_force(tmp_path: Path) -> None:
    out = tmp_path / "s"
    sweep = ["sweep", QUICK, "--methods", "pbd", "--out", str(out), "--quiet"]
    assert pbdval_command(*sweep, "--param", "timeStepSize=0.01,0.005").returncode == 0
    before = snapshot(out)
    expect_usage_error(pbdval_command(*sweep, "--param", "timeStepSize=0.02,0.01"), "of another plan", "--force")
    assert snapshot(out) == before
    assert pbdval_command(*sweep, "--param", "timeStepSize=0.02,0.01", "--force").returncode == 0


def test_python_run_raises_instead_of_returning_older_results(tmp_path: Path) -> None:
    out = tmp_path / "out"
    first = pbdval.run([QUICK], engines=["pbd"], out=out)
    assert {r.case for r in first} == {"projectile"}
    with pytest.raises(pbdval.CommandError, match="unknown engine 'nope'") as error:
        pbdval.run([QUICK], engines=["nope"], out=out)
    assert error.value.returncode == 2
    assert isinstance(error.value, subprocess.CalledProcessError)
    with pytest.raises(pbdval.CommandError, match="another plan"):
        pbdval.run([OTHER], engines=["pbd"], out=out)
    assert {r.case for r in pbdval.run([OTHER], engines=["pbd"], out=out, force=True)} == {"joint_hinge"}


def test_no_output_may_overwrite_an_input_of_the_same_command(tmp_path: Path) -> None:
    scene = tmp_path / "scene.json"
    shutil.copy(QUICK, scene)
    (tmp_path / "models").symlink_to(REPO / "cases" / "models")  # the meshes it names
    original = scene.read_bytes()
    os.link(scene, tmp_path / "hardlink.json")  # the same file under another name
    (tmp_path / "symlink.json").symlink_to(scene)
    for out in (scene, tmp_path / "hardlink.json", tmp_path / "symlink.json"):
        expect_usage_error(pbdval_command("simulate", str(scene), "--duration", "0.1", "--out", str(out)),
                           "is the scene")
        expect_usage_error(pbdval_command("export-scene", str(scene), "--out", str(out)), "is the scene")
    assert scene.read_bytes() == original
    same = tmp_path / "states.csv"
    expect_usage_error(pbdval_command("simulate", str(scene), "--duration", "0.1", "--out", str(same),
                                      "--particles", str(same)), "are the same file")
    assert not same.exists()

    results = tmp_path / "run"
    done = pbdval_command("run", str(scene), "--engines", "pbd", "--out", str(results), "--no-trajectories")
    assert done.returncode == 0
    results_json = results / "results.json"
    results_bytes = results_json.read_bytes()
    expect_usage_error(pbdval_command("baseline", "--results", str(results), "--out", str(results_json)),
                       "is the results")
    baseline = tmp_path / "baseline.json"
    assert pbdval_command("baseline", "--results", str(results), "--out", str(baseline)).returncode == 0
    baseline_bytes = baseline.read_bytes()
    gate = ["gate", "--baseline", str(baseline), "--results", str(results)]
    expect_usage_error(pbdval_command(*gate, "--junit", str(baseline)), "--junit", "is the baseline")
    expect_usage_error(pbdval_command(*gate, "--markdown", str(results_json)), "--markdown", "is the results")
    expect_usage_error(pbdval_command(*gate, "--json", str(baseline)), "--json", "is the baseline")
    expect_usage_error(pbdval_command(*gate, "--junit", str(tmp_path / "g"), "--markdown", str(tmp_path / "g")),
                       "are the same file")
    assert results_json.read_bytes() == results_bytes and baseline.read_bytes() == baseline_bytes


def test_a_parameter_the_engine_ignores_is_refused_from_python_too() -> None:
    scene = pbdval.load_scene(QUICK)
    with pytest.raises(ValueError, match="subSteps has no effect in ode/ode.quickstep"):
        pbdval.Simulation(scene, "ode.quickstep", {"subSteps": 10})
    with pytest.raises(ValueError, match='did you mean "iterations"'):
        pbdval.Simulation(scene, "ode.quickstep", {"iteration": 10})
    pbdval.Simulation(scene, "ode.quickstep", {"iterations": 10, "timeStepSize": 0.005})  # honoured


def test_the_python_api_suggests_names_with_the_command_lines_helper() -> None:
    registry = pbdval.engines()
    with pytest.raises(ValueError, match='unknown engine \'pdb\'.*did you mean "pbd"\\?'):
        registry.engine("pdb")
    with pytest.raises(ValueError, match='did you mean "ode.quickstep"\\?'):
        registry.method("ode.quickstp")
