"""`pbdval report` (python/pbdval/report.py): a real run and synthetic results folders with every
kind of gap render without crashing and say what is missing; a folder that is not a results
folder is a clear error."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path
from typing import Any

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
                  str(REPO / "reports/baselines/main.json"),
                  "--sweeps", str(REPO / "reports/sweeps/joint_hinge-timestep"))
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
    # The parity matrix from the engines' feature tables: Bullet, DART and Drake lack distance
    # joints (ODE and pbd have them, the MuJoCos approximate them with a tendon); pybullet has them, and
    # universal joints, only in its reduced-coordinate methods, which its cell names.
    parity = (report / "parity.html").read_text()
    distance_row = parity[parity.index("<td title='joint.distance'>"):].split("</tr>")[0]
    assert distance_row.count(">unsupported<") == 3 and ">native<" in distance_row
    assert ">unsupported; native: pybullet.multibody.si, pybullet.multibody.dantzig<" in distance_row
    universal_row = parity[parity.index("<td title='joint.universal'>"):].split("</tr>")[0]
    assert universal_row.count(">unsupported<") == 0
    assert ">unsupported; native: pybullet.multibody.si, pybullet.multibody.dantzig<" in universal_row
    assert (report / "figures/joint_hinge-energy.svg").read_text().startswith("<svg")
    assert "| joint_hinge |" in (report / "report.md").read_text()


@pytest.fixture(scope="module")
def tumbling_results(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """free_tumbling_box in pbd and MuJoCo: its reference has no orientation and its centre of
    mass rests, so its trajectory error is 0 in every engine."""
    out = tmp_path_factory.mktemp("tumbling") / "out"
    pbdval("run", str(REPO / "cases/free_tumbling_box.json"), "--engines", "pbd,mujoco", "--out", str(out),
           "--jobs", "2", "--quiet")
    return out


def ranking_row(index: str, case: str) -> str:
    row = re.search(rf"<tr><td><a href='cases/{case}.html'>.*?</tr>", index, re.DOTALL)
    assert row is not None, f"no row of {case} in the overview"
    return row[0]


def test_the_overview_ranks_by_a_metric_that_tells_the_engines_apart(tumbling_results: Path, tmp_path: Path) -> None:
    index = build_report(tumbling_results, tmp_path / "report", quiet=True).read_text()
    row = ranking_row(index, "free_tumbling_box")
    document = json.loads((tumbling_results / "results.json").read_text())
    runs = {f"{r['engine']}/{r['method']}": r for r in document["runs"]}
    assert all(r["metrics"]["trajectory_error_max"] == 0 for r in runs.values())  # why it must not decide
    # The case's own bound (energy_drift_final ≤ 0.01) decides, named with the unit metrics.h declares.
    assert "<th class='metric'>energy_drift_final <span class=unit>(1 (of E_ref))</span></th>" in row
    # RK4 (fourth order) conserves the torque-free energy far better than the first-order methods:
    # it is the best of the row, and the only one.
    cells = re.findall(r"<td class='num ([a-z]*)'[^>]*>(.*?)</td>", row)
    starred = [i for i, (_, text) in enumerate(cells) if "★" in text]
    labels = re.findall(r"<th><svg class='swatch'.*?</svg>([^<]+)</th>", index)
    assert [labels[i] for i in starred] == ["mujoco/mujoco.rk4"]
    best = min(abs(r["metrics"]["energy_drift_final"]) for r in runs.values() if r["status"] == "ok")
    assert best == abs(runs["mujoco/mujoco.rk4"]["metrics"]["energy_drift_final"])
    # Coloured by the case's bound as the gate's function judges it: Euler creates energy (+5 %,
    # beyond the +1 % bound); PBD dissipates it (within).
    where = {labels[i]: css for i, (css, _) in enumerate(cells)}
    assert where["mujoco/mujoco.euler"] == "beyond" and where["pbd/pbd"] == "within"
    summary = re.search(r"<tr><td><svg class='swatch'.*?</svg>mujoco/mujoco.rk4</td>(.*?)</tr>", index)
    assert summary is not None and re.findall(r">(\d+)<", summary[1])[:2] == ["1", "1"]  # runs, best


def test_every_metric_has_the_unit_docs_metrics_md_gives_it(real_results: Path) -> None:
    from pbdval.report import metric_units

    units = metric_units()
    document = json.loads((real_results / "results.json").read_text())
    assert {m for r in document["runs"] for m in r["metrics"]} <= set(units)
    text = (REPO / "docs/metrics.md").read_text()
    table = text[text.index("| name | unit | present when |"):].split("\n\n")[0]
    compared = 0
    for names, unit in re.findall(r"^\| (`[^|]*) \| ([^|,]+) \|", table, re.MULTILINE):
        for name in re.findall(r"`([a-z_]+)`", names.split("(+")[0]):
            assert units[name].split(" ")[0] == unit.split(" ")[0], name
            compared += 1
    assert compared >= 20


def tampered_baseline(real_results: Path, tmp_path: Path) -> Path:
    """A baseline of the real run, edited so that against it the run shows one of each verdict:
    joint_hinge pbd/pbd's trajectory error twice its baseline (a regression) and pbd.xpbd's 5 %
    above it (tolerated: trajectory errors allow 10 %), joint_distance pbd's joint error 4x below
    it (an improvement), a run the baseline lacks (new) and one of joint_distance the results lack
    (missing)."""
    baseline = tmp_path / "baseline.json"
    pbdval("baseline", "--results", str(real_results), "--out", str(baseline))
    document = json.loads(baseline.read_text())
    runs = document["runs"]
    hinge = next(r for r in runs if r["case"] == "joint_hinge" and r["method"] == "pbd")
    hinge["metrics"]["trajectory_error_max"] /= 2
    xpbd = next(r for r in runs if r["case"] == "joint_hinge" and r["method"] == "pbd.xpbd")
    xpbd["metrics"]["trajectory_error_max"] /= 1.05
    plain = next(r for r in runs if r["case"] == "joint_distance" and r["method"] == "pbd")
    plain["metrics"]["joint_error_linear_max"] *= 4
    runs.remove(next(r for r in runs if r["case"] == "joint_distance" and r["engine"] == "bullet"))
    runs.append(dict(plain, method="pbd.gone"))
    baseline.write_text(json.dumps(document))
    return baseline


def gate_row(index: str, verdict: str, case: str, check: str) -> str:
    """The line of a check ("RUN WHAT": "pbd/pbd trajectory_error_max") in its run's row of the
    report's changes table, or "" when there is none."""
    run, what = check.rsplit(" ", 1)
    for row in re.findall(r"<tr class='verdict-[a-z_]+'>.*?</tr>", index):
        if f"<td>{case}</td><td>{run}</td>" in row:
            for line in re.findall(rf"<div class='change verdict-{verdict}'>.*?</div>", row):
                if f"<b>{what}</b>" in line:
                    return str(line)
    return ""


