"""`pbdval report` (python/pbdval/report.py): a real run and synthetic results folders with every
kind of gap render without crashing and say what is missing; a folder that is not a results
folder is a clear error."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

from pbdval.report import build_report
from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[2]


def pbdval(*args: str, check: bool = True) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(pbdval_binary()), *args], capture_output=True, text=True, check=check)


@pytest.fixture(scope="module")
def real_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("results") / "out"
    pbdval("run", str(REPO / "cases/joint_hinge.json"), str(REPO / "cases/joint_distance.json"),
           "--engines", "pbd,bullet", "--out", str(out), "--jobs", "2", "--quiet")
    return out


def test_a_real_run_renders_every_case_and_run(real_results: Path, tmp_path: Path) -> None:
    report = tmp_path / "report"
    done = pbdval("report", str(real_results), "--out", str(report), "--baseline",
                  str(REPO / "reports/baselines/main.json"), "--sweeps", str(REPO / "reports/sweeps/joint_hinge-timestep"))
    assert done.stdout.strip() == str(report / "index.html")
    index = (report / "index.html").read_text()
    for case in ("joint_hinge", "joint_distance"):
        assert f"cases/{case}.html" in index
        assert (report / "cases" / f"{case}.html").is_file()
    for label in ("pbd/pbd", "pbd/pbd.xpbd", "bullet/bullet.si"):
        assert label in index
    assert "Gate" in index  # the gate ran against the baseline (missing runs: it fails, and says so)
    hinge = (report / "cases/joint_hinge.html").read_text()
    # One curve per ok run (pbd, pbd.xpbd, bullet) in the energy figure and in every metric's
    # figure over time (the series behind the metrics, pbdval.measure).
    for figure in ("energy", "trajectory_error", "joint_error_linear_hinge", "joint_error_angular_hinge"):
        svg = (report / f"figures/joint_hinge-{figure}.svg").read_text()
        assert len(re.findall(r'<path d="M', svg)) == 3, figure
        assert svg in hinge  # shown on the page as well
    distance = (report / "cases/joint_distance.html").read_text()
    assert "unsupported" in distance and "DistanceJoints[0]" in distance  # bullet lacks it, says why
    convergence = (report / "convergence.html").read_text()
    assert "p = " in convergence and "slope 4" in convergence
    # Error against wall time with the sweep's Pareto front (marked by pbdval sweep).
    assert "Pareto front" in convergence and (report / "figures/sweep-joint_hinge-timestep-cost.svg").is_file()
    # The parity matrix from docs/parity-*.md: Bullet lacks distance joints, MuJoCo universal joints.
    parity = (report / "parity.html").read_text()
    distance_row = parity[parity.index("<td>DistanceJoints</td>"):].split("</tr>")[0]
    assert distance_row.count("unsupported") >= 3 and "native" in distance_row
    universal_row = parity[parity.index("<td>UniversalJoints</td>"):].split("</tr>")[0]
    assert "unsupported" in universal_row
    assert (report / "figures/joint_hinge-energy.svg").read_text().startswith("<svg")
    assert "| joint_hinge |" in (report / "report.md").read_text()


def test_changes_against_the_baseline_are_listed_with_their_numbers(real_results: Path, tmp_path: Path) -> None:
    baseline = tmp_path / "baseline.json"
    pbdval("baseline", "--results", str(real_results), "--out", str(baseline))
    document = json.loads(baseline.read_text())
    runs = document["runs"]
    hinge = next(r for r in runs if r["case"] == "joint_hinge" and r["method"] == "pbd")
    now = hinge["metrics"]["trajectory_error_max"]
    hinge["metrics"]["trajectory_error_max"] = now / 2  # the run is now twice as far off: worse
    distance = next(r for r in runs if r["case"] == "joint_distance" and r["method"] == "pbd.xpbd")
    distance["metrics"]["joint_error_linear_max"] *= 4  # now four times better
    runs.remove(next(r for r in runs if r["case"] == "joint_distance" and r["engine"] == "bullet"))  # new
    runs.append(dict(hinge, case="joint_gone"))  # missing
    baseline.write_text(json.dumps(document))
    report = tmp_path / "report"
    build_report(real_results, report, baseline=baseline, quiet=True)
    index = (report / "index.html").read_text()
    assert "1 metrics worse, 1 better, 0 status changes, 1 new runs, 1 missing runs" in index
    worse = index[index.index("<span class='badge fail'>worse</span>"):].split("</tr>")[0]
    assert "joint_hinge" in worse and "trajectory_error_max" in worse and f"{now / 2:.4g}" in worse and "2×" in worse
    assert "joint_distance bullet/bullet.si" in index and "joint_gone pbd/pbd" in index
    assert "| worse | joint_hinge | pbd/pbd | trajectory_error_max |" in (report / "report.md").read_text()


def test_sweep_writes_its_convergence_page(tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    done = pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "timeStepSize=0.01,0.005,0.0025",
                  "--methods", "pbd", "--out", str(out), "--report", "--quiet")
    assert done.stdout.strip().endswith(str(out / "report/convergence.html"))
    page = (out / "report/convergence.html").read_text()
    assert "projectile" in page and "p = " in page and "Pareto front" in page
    assert "href='index.html'" not in page  # on its own: no links to pages that do not exist


def synthetic(folder: Path, runs: list[dict], schema_version: int = 1, case_file: str = "") -> Path:
    folder.mkdir(parents=True)
    cases = {r["case"]: {"file": case_file, "description": "synthetic", "checks": [], "tolerances": {}}
             for r in runs}
    (folder / "results.json").write_text(json.dumps({
        "schema": "pbdval-results", "schemaVersion": schema_version, "metadata": {}, "cases": cases, "runs": runs}))
    return folder


def run_record(case: str, engine: str, method: str, status: str, metrics: dict, trajectory: str = "") -> dict:
    return {"case": case, "caseFile": "", "engine": engine, "method": method, "status": status,
            "reason": "" if status == "ok" else f"synthetic {status}", "metrics": metrics,
            "trajectory": trajectory, "parameters": {}, "settings": {"solver": "x"}, "facts": {}}


def test_gaps_render_with_a_note_instead_of_crashing(tmp_path: Path) -> None:
    runs = [run_record("a", "pbd", "pbd", "ok", {"energy_drift_max": None}, trajectory="missing.csv"),
            run_record("a", "ode", "ode.quickstep", "diverged", {}),
            run_record("a", "bullet", "bullet.si", "unsupported", {}),
            run_record("b", "mujoco", "mujoco.euler", "error", {"wall_time_s": 0.1})]
    folder = synthetic(tmp_path / "results", runs, case_file=str(tmp_path / "no-such-scene.json"))
    empty_sweep = tmp_path / "sweep-empty"
    empty_sweep.mkdir()
    (empty_sweep / "sweep.json").write_text(json.dumps({"case": "a", "metric": "m", "points": [], "fits": []}))
    index = build_report(folder, tmp_path / "report", sweeps=[empty_sweep, tmp_path / "no-sweep"], quiet=True)
    text = index.read_text()
    for status in ("diverged", "unsupported", "error"):
        assert status in text
    page = (tmp_path / "report/cases/a.html").read_text()
    assert "could not be loaded" in page  # the scene file is missing: no plots, a note
    assert "synthetic diverged" in page
    convergence = (tmp_path / "report/convergence.html").read_text()
    assert "no points" in convergence and "not a sweep" in convergence


def test_an_older_schema_renders_a_note(tmp_path: Path) -> None:
    folder = synthetic(tmp_path / "old", [run_record("a", "pbd", "pbd", "ok", {})], schema_version=0)
    index = build_report(folder, tmp_path / "report", quiet=True)
    assert "schemaVersion 0" in index.read_text()


def test_a_folder_that_is_not_a_results_folder_is_a_clear_error(tmp_path: Path) -> None:
    done = pbdval("report", str(tmp_path), "--out", str(tmp_path / "r"), check=False)
    assert done.returncode == 2
    assert f"{tmp_path}: expected a results folder" in done.stderr
    assert not (tmp_path / "r").exists()
