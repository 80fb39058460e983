"""The numbers README.md and docs/ state about the case library cannot go stale: each is checked
against the plan `scripts/validate` runs (`pbdval run cases --engines … --list-plan`) and the committed baseline
(reports/baselines/main.json), recomputed from them by the rules docs/gate.md states, never
copied from a run's output."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path
from typing import Any

import pytest

from pbdval.results import pbdval_binary

REPO = Path(__file__).resolve().parents[2]
BASELINE = REPO / "reports/baselines/main.json"
#: How README.md writes small counts ("in six engines").
NUMBER_WORDS = {"two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8, "nine": 9,
                "ten": 10, "eleven": 11, "twelve": 12}
#: Metrics the gate does not compare unless a case's tolerances name them (docs/gate.md, default
#: tolerances: the normalisations *_scale and the timing metrics).
UNGATED = ("wall_time_s", "steps", "real_time_factor")


@pytest.fixture(scope="module")
def plan() -> dict[str, Any]:
    # The plan scripts/validate runs: its engines are declared there (validated_engines=...).
    declared = re.search(r"^validated_engines=(\S+)$", (REPO / "scripts" / "validate").read_text(encoding="utf-8"),
                         re.MULTILINE)
    assert declared, "scripts/validate no longer declares validated_engines=..."
    done = subprocess.run([str(pbdval_binary()), "run", "cases", "--engines", declared[1], "--list-plan"], cwd=REPO,
                          capture_output=True, text=True, check=True)
    document: dict[str, Any] = json.loads(done.stdout)
    return document


@pytest.fixture(scope="module")
def baseline() -> dict[str, Any]:
    document: dict[str, Any] = json.loads(BASELINE.read_text(encoding="utf-8"))
    return document


def run_keys(runs: list[dict[str, Any]]) -> set[tuple[str, str, str, tuple[str, ...]]]:
    return {(r["case"], r["engine"], r["method"], tuple(r.get("assignments", []))) for r in runs}


def gate_checks(baseline: dict[str, Any]) -> int:
    """How many checks `pbdval gate` makes when results hold exactly the baseline's runs with
    their statuses (docs/gate.md, "What is checked"): one status check per run; one comparison
    per gated metric of each completed (ok or suspect) run; one per case bound and matching ok
    run; one per ordering."""
    cases = baseline["cases"]
    count = 0
    for run in baseline["runs"]:
        count += 1
        if run["status"] in ("ok", "suspect"):
            tolerated = cases[run["case"]].get("tolerances", {})
            count += sum(1 for m in run["metrics"]
                         if m in tolerated or not (m.endswith("_scale") or m in UNGATED))
    for case, data in cases.items():
        for check in data["checks"]:
            if "better" in check:
                count += 1
                continue
            count += sum(1 for r in baseline["runs"] if r["case"] == case and r["status"] == "ok"
                         and (not check.get("engines") or r["engine"] in check["engines"])
                         and (not check.get("methods") or r["method"] in check["methods"]))
    return count


def test_the_committed_baseline_holds_exactly_the_plans_runs(plan: dict[str, Any], baseline: dict[str, Any]) -> None:
    assert run_keys(plan["runs"]) == run_keys(baseline["runs"])
    assert plan["planSize"] == len(plan["runs"])


def test_the_readme_counts_cases_runs_and_engines_of_the_plan(plan: dict[str, Any]) -> None:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    found = re.search(r"The full library \((\d+) cases, (\d+) runs in (\w+) engines", text)
    assert found, "README.md no longer states the library's size as '(N cases, M runs in K engines'"
    cases, runs, engines = int(found[1]), int(found[2]), NUMBER_WORDS.get(found[3], -1)
    assert cases == len({r["case"] for r in plan["runs"]})
    assert runs == plan["planSize"]
    assert engines == len({r["engine"] for r in plan["runs"]})


def test_the_readme_gate_line_counts_the_checks_and_known_failures_of_the_baseline(
        baseline: dict[str, Any]) -> None:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    found = re.search(r"pbdval gate: passed \((\d+) checks, 0 failed; (\d+) known failures", text)
    assert found, "README.md no longer shows the gate's line on the whole library"
    assert int(found[1]) == gate_checks(baseline)
    # Known failures: the case checks that failed in the baseline's results, and the runs
    # suspect there (a run suspect in the baseline and now is a known failure, docs/gate.md).
    suspect = sum(1 for r in baseline["runs"] if r["status"] == "suspect")
    assert int(found[2]) == len(baseline["knownFailures"]) + suspect


def test_the_report_page_counts_the_library_of_the_plan(plan: dict[str, Any]) -> None:
    text = (REPO / "docs/report.md").read_text(encoding="utf-8")
    found = re.search(r"The whole case library's report \((\d+) runs, (\d+) cases", text)
    assert found, "docs/report.md no longer states the size of the library it measured"
    assert int(found[1]) == plan["planSize"]
    assert int(found[2]) == len({r["case"] for r in plan["runs"]})


#: Superscript digits and minus as docs/ write exponents ("2.0·10⁻³").
SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def documented_figure(text: str) -> tuple[float, float]:
    """A figure as the docs write it ("−5.33", "+0.40", "2.0·10⁻³") and half a unit of its last digit."""
    mantissa, _, exponent = text.replace("−", "-").partition("·10")
    power = int(exponent.translate(SUPERSCRIPTS)) if exponent else 0
    decimals = len(mantissa.partition(".")[2])
    return float(mantissa) * 10.0**power, 0.5 * 10.0 ** (power - decimals)


def test_the_rod_helix_figures_in_methods_are_the_baselines(baseline: dict[str, Any]) -> None:
    text = " ".join((REPO / "docs/methods.md").read_text(encoding="utf-8").split())
    start = text.find("The case `cases/rod_helix.json`")
    assert start >= 0, "docs/methods.md no longer describes cases/rod_helix.json"
    paragraph = text[start:text.find("The case checks the final drift only.", start)]
    figure = r"([−+]?[\d.]+(?:·10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?)"
    pattern = (rf"`{{method}}`(?: \([^)]*\))? energy_drift_final {figure} %, energy_drift_max {figure} %, "
               rf"particle_stretch_max {figure}")
    for method in ("pbd", "pbd.xpbd"):
        found = re.search(pattern.format(method=re.escape(method)), paragraph)
        assert found, f"docs/methods.md no longer gives rod_helix's figures for {method} in the checked form"
        run = next(r for r in baseline["runs"]
                   if r["case"] == "rod_helix" and r["engine"] == "pbd" and r["method"] == method)
        # Drifts are written in per cent, the stretch as a fraction (docs/metrics.md).
        for written, metric, scale in zip(found.groups(), ("energy_drift_final", "energy_drift_max",
                                                           "particle_stretch_max"), (100.0, 100.0, 1.0)):
            value, half_unit = documented_figure(written)
            measured = run["metrics"][metric] * scale
            # The docs round to the digits they show: the baseline's value is within half a unit
            # of the last one (plus the binary round-off of that comparison).
            assert abs(measured - value) <= half_unit * (1 + 1e-9), f"{method} {metric}: {written} vs {measured}"