def test_the_gates_verdicts_are_listed_with_their_numbers(real_results: Path, tmp_path: Path) -> None:
    baseline = tampered_baseline(real_results, tmp_path)
    report = tmp_path / "report"
    build_report(real_results, report, baseline=baseline, quiet=True)
    index = (report / "index.html").read_text()
    # The counts on top: the regression and the missing run are the only failures, in two cases.
    assert "<b>1 regression and 1 missing in 2 cases</b>" in index
    regression = gate_row(index, "regression", "joint_hinge", "pbd/pbd trajectory_error_max")
    assert "badge fail" in regression and "×2," in regression  # the ratio to the baseline
    tolerated = gate_row(index, "tolerated_change", "joint_hinge", "pbd/pbd.xpbd trajectory_error_max")
    assert "badge warn" in tolerated and "×1.05," in tolerated
    improvement = gate_row(index, "improvement", "joint_distance", "pbd/pbd joint_error_linear_max")
    assert "badge pass" in improvement and "×0.25," in improvement
    assert "badge fail" in gate_row(index, "missing", "joint_distance", "pbd/pbd.gone present")
    assert "badge note" in gate_row(index, "new", "joint_distance", "bullet/bullet.si new")
    # The table is HTML, not the gate's Markdown as text.
    assert "| regression |" not in index and "<table class='gate'>" in index
    assert "| regression | joint_hinge | pbd/pbd trajectory_error_max |" in (report / "report.md").read_text()


def test_the_settings_that_differ_from_the_baseline_are_listed_with_their_runs(real_results: Path,
                                                                               tmp_path: Path) -> None:
    """`pbdval baseline` records each run's settings and the build's flags; a baseline edited to
    hold another subSteps for one run and other flags shows exactly those differences, and a
    baseline without settings (made before they were stored) says so instead."""
    baseline = tmp_path / "baseline.json"
    pbdval("baseline", "--results", str(real_results), "--out", str(baseline))
    document = json.loads(baseline.read_text())
    hinge = next(r for r in document["runs"] if r["case"] == "joint_hinge" and r["method"] == "pbd")
    now = hinge["settings"]["subSteps"]
    hinge["settings"]["subSteps"] = now + "0"
    document["source"]["flags"] = "-O0"
    baseline.write_text(json.dumps(document))
    index = build_report(real_results, tmp_path / "report", baseline=baseline, quiet=True).read_text()
    table = index[index.index("Settings that differ from the baseline"):]
    rows = re.findall(r"<tr><td>([^<]*)</td><td>([^<]*)</td><td>([^<]*)</td><td>([^<]*)</td></tr>", table)
    assert rows == [("subSteps", now + "0", now, "1: joint_hinge pbd/pbd")]
    assert "<b>flags</b> -O0 → " in table
    for run in document["runs"]:
        run.pop("settings", None)
    baseline.write_text(json.dumps(document))
    index = build_report(real_results, tmp_path / "old", baseline=baseline, quiet=True).read_text()
    assert "the baseline records no run's settings" in index


def test_gate_text_junit_markdown_and_report_count_the_same_failures(real_results: Path, tmp_path: Path) -> None:
    """A manufactured regression: every metric of one case's runs 100x worse in a copy of the
    results. The gate's text, JUnit, Markdown and JSON and the report's counts all equal the
    number of checks the gate's verdict function flagged (those listed as regression or missing)."""
    baseline = tmp_path / "baseline.json"
    pbdval("baseline", "--results", str(real_results), "--out", str(baseline))
    worse = tmp_path / "worse"
    worse.mkdir()
    document = json.loads((real_results / "results.json").read_text())
    for run in document["runs"]:
        if run["case"] == "joint_hinge":
            run["metrics"] = {k: (v * 100 if isinstance(v, float) else v) for k, v in run["metrics"].items()}
    (worse / "results.json").write_text(json.dumps(document))
    files = {kind: tmp_path / f"gate.{kind}" for kind in ("json", "xml", "md")}
    done = pbdval("gate", "--baseline", str(baseline), "--results", str(worse), "--json", str(files["json"]),
                  "--junit", str(files["xml"]), "--markdown", str(files["md"]), check=False)
    assert done.returncode == 1, done.stderr
    verdicts = json.loads(files["json"].read_text())
    flagged = sum(1 for c in verdicts["checks"] if c["verdict"] in ("regression", "missing"))
    assert flagged > 0 and {c["case"] for c in verdicts["checks"] if c["verdict"] == "regression"} == {"joint_hinge"}
    assert verdicts["counts"]["failed"] == flagged
    text = done.stdout
    assert len(re.findall(r"^FAIL ", text, re.MULTILINE)) == flagged
    assert f", {flagged} failed in 1 case (" in text.splitlines()[-1]
    junit = files["xml"].read_text()
    failures = re.search(r'<testsuites [^>]*failures="(\d+)"', junit)
    assert failures is not None and failures.group(1) == str(flagged)
    assert junit.count("<failure ") == flagged
    markdown = files["md"].read_text()
    assert len(re.findall(r"^\| (regression|missing) \|", markdown, re.MULTILINE)) == flagged
    assert f", {flagged} failed in 1 case (" in markdown
    # The report, running the gate itself or showing the verdicts of the gate above.
    for name, gate_baseline, gate_json in (("report", baseline, None), ("shown", None, files["json"])):
        build_report(worse, tmp_path / name, quiet=True, baseline=gate_baseline, gate_json=gate_json)
        index = (tmp_path / name / "index.html").read_text()
        lines = re.findall(r"<div class='change verdict-(regression|missing)'>", index)
        assert len(lines) == flagged, name
        # One row per run: every run of joint_hinge has a regression, and no other run.
        rows = re.findall(r"<tr class='verdict-regression'><td>.*?</td><td>([a-z_]+)</td>", index)
        assert rows and set(rows) == {"joint_hinge"}, name
        assert f"<b>{flagged} regressions and 0 missing in 1 case</b>" in index, name
        assert verdicts["summary"] in index, name
        assert f"{flagged} failed in 1 case" in (tmp_path / name / "report.md").read_text(), name


def test_a_file_that_is_not_gate_verdicts_is_a_clear_error(real_results: Path, tmp_path: Path) -> None:
    wrong = tmp_path / "gate.json"
    wrong.write_text(json.dumps({"schema": "pbdval-results", "schemaVersion": 1}))
    done = pbdval("report", str(real_results), "--out", str(tmp_path / "r"), "--gate-json", str(wrong), check=False)
    assert done.returncode == 2
    assert f"{wrong}: not the verdicts of pbdval gate --json" in done.stderr
    # Nothing was written before the verdicts were read (a missing file too).
    assert not (tmp_path / "r").exists()
    missing = pbdval("report", str(real_results), "--out", str(tmp_path / "m"), "--gate-json",
                     str(tmp_path / "no_such_gate.json"), check=False)
    assert missing.returncode == 2 and "no_such_gate.json" in missing.stderr
    assert not (tmp_path / "m").exists()


def test_sweep_writes_its_convergence_page(tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    done = pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "timeStepSize=0.01,0.005,0.0025",
                  "--methods", "pbd", "--out", str(out), "--report", "--quiet")
    assert done.stdout.strip().endswith(str(out / "report/convergence.html"))
    page = (out / "report/convergence.html").read_text()
    assert "projectile" in page and "p = " in page and "Pareto front" in page
    assert "href='index.html'" not in page  # on its own: no links to pages that do not exist
    # Each point's wall time is the median of three passes (the default --repeat), each kept.
    for point in json.loads((out / "sweep.json").read_text())["points"]:
        times = sorted(point["wall_times_s"])
        assert len(times) == 3 and point["wall_time_s"] == times[1]
    assert "the median of its 3 passes" in page and 'class="spread"' in page
    assert "trajectory_error_max (m)" in page and "timeStepSize (s)" in page  # both axes with units
    done = pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "timeStepSize=0.01", "--methods", "pbd",
                  "--out", str(tmp_path / "none"), "--repeat", "0", check=False)
    assert done.returncode == 2 and "--repeat" in done.stderr


def test_sweep_with_a_held_setting_and_a_floor_fit_draws_one_parameter(tmp_path: Path) -> None:
    out = tmp_path / "floor"
    pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "maxIterations=2",
           "--param", "timeStepSize=0.01,0.005,0.0025,0.00125", "--methods", "pbd", "--fit", "floor",
           "--repeat", "1", "--out", str(out), "--report", "--quiet")
    fit = json.loads((out / "sweep.json").read_text())["fits"][0]
    assert fit["model"] == "power_plus_floor" and "floor" in fit
    assert list(fit["orders"]) == ["timeStepSize"]  # the held setting is not fitted
    page = (out / "report/convergence.html").read_text()
    assert "timeStepSize (s)" in page and "a grid of several parameters" not in page
    done = pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "timeStepSize=0.01,0.005",
                  "--methods", "pbd", "--fit", "offset", "--out", str(tmp_path / "bad"), check=False)
    assert done.returncode == 2 and "--fit: expected power or floor, got 'offset'" in done.stderr


def test_sweep_along_a_path_fits_its_coordinate_and_draws_it(tmp_path: Path) -> None:
    """--together timeStepSize,subSteps halves the step and doubles the substeps at once: PBD's
    projectile error is its integration step h/n times g t/2 (first order, exactly:
    convergence.md), and h/n falls as h², so the order in the path's coordinate h is 2."""
    out = tmp_path / "path"
    pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "timeStepSize=0.01,0.005,0.0025",
           "--param", "subSteps=1,2,4", "--together", "timeStepSize,subSteps", "--methods", "pbd",
           "--repeat", "1", "--out", str(out), "--report", "--quiet")
    document = json.loads((out / "sweep.json").read_text())
    assert document["together"] == ["timeStepSize", "subSteps"]
    assert [(p["parameters"]["timeStepSize"], p["parameters"]["subSteps"]) for p in document["points"]] == [
        ("0.01", "1"), ("0.005", "2"), ("0.0025", "4")]  # a path of three points, not a grid of nine
    fit = document["fits"][0]
    assert list(fit["orders"]) == ["timeStepSize"]
    assert fit["orders"]["timeStepSize"]["order"] == pytest.approx(2.0, abs=0.01)  # 1.000 per step: 2 here
    page = (out / "report/convergence.html").read_text()
    assert "timeStepSize (s)" in page and "a grid of several parameters" not in page
    done = pbdval("sweep", str(REPO / "cases/projectile.json"), "--param", "timeStepSize=0.01,0.005",
                  "--param", "subSteps=1,2,4", "--together", "timeStepSize,subSteps", "--methods", "pbd",
                  "--out", str(tmp_path / "bad"), check=False)
    assert done.returncode == 2
    assert "--together: --param subSteps has 3 values and --param timeStepSize 2" in done.stderr


def synthetic(folder: Path, runs: list[dict[str, Any]], schema_version: int = 1, case_file: str = "") -> Path:
    folder.mkdir(parents=True)
    cases = {r["case"]: {"file": case_file, "description": "synthetic", "checks": [], "tolerances": {}}
             for r in runs}
    (folder / "results.json").write_text(json.dumps({
        "schema": "pbdval-results", "schemaVersion": schema_version, "metadata": {}, "cases": cases, "runs": runs}))
    return folder


def run_record(case: str, engine: str, method: str, status: str, metrics: dict[str, Any],
               trajectory: str = "") -> dict[str, Any]:
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


def test_a_suspect_run_shows_its_metric_and_its_reason(tmp_path: Path) -> None:
    """A suspect run completed and was measured: the overview shows its value marked suspect
    (its reason as the tooltip), and its case page lists it under the runs held suspect, apart
    from the runs that did not complete."""
    runs = [run_record("a", "pbd", "pbd", "ok", {"energy_drift_max": 0.01}),
            run_record("a", "bullet", "bullet.si", "suspect", {"energy_drift_max": 17.6}),
            run_record("a", "ode", "ode.quickstep", "diverged", {})]
    folder = synthetic(tmp_path / "results", runs, case_file=str(tmp_path / "no-such-scene.json"))
    index = build_report(folder, tmp_path / "report", quiet=True).read_text()
    cell = re.search(r"<td class='num [a-z]+' title='([^']*)'><span class='v'>17.6(.*?)</td>", index)
    assert cell is not None and "synthetic suspect" in cell[1] and "badge warn'>suspect<" in cell[2]
    page = (tmp_path / "report/cases/a.html").read_text()
    held = page[page.index("Runs held suspect"):]
    assert "bullet/bullet.si" in held.split("Runs that did not complete")[0]
    assert "ode/ode.quickstep" in page[page.index("Runs that did not complete"):]


def test_report_cases_covers_those_cases_and_gates_only_them(real_results: Path, tmp_path: Path) -> None:
    """`report --cases joint_hinge`: the other case of the results has no page and no row, and the
    gate (against the full library's baseline) lists none of the baseline's other 51 cases as
    missing runs — only this case's runs of engines the results lack (pbd and bullet ran, so the
    baseline's mujoco/ode/... runs of joint_hinge are missing, and nothing of joint_distance)."""
    report = tmp_path / "report"
    pbdval("report", str(real_results), "--out", str(report), "--cases", "joint_hinge", "--baseline",
           str(REPO / "reports/baselines/main.json"))
    index = (report / "index.html").read_text()
    assert "cases/joint_hinge.html" in index and (report / "cases/joint_hinge.html").is_file()
    # (the run's command line in the metadata still names both cases' files)
    assert "cases/joint_distance.html" not in index and not (report / "cases/joint_distance.html").exists()
    assert " in 1 case</b>" in index
    gate_rows = re.findall(r"<tr class='verdict-[a-z_]+'><td><span class='badge [a-z]+'>[^<]*</span></td>"
                           r"<td>([a-z0-9_]+)</td>", index)
    assert gate_rows and set(gate_rows) == {"joint_hinge"}


def test_report_cases_with_an_unknown_name_is_a_clear_error(real_results: Path, tmp_path: Path) -> None:
    done = pbdval("report", str(real_results), "--out", str(tmp_path / "r"), "--cases", "joint_hinje", check=False)
    assert done.returncode == 2
    assert "no case 'joint_hinje'" in done.stderr and "did you mean joint_hinge" in done.stderr
    assert not (tmp_path / "r").exists()


def test_every_declared_method_has_a_style_of_its_own_fixed_by_the_registry() -> None:
    """The palette is a function of the registry's declaration: every (engine, method) pair the
    registry declares gets a distinct (colour, dash); a label with assignments keeps its method's
    style; a sweep's bare method name gets its engine/method's style; asking in another order
    gives the same answers."""
    from pbdval.palette import declared_engines, style_of_label

    pairs = [(engine, method) for engine, methods in declared_engines() for method in methods]
    styles = [style_of_label(f"{engine}/{method}") for engine, method in pairs]
    assert len({(s.colour, s.dash) for s in styles}) == len(pairs)
    assert [style_of_label(f"{e}/{m}") for e, m in reversed(pairs)] == list(reversed(styles))
    assert style_of_label("pbd/pbd.xpbd [timeStepSize=0.01]") == style_of_label("pbd/pbd.xpbd")
    assert style_of_label("ode.quickstep") == style_of_label("ode/ode.quickstep")
    assert style_of_label("gone/gone.euler").colour == "#999999"  # an engine the registry does not declare
