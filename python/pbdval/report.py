"""`pbdval report RESULTS_DIR [--out DIR] [--baseline FILE] [--sweeps DIR...]` (docs/report.md).

A static, self-contained, offline report of a results folder: `index.html` (the overview: the
ranking of cases × engine/method by each case's deciding metric with its unit, the best marked,
coloured by the case's own bounds, with status and verdict badges, and a summary per engine;
the gate's changes by run and the settings that differ from the baseline when one is given;
the run's metadata), one page per case (its metrics, every metric over time of every run
overlaid, the 3D replay of every model kind, each engine's effective settings), one
convergence page per sweep (error against the swept parameter, log-log, with the fitted order,
R², the local orders, the points left out and the flags; error against wall time with the
Pareto front), every figure a standalone SVG file in one palette (python/pbdval/palette.py);
and `report.md`, the same overview for a pull request. Nothing here computes a metric or
decides a check: the numbers come from results.json, the series from the suite's own code
(`pbdval.measure`), the units from validation/measure/metrics.h, every verdict and every bound from the
gate's functions (`pbdval gate --json`, or `evaluateCaseChecks` through pbdval._core).
"""

from __future__ import annotations

import argparse
import difflib
import functools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from html import escape
from pathlib import Path
from typing import Any

import numpy as np

from pbdval.errors import PbdvalError, ResultsError
from pbdval.palette import declared_engines, engine_of_method, style_of_label
from pbdval.replay import replay_data, replay_script
from pbdval.results import Results, RunResult, load_results, pbdval_binary
from pbdval.svg import Series, line_plot

#: The report's browser code: three.js from npm (python/pbdval/web, `npm ci` by
#: scripts/install-deps) and the replay viewer, copied into the report's assets/.
WEB = Path(__file__).resolve().parent / "web"
THREE_FILES = {"three.min.js": "node_modules/three/build/three.min.js",
               "OrbitControls.js": "node_modules/three/examples/js/controls/OrbitControls.js",
               "three-LICENSE.txt": "node_modules/three/LICENSE"}

STATUS_COLOURS = {"ok": "#d9f2d9", "suspect": "#ffc8a0", "unsupported": "#eeeeee", "diverged": "#ffd9b3",
                  "timeout": "#ffe9a8", "error": "#f7c6c6"}
#: Points per series in a time plot (every k-th sample beyond it: a 600-pixel-wide figure shows no
#: more, and a 39-case report stays small).
MAX_PLOT_POINTS = 400

CSS = """
body { font-family: Helvetica, Arial, sans-serif; margin: 24px; color: #222; }
table { border-collapse: collapse; font-size: 12px; }
th, td { border: 1px solid #ccc; padding: 3px 6px; text-align: left; vertical-align: top; }
th { background: #f4f4f4; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.badge { display: inline-block; padding: 1px 6px; border-radius: 8px; font-size: 11px; margin-left: 4px; }
.warn { background: #ffe9a8; } .fail { background: #f7c6c6; } .pass { background: #d9f2d9; }
.known { background: #e4e4e4; } .note { background: #dbe8f7; }
figure { margin: 12px 0; } figcaption { font-size: 12px; color: #555; }
nav a { margin-right: 12px; }
pre { background: #f7f7f7; padding: 8px; overflow-x: auto; font-size: 12px; }
.replay-controls { margin: 6px 0; font-size: 13px; } .replay-legend label { margin-right: 14px; font-size: 12px; }
.swatch { display: inline-block; width: 12px; height: 12px; margin: 0 4px; vertical-align: middle; }
.scroll { overflow-x: auto; max-width: 100%; margin: 6px 0; }
figure svg { max-width: 100%; height: auto; }
td.within { background: #d9f2d9; } td.near { background: #ffe9a8; } td.beyond { background: #f7c6c6; }
td.unbounded { background: #ffffff; } .best { font-weight: bold; color: #0b5d1e; }
th .unit { font-weight: normal; color: #555; }
table.ranking .v { white-space: nowrap; } table.ranking .badge { margin: 1px 0 1px 4px; }
table.ranking th.metric { max-width: 13em; font-size: 11px; }
"""


def nav(prefix: str = "") -> str:
    """The links between the report's pages; `prefix` leads from a subfolder ("../")."""
    return (f"<nav><a href='{prefix}index.html'>overview</a><a href='{prefix}convergence.html'>convergence</a>"
            f"<a href='{prefix}parity.html'>parity</a></nav>")


def page(title: str, body: str) -> str:
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>{escape(title)}</title>'
            f"<style>{CSS}</style></head><body>\n{body}\n</body></html>\n")


def number(value: float | None) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    return f"{value:.3g}"


def slug(text: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in text)


class Colours:
    """The report's styles: the palette's (python/pbdval/palette.py), fixed by the registry's
    engines and methods, never by the order in which this report meets its runs."""

    def of(self, label: str) -> str:
        return style_of_label(label).colour

    def series(self, label: str, x: Sequence[float], y: Sequence[float], *, style_label: str | None = None,
               markers: bool = False, hollow: Sequence[bool] = (), point_labels: Sequence[str] = (),
               x_spread: Sequence[tuple[float, float]] = ()) -> Series:
        """A plot series of `label` in its palette style (`style_label`'s, when given)."""
        style = style_of_label(style_label or label)
        return Series(label, x, y, style.colour, markers=markers, hollow=list(hollow), dash=style.dash,
                      marker=style.marker, point_labels=list(point_labels), x_spread=list(x_spread))


@functools.lru_cache(maxsize=1)
def metric_units() -> dict[str, str]:
    """Every metric's unit, as validation/measure/metrics.h declares it (metric::declared())."""
    from pbdval import _core  # the C++ core, imported only here

    return {str(k): str(v) for k, v in _core._metric_units().items()}


def wall_time_range(point: dict[str, Any]) -> tuple[float, float]:
    """The range of a sweep point's wall times over its passes (`pbdval sweep --repeat`; a sweep
    of one pass: its one wall time)."""
    times = [float(t) for t in point.get("wall_times_s") or [point["wall_time_s"]]]
    return min(times), max(times)


def metric_label(metric: str) -> str:
    """"trajectory_error_max (m)": a metric with its declared unit."""
    unit = metric_units().get(metric)
    return f"{metric} ({unit})" if unit else metric


def parameter_label(name: str, methods: Sequence[str]) -> str:
    """A swept parameter with its unit: the unit the methods' registry declares for it, "s"
    for the scene's time step (docs/scene-format.md), none for a count."""
    from pbdval.api import engines  # the C++ core, imported only here

    if name == "timeStepSize":
        return f"{name} (s)"
    for engine in engines():
        for method in engine.methods:
            if method.name in methods:
                for parameter in method.parameters:
                    if parameter.name == name and parameter.unit:
                        return f"{name} ({parameter.unit})"
    return f"{name} (count)" if name.lower().endswith(("steps", "iterations", "substeps")) else name


def thin(times: Any, values: Any) -> tuple[list[float], list[float]]:
    """At most MAX_PLOT_POINTS points of a series for a plot (the data is not changed): from each
    window of consecutive samples, the one farthest from zero, so that a short spike (an impact's
    penetration) survives the thinning."""
    t, v = np.asarray(times, dtype=np.float64), np.asarray(values, dtype=np.float64)
    stride = max(1, -(-len(t) // MAX_PLOT_POINTS))
    if stride == 1:
        return t.tolist(), v.tolist()
    picked = []
    for start in range(0, len(t), stride):
        window = np.abs(v[start:start + stride])
        picked.append(start + (int(np.nanargmax(window)) if np.isfinite(window).any() else 0))
    return t[picked].tolist(), v[picked].tolist()


def write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(text, encoding="utf-8")
    os.replace(temporary, path)


def progress(message: str, quiet: bool) -> None:
    if not quiet:
        print(message, file=sys.stderr, flush=True)


#: The metric series of a case page, in this order: (label, unit, logarithmic axis).
SERIES_ORDER = ("trajectory_error", "rotation_error", "joint_error_linear", "joint_error_angular",
                "motor_tracking", "penetration")
SERIES_LABELS = {"trajectory_error": ("trajectory error", "m", True), "rotation_error": ("rotation error", "rad", True),
                 "joint_error_linear": ("joint error, linear", "m", True),
                 "joint_error_angular": ("joint error, angular", "rad", True),
                 "motor_tracking": ("motor tracking error", "", True), "penetration": ("penetration", "m", False)}
SERIES_CAPTIONS = {
    "trajectory_error": "Largest distance of a compared body from the reference, per sample "
                        "(trajectory_error_max is its maximum; docs/metrics.md).",
    "rotation_error": "Largest geodesic angle of a compared body from the reference, per sample.",
    "joint_error_linear": "Largest anchor separation over the joints of this type, per sample "
                          "(zero, exact joints, is off the logarithmic axis).",
    "joint_error_angular": "Largest angular error over the joints of this type, per sample.",
    "motor_tracking": "Largest |set point − achieved| over the motors of this kind, per sample "
                      "(rad, rad/s, m or m/s by kind; the first sample is not yet tracked).",
    "penetration": "Deepest overlap of any body pair (FCL, the engine's margin subtracted), per sample.",
}


# ---- the gate ------------------------------------------------------------------------------------


@dataclass
class GateVerdicts:
    """`pbdval gate`'s verdicts on a results folder (docs/gate.md#json): the report prints them
    and decides nothing. `document` is None when the gate could not judge (exit status 2; `error`
    says why)."""

    status: int  #: the gate's exit status: 0 passed, 1 failed, 2 could not judge
    document: dict[str, Any] | None
    error: str


def run_gate(results_dir: Path, baseline: Path, cases: Sequence[str] | None = None) -> GateVerdicts:
    """Runs `pbdval gate --json` on the results against the baseline (on `cases` only, when
    given: the gate's own --cases, so the other cases' runs are not "missing")."""
    with tempfile.TemporaryDirectory() as folder:
        verdicts = Path(folder) / "gate.json"
        only = ["--cases", ",".join(cases)] if cases else []
        done = subprocess.run([str(pbdval_binary()), "gate", "--baseline", str(baseline), "--results",
                               str(results_dir), "--json", str(verdicts), "--quiet", *only],
                              capture_output=True, text=True, check=False)
        document = json.loads(verdicts.read_text(encoding="utf-8")) if verdicts.exists() else None
    return GateVerdicts(done.returncode, document, done.stderr.strip())


def read_gate_json(path: Path) -> GateVerdicts:
    """The verdicts a `pbdval gate --json` wrote (scripts/validate: what CI gated, with its
    options). Raises ResultsError naming the file when it is not such a file."""
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(document, dict) or document.get("schema") != "pbdval-gate" \
                or document.get("schemaVersion") != 1:
            raise ValueError('expected "schema": "pbdval-gate", "schemaVersion": 1')
        passed = bool(document["passed"])
    except (OSError, ValueError, KeyError) as error:
        raise ResultsError(f"{path}: not the verdicts of pbdval gate --json ({error})") from error
    return GateVerdicts(0 if passed else 1, document, "")


#: How the report draws each verdict, most severe first: (label, badge class).
VERDICT_STYLE = {"regression": ("regression", "fail"), "missing": ("missing", "fail"),
                 "known_failure": ("known failure", "known"), "tolerated_change": ("tolerated change", "warn"),
                 "improvement": ("improvement", "pass"), "new": ("new", "note")}


def plural(count: int, one: str, many: str) -> str:
    return f"{count} {one if count == 1 else many}"


def gate_headline(counts: dict[str, Any]) -> str:
    """"3 regressions and 1 missing in 2 cases", or "no failed check", from the gate's counts."""
    verdicts = counts["verdicts"]
    if not counts["failed"]:
        return "no failed check"
    return (f"{plural(verdicts['regression'], 'regression', 'regressions')} and {verdicts['missing']} missing "
            f"in {plural(counts['failingCases'], 'case', 'cases')}")


def gate_section(gate: GateVerdicts, baseline: Path | None, results: Results) -> tuple[str, str]:
    """The gate's verdict and counts, then every run with a check that is not a plain pass, one
    row per run (its worst verdict, each changed metric with its ratio to the baseline), then
    what differs between the run and the baseline's settings (HTML and Markdown)."""
    verdict = {0: ("passed", "pass"), 1: ("FAILED", "fail")}.get(gate.status, ("could not judge", "warn"))
    html = [f"<h2>Gate <span class='badge {verdict[1]}'>{verdict[0]}</span></h2>"]
    md = [f"## Gate: {verdict[0]}", ""]
    if gate.document is None:
        html.append(f"<p class='badge warn'>{escape(gate.error)}</p>")
        return "\n".join(html), "\n".join(md + [gate.error, ""]) + "\n"
    document = gate.document
    headline = gate_headline(document["counts"])
    against = f"; baseline <code>{escape(str(baseline))}</code>" if baseline else ""
    html.append(f"<p class='gate-counts'><b>{escape(headline)}</b>. {escape(document['summary'])}{against}.</p>")
    md += [f"**{headline}**", ""]
    by_run: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for check in document["checks"]:
        if check["verdict"] != "pass" and check["case"] in results.cases:
            by_run.setdefault((str(check["case"]), str(check.get("run") or "(case)")), []).append(check)
    if by_run:
        html.append("<h3>Changes by run</h3><div class='scroll'><table class='gate'><tr><th>verdict</th><th>case</th>"
                    "<th>run</th><th>what changed (now, baseline, ratio now / baseline, allowed)</th></tr>")
        order = sorted(by_run.items(), key=lambda item: (min(VERDICT_ORDER.index(c["verdict"]) for c in item[1]),
                                                          item[0]))
        for (case, run), checks in order:
            worst = min((c["verdict"] for c in checks), key=VERDICT_ORDER.index)
            label, css = VERDICT_STYLE[worst]
            lines = []
            for check in sorted(checks, key=lambda c: VERDICT_ORDER.index(c["verdict"])):
                before, now = check.get("baseline"), check.get("now")
                ratio = f", ×{now / before:.3g}" if before not in (None, 0) and now is not None else ""
                what = check.get("metric") or check["name"].removeprefix(f"{run} ")
                allowed = f", allowed {number(check['allowed'])}" if check.get("allowed") is not None else ""
                name, badge = VERDICT_STYLE[check["verdict"]]
                lines.append(f"<div class='change verdict-{check['verdict']}'><span class='badge {badge}'>"
                             f"{escape(name)}</span> <b>{escape(what)}</b>: "
                             + (f"{number(now)} (baseline {number(before)}{ratio}{allowed})" if now is not None
                                else escape(check["message"])) + "</div>")
            html.append(f"<tr class='verdict-{worst}'><td><span class='badge {css}'>{label}</span></td>"
                        f"<td>{escape(case)}</td><td>{escape(run)}</td><td>{''.join(lines)}</td></tr>")
        html.append("</table></div>")
    if document["notes"]:
        html.append("<p><b>Notes:</b></p><ul>" + "".join(f"<li>{escape(n)}</li>" for n in document["notes"]) + "</ul>")
    settings_html, settings_md = settings_changes(results, baseline)
    html.append(settings_html)
    # report.md is Markdown: the gate's own summary goes in as it is, under this page's heading.
    md.append(re.sub(r"\A# [^\n]*\n+", "", document["markdown"]))
    md += settings_md
    return "\n".join(html), "\n".join(md) + "\n"


#: The build and machine facts a baseline records (its "source") and the results' metadata
#: that they are compared with.
BUILD_FACTS = (("commit", ("pbdval", "commit")), ("compiler", ("pbdval", "compiler")),
               ("buildType", ("pbdval", "buildType")), ("flags", ("pbdval", "flags")),
               ("precision", ("pbdval", "precision")), ("machine", ("machine", "cpu")),
               ("planDigest", ("planDigest",)))


def settings_changes(results: Results, baseline: Path | None) -> tuple[str, list[str]]:
    """What differs between the results and the baseline they were gated against: the build
    (commit, compiler, flags, precision, machine) and each run's effective settings and method
    parameters (recorded by `pbdval baseline` since baselines store them), each difference once
    with the runs it concerns."""
    head = "<h3>Settings that differ from the baseline</h3>"
    if baseline is None:
        return (head + "<p>Give the baseline (<code>--baseline FILE</code>) to compare the settings.</p>",
                [])
    try:
        document = json.loads(baseline.read_text(encoding="utf-8"))
        source, runs = dict(document.get("source", {})), list(document["runs"])
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as error:
        raise ResultsError(f"{baseline}: not a pbdval baseline ({error})") from error
    build = []
    for key, path in BUILD_FACTS:
        now: Any = results.metadata
        for part in path:
            now = now.get(part, "") if isinstance(now, dict) else ""
        if key in source and str(source[key]) != str(now):
            build.append((key, str(source[key]), str(now)))
    differences: dict[tuple[str, str, str], list[str]] = {}
    recorded = 0
    base_runs = {(r.get("case"), r.get("engine"), r.get("method"), tuple(r.get("assignments", []))): r
                 for r in runs if isinstance(r, dict)}
    for r in results:
        base = base_runs.get((r.case, r.engine, r.method, tuple(r.assignments)))
        if base is None or "settings" not in base:
            continue
        recorded += 1
        before = {**{f"parameter {k}": str(v) for k, v in base.get("parameters", {}).items()},
                  **{k: str(v) for k, v in base["settings"].items()}}
        after = {**{f"parameter {k}": str(v) for k, v in r.parameters.items()},
                 **{k: str(v) for k, v in r.settings.items()}}
        for key in sorted(set(before) | set(after)):
            if before.get(key) != after.get(key):
                differences.setdefault((key, before.get(key, "(not set)"), after.get(key, "(not set)")),
                                       []).append(f"{r.case} {r.label}")
    html = [head]
    md = ["", "### Settings that differ from the baseline", ""]
    if build:
        html.append("<p>Build: " + "; ".join(f"<b>{escape(k)}</b> {escape(b)} → {escape(n)}" for k, b, n in build)
                    + "</p>")
        md.append("Build: " + "; ".join(f"{k} `{b}` → `{n}`" for k, b, n in build))
    if not recorded:
        html.append("<p class='badge warn'>the baseline records no run's settings (it was made before baselines "
                    "stored them): make it again with pbdval baseline to compare them</p>")
        md.append("The baseline records no run's settings (made before baselines stored them).")
    elif not differences:
        html.append(f"<p>None: the {recorded} runs the baseline records settings for ran with the same settings.</p>")
        md.append(f"None ({recorded} runs compared).")
    else:
        html.append("<div class='scroll'><table class='settings'><tr><th>setting</th><th>baseline</th><th>now</th>"
                    "<th>runs</th></tr>")
        md += ["| setting | baseline | now | runs |", "|---|---|---|---|"]
        for (key, before_value, now_value), where in sorted(differences.items()):
            shown = ", ".join(where[:6]) + (f" and {len(where) - 6} more" if len(where) > 6 else "")
            html.append(f"<tr><td>{escape(key)}</td><td>{escape(before_value)}</td><td>{escape(now_value)}</td>"
                        f"<td>{len(where)}: {escape(shown)}</td></tr>")
            md.append(f"| {key} | {before_value} | {now_value} | {len(where)}: {shown} |")
        html.append("</table></div>")
    return "\n".join(html), md


# ---- pages ---------------------------------------------------------------------------------------


def overview(results: Results, labels: list[str], gate: tuple[str, str] | None, checks: list[dict[str, Any]],
             verdicts: dict[tuple[str, str], str], checks_note: str = "") -> tuple[str, str]:
    """The index page's body and report.md."""
    cases = sorted({r.case for r in results})
    cell: dict[tuple[str, str], RunResult] = {}
    for r in results:
        cell.setdefault((r.case, r.label), r)
    meta = results.metadata
    build = meta.get("pbdval", {})
    machine = meta.get("machine", {})
    html = [f"<h1>pbdval report</h1>{nav()}",
            (f"<p>{len(results)} runs of {len(cases)} cases. Results: <code>{escape(str(results.folder))}</code>, "
            f"created {escape(str(meta.get('created', '?')))} by <code>{escape(str(meta.get('command', '?')))}</code>; "
            f"pbdval {escape(str(build.get('version', '?')))}, commit {escape(str(build.get('commit', '?'))[:12])} "
            f"({escape(str(build.get('commitState', '?')))}), {escape(str(build.get('buildType', '')))}, "
            f"{escape(str(build.get('compiler', '')))}, <code>{escape(str(build.get('flags', '')))}</code>, "
            f"{escape(str(build.get('precision', '')))}; machine {escape(str(machine.get('hostname', '?')))} "
            f"({escape(str(machine.get('cpu', '')))}, {escape(str(machine.get('cores', '')))} cores).</p>")]
    md = ["# pbdval report", "",
          (f"{len(results)} runs of {len(cases)} cases; commit `{str(build.get('commit', '?'))[:12]}` "
           f"({build.get('commitState', '?')}), {build.get('compiler', '')}."),
          ""]
    table_html, table_md = ranking(results, labels, checks, verdicts)
    if checks_note:
        table_html = f"<p class='badge warn'>{escape(checks_note)}</p>" + table_html
    if gate is not None:  # the headline on top, the details under the ranking
        headline = gate[0].split("</p>", 1)
        html.append(headline[0] + ("</p>" if len(headline) > 1 else ""))
        html.append(table_html)
        html.append(headline[1] if len(headline) > 1 else "")
        md += [gate[1], ""]
    else:
        html.append(table_html)
    md += table_md
    return "\n".join(html), "\n".join(md) + "\n"


# ---- the ranking overview ------------------------------------------------------------------------

#: The metrics that can decide a case, in order of preference when the case's own checks bound
#: none of them: accuracy against a reference first, then constraint, contact and conservation
#: errors. Every one is an error (smaller is better).
DECIDING_METRICS = ("trajectory_error_max", "particle_trajectory_error_max", "static_displacement_error",
                    "joint_error_linear_max", "joint_error_angular_max", "motor_tracking_angle_max",
                    "motor_tracking_angular_velocity_max", "motor_tracking_position_max",
                    "motor_tracking_velocity_max", "particle_stretch_max", "tet_volume_error_max",
                    "solid_volume_error_max", "fluid_escape_max", "penetration_max", "particle_penetration_max",
                    "solid_penetration_max", "rotation_error_max", "energy_drift_max",
                    "momentum_angular_drift_max", "momentum_linear_drift_max")
#: A value within a bound but closer to it than this fraction of the bound is "near" it.
NEAR_FRACTION = 0.2
#: Two values within this relative difference are equally good (round-off; the gate's own
#: kRoundOffRelative, validation/verdict/gate.h).
SAME_RELATIVE = 1e-9
#: The gate's verdicts on a run, most severe first (the badge shows the worst).
VERDICT_ORDER = ("regression", "missing", "known_failure", "tolerated_change", "improvement", "new", "pass")
BOUND_TEXT = {"within": "within the case's bounds", "near": f"within {NEAR_FRACTION:.0%} of a bound",
              "beyond": "beyond a bound", "unbounded": "no bound on this metric"}


def case_checks(results: Results, gate: GateVerdicts | None) -> tuple[list[dict[str, Any]], str]:
    """The case checks (Validation.checks) judged on these results: the gate's (as the baseline
    pins them) when it ran, else the gate's own function on the results' checks (pbdval._core
    _case_checks, validation/verdict/gate.h evaluateCaseChecks). Each: case, run, metric, holds, now,
    allowed, message. With a note when they cannot be judged (results the gate's reader refuses:
    the report then colours no bound, and says why)."""
    if gate is not None and gate.document is not None:
        return [{**c, "holds": c["verdict"] not in ("regression", "known_failure", "missing")}
                for c in gate.document["checks"] if c.get("caseCheck")], ""
    from pbdval import _core  # the C++ core, imported only here

    try:
        checks = _core._case_checks(str(results.folder / "results.json"))
    except PbdvalError as error:
        return [], f"the cases' bounds could not be judged on these results: {error}"
    return [c for c in checks if c["case"] in results.cases], ""


def run_verdicts(gate: GateVerdicts | None) -> dict[tuple[str, str], str]:
    """(case, run label) → the gate's worst verdict on the run's checks."""
    worst: dict[tuple[str, str], str] = {}
    if gate is None or gate.document is None:
        return worst
    for check in gate.document["checks"]:
        key = (str(check["case"]), str(check.get("run", "")))
        if key[1] and (key not in worst or VERDICT_ORDER.index(check["verdict"]) < VERDICT_ORDER.index(worst[key])):
            worst[key] = check["verdict"]
    return worst


def magnitudes(runs: Sequence[RunResult], metric: str) -> list[float]:
    return [abs(r.metrics[metric]) for r in runs if r.measured and math.isfinite(r.metrics.get(metric, math.nan))]


def discriminates(values: Sequence[float]) -> bool:
    """Some value is not zero, and the values are not all equal: the metric tells runs apart
    (free_tumbling_box's trajectory error is 0 in every engine: its reference has no orientation
    and its centre of mass does not move)."""
    return bool(values) and max(values) > 0 and (len(values) == 1 or max(values) - min(values) >
                                                 SAME_RELATIVE * max(values))


def deciding_metric(case: str, runs: Sequence[RunResult], checks: Sequence[dict[str, Any]]) -> str:
    """The metric that decides a case: the metric its own bounds (Validation.checks with max or
    min) constrain on most runs, when they bound at least half of the measured runs and it tells
    runs apart; else the first of DECIDING_METRICS that tells runs apart; else the first present."""
    measured = [r for r in runs if r.measured]
    bounded: dict[str, set[str]] = {}
    for c in checks:
        if c["case"] == case and c.get("allowed") is not None and c.get("metric"):
            bounded.setdefault(str(c["metric"]), set()).add(str(c["run"]))
    for metric, bound_runs in sorted(bounded.items(), key=lambda item: -len(item[1])):
        if 2 * len(bound_runs) >= len(measured) and discriminates(magnitudes(measured, metric)):
            return metric
    for metric in DECIDING_METRICS:
        if discriminates(magnitudes(measured, metric)):
            return metric
    return next((m for m in (*bounded, *DECIDING_METRICS) if magnitudes(measured, m)), "")


def bound_class(case: str, label: str, metric: str, checks: Sequence[dict[str, Any]]) -> tuple[str, str]:
    """Where a run's value of `metric` lies against the case's bounds on it: "within", "near"
    (within NEAR_FRACTION of the bound), "beyond" (a bound that does not hold, as the gate
    judged it) or "unbounded"; with the checks' messages."""
    mine = [c for c in checks if c["case"] == case and c["run"] == label and c.get("metric") == metric
            and c.get("allowed") is not None]
    if not mine:
        return "unbounded", ""
    messages = "; ".join(str(c["message"]) for c in mine)
    if not all(c["holds"] for c in mine):
        return "beyond", messages
    near = any(c.get("now") is not None and abs(float(c["now"]) - float(c["allowed"]))
               <= NEAR_FRACTION * abs(float(c["allowed"])) for c in mine)
    return ("near" if near else "within"), messages


def ranking(results: Results, labels: list[str], checks: list[dict[str, Any]],
            verdicts: dict[tuple[str, str], str]) -> tuple[str, list[str]]:
    """The overview's table (HTML and Markdown lines): per case its deciding metric with its unit,
    each engine/method's value coloured by the case's bounds, the best marked ★, the run's status
    and the gate's verdict as badges; then the per-engine summary."""
    by_case: dict[str, list[RunResult]] = {}
    for r in results:
        by_case.setdefault(r.case, []).append(r)
    summary = {label: {k: 0 for k in ("runs", "best", "within", "near", "beyond", "unbounded", "failed",
                                      "unsupported", "suspect")} for label in labels}
    swatches = "".join(f"<th>{swatch(label)}{escape(label)}</th>" for label in labels)
    html = [("<h2>Runs</h2><p>Per case, the metric that decides it (the one its own checks bound, else the "
            "first error that tells the runs apart), with its unit; each engine/method's value, the best marked "
            "<span class='best'>★</span> (smallest magnitude among the ok runs); the colour says where the "
            "value lies against the case's bounds: <span class='badge pass'>within</span> "
            f"<span class='badge warn'>near (within {NEAR_FRACTION:.0%} of a bound)</span> "
            "<span class='badge fail'>beyond</span>, white when the case bounds no such metric; badges give a "
            "status other than ok and the gate's worst verdict on the run.</p>"),
            (f"<div class='scroll'><table class='ranking'><tr><th>case</th><th>deciding metric (unit)</th>"
             f"{swatches}</tr>")]
    md = ["## Runs", "", "Deciding metric per case (unit); ★ best; [within]/[near]/[beyond] the case's bounds.", "",
          "| case | metric (unit) | " + " | ".join(labels) + " |", "|---" * (len(labels) + 2) + "|"]
    for case in sorted(by_case):
        runs = by_case[case]
        metric = deciding_metric(case, runs, checks)
        cell = {r.label: r for r in runs}
        ok_values = [abs(r.metrics[metric]) for r in runs if r.ok and math.isfinite(r.metrics.get(metric, math.nan))]
        best = min(ok_values) if ok_values else math.nan
        unit = metric_units().get(metric, "")
        html.append(f"<tr><td><a href='cases/{slug(case)}.html'>{escape(case)}</a></td>"
                    f"<th class='metric'>{escape(metric or '–')}"
                    f"{f' <span class=unit>({escape(unit)})</span>' if unit else ''}</th>")
        row = [case, metric_label(metric) if metric else "–"]
        for label in labels:
            run = cell.get(label)
            if run is None:
                html.append("<td></td>")
                row.append("")
                continue
            counts = summary[label]
            counts["runs"] += 1
            badges = []
            if run.status == "unsupported":
                counts["unsupported"] += 1
            elif not run.measured:
                counts["failed"] += 1
            if run.status != "ok":
                counts["suspect"] += run.status == "suspect"
                css = "warn" if run.status == "suspect" else "known" if run.status == "unsupported" else "fail"
                badges.append(f"<span class='badge {css}'>{escape(run.status)}</span>")
            verdict = verdicts.get((case, label))
            if verdict and verdict != "pass":
                name, css = VERDICT_STYLE[verdict]
                badges.append(f"<span class='badge {css}'>{escape(name)}</span>")
            value = run.metrics.get(metric, math.nan) if run.measured else math.nan
            is_best = run.ok and math.isfinite(value) and abs(value) <= best * (1 + SAME_RELATIVE)
            counts["best"] += is_best
            where, messages = bound_class(case, label, metric, checks) if run.measured else ("unbounded", "")
            if run.measured:
                counts[where] += 1
            text = number(value) if run.measured else ""
            star = " <span class='best' title='best of the row'>★</span>" if is_best else ""
            tooltip = "; ".join(x for x in (BOUND_TEXT[where] if run.measured else "", messages, run.reason) if x)
            background = "" if run.measured else f" style='background:{STATUS_COLOURS.get(run.status, '#fff')}'"
            html.append(f"<td class='num {where if run.measured else ''}'{background} title='{escape(tooltip)}'>"
                        f"<span class='v'>{escape(text)}{star}</span>{''.join(badges)}</td>")
            row.append((f"**{text}** ★" if is_best else text) + (f" [{where}]" if run.measured and where != "unbounded"
                                                                 else "") + ("" if run.ok else f" ({run.status})"))
        html.append("</tr>")
        md.append("| " + " | ".join(row) + " |")
    html.append("</table></div>")
    columns = ("runs", "best", "within", "near", "beyond", "unbounded", "failed", "unsupported", "suspect")
    heads = {"best": "best ★", "within": "within bounds", "near": "near a bound", "beyond": "beyond a bound",
             "unbounded": "no bound", "failed": "failed (error, diverged, timeout)"}
    html.append("<h2>Engines across cases</h2><p>Per engine/method, over the cases it ran: how often it was the "
                "best of its case, where its deciding values lie against the cases' bounds, and how many runs "
                "failed, were unsupported or suspect.</p><div class='scroll'><table class='engines'><tr>"
                "<th>engine/method</th>" + "".join(f"<th>{escape(heads.get(c, c))}</th>" for c in columns) + "</tr>")
    md += ["", "## Engines across cases", "",
           "| engine/method | " + " | ".join(heads.get(c, c) for c in columns) + " |",
           "|---" * (len(columns) + 1) + "|"]
    for label in labels:
        counts = summary[label]
        html.append(f"<tr><td>{swatch(label)}{escape(label)}</td>"
                    + "".join(f"<td class='num'>{counts[c]}</td>" for c in columns) + "</tr>")
        md.append(f"| {label} | " + " | ".join(str(counts[c]) for c in columns) + " |")
    html.append("</table></div>")
    return "\n".join(html), md


def declared_order(label: str) -> tuple[int, int, str]:
    """Sort key of a run label: the registry's order of engines, then of their methods."""
    base = label.split(" [", 1)[0]
    engine, _, method = base.partition("/")
    for index, (name, methods) in enumerate(declared_engines()):
        if name == engine:
            return index, methods.index(method) if method in methods else len(methods), label
    return len(declared_engines()), 0, label


def swatch(label: str) -> str:
    """The label's palette colour and dash, as a small line (the same as in every figure)."""
    style = style_of_label(label)
    dash = f" stroke-dasharray='{style.dash}'" if style.dash else ""
    return (f"<svg class='swatch' width='26' height='10'><line x1='1' y1='5' x2='25' y2='5' stroke='{style.colour}' "
            f"stroke-width='2.5'{dash}/></svg>")


def copy_assets(out: Path) -> bool:
    """Copies three.js and the replay viewer into out/assets; False when three.js is not
    installed (the case pages then say so instead of replaying)."""
    assets = out / "assets"
    assets.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(WEB / "replay.js", assets / "replay.js")
    sources = {name: WEB / relative for name, relative in THREE_FILES.items()}
    if not all(path.is_file() for path in sources.values()):
        return False
    for name, path in sources.items():
        shutil.copyfile(path, assets / name)
    return True


def case_page(case: str, runs: list[RunResult], results: Results, colours: Colours, figures: Path,
              quiet: bool, out: Path | None = None, three: bool = False) -> str:
    from pbdval.api import load_scene, measure  # the C++ core, imported only here

    info = results.cases.get(case, {})
    body = [nav("../"),
            f"<h1>{escape(case)}</h1><p>{escape(str(info.get('description', '')))}</p>",
            f"<p>Scene: <code>{escape(str(info.get('file', '')))}</code>. References: "
            + escape(", ".join(sorted({r.reference for r in runs if r.reference})) or "none") + "</p>"]
    # Every metric over time, every run overlaid: the series behind the metrics, from the suite's
    # own measurement code (pbdval.measure: the runner's path, with the run's margin and step).
    series: list[Series] = []
    over_time: dict[str, list[Series]] = {}
    notes: list[str] = []
    scene = None
    try:
        scene = load_scene(info["file"]) if info.get("file") else None
    except (PbdvalError, OSError) as error:
        notes.append(f"the scene could not be loaded for the plots: {error}")
    replayed = []
    for r in runs:
        if not r.measured or scene is None:
            continue
        try:
            trajectory = r.trajectory()
            replayed.append((r.label, colours.of(r.label), trajectory))
            steps = float(r.facts.get("integratorStepsPerSceneStep") or 1)
            measured = measure(scene, trajectory, contact_margin=float(r.facts.get("contactMargin") or 0.0),
                               integration_step=scene.time_step / max(1.0, steps)).series
            times = measured["times"]
            for name, values in measured.items():
                if name == "times":
                    continue
                target = series if name == "energy_drift" else over_time.setdefault(name, [])
                thinned_times, thinned = thin(times, values)
                target.append(colours.series(r.label, thinned_times, thinned))
        except (PbdvalError, ValueError, OSError) as error:
            notes.append(f"{r.label}: no energy series ({error})")
    svg = line_plot(series, title=f"{case}: energy drift", xlabel="time (s)", ylabel="(E(t) − E(0)) / E_ref",
                    width=820, legend_width=290)
    write(figures / f"{slug(case)}-energy.svg", svg)
    body.append(f"<figure>{svg}<figcaption>Relative energy drift of every ok run "
                f"(<a href='../figures/{slug(case)}-energy.svg' download>SVG</a>).</figcaption></figure>")
    for name in sorted(over_time, key=lambda n: [k for k in SERIES_ORDER if n.startswith(k)][:1] + [n]):
        kind, _, detail = name.partition("/")
        label, unit, logy = SERIES_LABELS.get(kind, (kind, "", False))
        # A logarithmic axis needs a positive value (exact joints have an error of zero).
        logy = logy and any(math.isfinite(y) and y > 0 for s in over_time[name] for y in s.y)
        title = f"{case}: {label}" + (f" ({detail.replace('_', ' ')})" if detail else "")
        svg = line_plot(over_time[name], title=title, xlabel="time (s)", ylabel=f"{label} ({unit})" if unit else label,
                        logy=logy, width=820, legend_width=290)
        file = f"{slug(case)}-{slug(name)}.svg"
        write(figures / file, svg)
        body.append(f"<figure>{svg}<figcaption>{escape(SERIES_CAPTIONS.get(kind, ''))} "
                    f"(<a href='../figures/{file}' download>SVG</a>)</figcaption></figure>")
    for note in notes:
        body.append(f"<p class='badge warn'>{escape(note)}</p>")
    # 3D replay (python/pbdval/replay.py, web/replay.js).
    body.append("<h2>3D replay</h2>")
    not_replayed = [f"{r.label}: {r.status}" + (f" ({r.reason})" if r.reason else "") for r in runs if not r.measured]
    data = replay_data(case, scene, replayed, not_replayed) if scene is not None else None
    if out is not None and data is not None and data["runs"]:
        write(out / "replay" / f"{slug(case)}.js", replay_script(data))
        body.append("<p>Every completed run together, one colour per engine/method (the report's palette; static "
                    "bodies grey): rigid bodies as their shapes, cloth and solids as surfaces, rods as polylines, "
                    "fluids as points. Drag to turn, wheel to zoom, the slider to scrub.</p><div id='replay'></div>")
        if three:
            body.append("<script src='../assets/three.min.js'></script>"
                        "<script src='../assets/OrbitControls.js'></script>")
        body.append(f"<script src='../replay/{slug(case)}.js'></script><script src='../assets/replay.js'></script>")
    else:
        why = "the scene could not be loaded" if scene is None else "no run completed with a trajectory"
        body.append(f"<p class='badge warn replay-none'>no replay: {escape(why)}</p>")
    said = (data or {}).get("notes") or not_replayed
    if said:
        body.append("<p class='replay-notes'>Not replayed:</p><ul class='replay-notes'>"
                    + "".join(f"<li>{escape(str(n))}</li>" for n in said) + "</ul>")
    # Metrics table.
    metrics = sorted({m for r in runs for m in r.metrics})
    body.append("<h2>Metrics</h2><div class='scroll'><table><tr><th>engine/method</th><th>status</th>"
                + "".join(f"<th>{escape(m)}</th>" for m in metrics) + "</tr>")
    for r in runs:
        body.append(f"<tr><td>{escape(r.label)}</td><td style='background:{STATUS_COLOURS.get(r.status, '#fff')}'>"
                    f"{escape(r.status)}</td>"
                    + "".join(f"<td class='num'>{number(r.metrics.get(m))}</td>" for m in metrics) + "</tr>")
    body.append("</table></div>")
    suspect = [r for r in runs if r.status == "suspect"]
    if suspect:
        body.append("<h2>Runs held suspect</h2><p>They completed and were measured, but broke a "
                    "sanity bound or a velocity check (docs/metrics.md).</p><ul>"
                    + "".join(f"<li><b>{escape(r.label)}</b>: {escape(r.reason)}</li>" for r in suspect)
                    + "</ul>")
    failed = [r for r in runs if not r.measured]
    if failed:
        body.append("<h2>Runs that did not complete</h2><ul>"
                    + "".join(f"<li><b>{escape(r.label)}</b> {escape(r.status)}: {escape(r.reason)}</li>"
                              for r in failed)
                    + "</ul>")
    # Parity record.
    body.append("<h2>Effective settings (the parity record)</h2>")
    for r in runs:
        settings = "".join(f"<tr><td>{escape(k)}</td><td>{escape(str(v))}</td></tr>"
                           for k, v in sorted(r.settings.items()))
        parameters = ", ".join(f"{k} = {v}" for k, v in sorted(r.parameters.items()))
        body.append(f"<details><summary>{escape(r.label)} — {escape(str(r.facts.get('engineVersion', '')))}"
                    f"{'; ' + escape(parameters) if parameters else ''}</summary><table>{settings}</table></details>")
    progress(f"  case {case}: {len(runs)} runs", quiet)
    return page(f"pbdval report: {case}", "\n".join(body))


def convergence_page(sweeps: Sequence[Path], colours: Colours, figures: Path, *, standalone: bool = False) -> str:
    body = ["" if standalone else nav(),
            ("<h1>Convergence</h1><p>Error against the swept parameter, log-log, per method: filled points are "
            "fitted, hollow ones were left out (on a floor); dashed lines are reference slopes 1, 2 and 4 "
            "through the coarsest point of the first method. The legend gives the fitted order and R². Under it, "
            "the error against the wall time of each run, with the Pareto front.</p>")]
    if not sweeps:
        body.append("<p class='badge warn'>no sweep given (pbdval report --sweeps DIR...)</p>")
    for path in sweeps:
        try:
            document: dict[str, Any] = json.loads((path / "sweep.json").read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError) as error:
            body.append(f"<p class='badge fail'>{escape(str(path))}: not a sweep ({escape(str(error))})</p>")
            continue
        points = document.get("points", [])
        # the parameters that vary (one held at a single value, e.g. stepControl=fixed, does not;
        # nor do those varied with the coordinate of a --together path, functions of it)
        together = [str(n) for n in document.get("together", [])]
        names = sorted(k for k in {k for p in points for k in p.get("parameters", {})}
                       if k not in together[1:] and len({str(p.get("parameters", {}).get(k)) for p in points}) > 1)
        title = f"{document.get('case', '?')}: {document.get('metric', '?')}"
        if together:
            title += f" along {', '.join(together)} together"
        if len(names) != 1 or not points:
            body.append(f"<h2>{escape(title)}</h2><p class='badge warn'>"
                        f"{'no points' if not points else 'a grid of several parameters: see sweep.json'}</p>")
            continue
        name = names[0]
        metric = str(document.get("metric", ""))
        y_label = metric_label(metric)
        x_label = parameter_label(name, [str(p.get("method", "")) for p in points])
        series: list[Series] = []
        badges: list[str] = []
        for fit in document.get("fits", []):
            method = fit.get("method", "?")
            mine = [p for p in points if p.get("method") == method]
            excluded = {float(e.get("value")) for e in fit.get("excluded", [])}
            xs = [float(p["parameters"][name]) for p in mine]
            ys = [float(p["metric"]) if p.get("metric") is not None else math.nan for p in mine]
            order = fit.get("orders", {}).get(name, {}).get("order")
            label = f"{method}: p = {order:.2f}, R² {fit.get('r_squared', 0):.3f}" if order is not None else \
                f"{method}: no fit"
            if fit.get("model") == "power_plus_floor" and fit.get("floor") is not None:
                label += f", floor {float(fit['floor']):.3g}"
            series.append(colours.series(label, xs, ys, style_label=method, markers=True,
                                         hollow=[x in excluded for x in xs]))
            for flag in fit.get("flags", []):
                badges.append(f"<span class='badge warn'>{escape(method)}: {escape(flag)}</span>")
            local = fit.get("orders", {}).get(name, {}).get("local", [])
            if local:
                badges.append(f"<span class='badge'>{escape(method)} local orders: "
                              + ", ".join(f"{l['order']:.2f}" for l in local) + "</span>")
        first = next((s for s in series if any(math.isfinite(y) and y > 0 for y in s.y)), None)
        if first is not None:
            x0, y0 = next((x, y) for x, y in zip(first.x, first.y) if math.isfinite(y) and y > 0)
            step_like = name in ("timeStepSize", "tolerance", "targetAccuracy")
            for p in (1, 2, 4):
                xs = sorted(first.x)
                series.append(Series(f"slope {p}", xs,
                                     [y0 * (x / x0) ** (p if step_like else -p) for x in xs], "#999999", dashed=True))
        svg = line_plot(series, title=title, xlabel=x_label, ylabel=y_label, logx=True, logy=True,
                        width=900, height=400, legend_width=330)
        file = f"sweep-{slug(path.name)}.svg"
        write(figures / file, svg)
        body.append(f"<h2>{escape(title)}</h2><p>{' '.join(badges)}</p><figure>{svg}<figcaption>"
                    f"<code>{escape(str(document.get('metadata', {}).get('command', '')))}</code> "
                    f"(<a href='figures/{file}' download>SVG</a>)</figcaption></figure>")
        # Error against wall time: the cost of accuracy, every point labelled with its method's
        # parameter value, with the sweep's Pareto front (the points no other point beats in
        # both, marked by `pbdval sweep` in sweep.json) drawn as a line.
        cost: list[Series] = []
        timed = [p for p in points if p.get("metric") is not None and p.get("wall_time_s") is not None]
        for method in sorted({str(p.get("method", "?")) for p in points},
                             key=lambda m: declared_order(f"{engine_of_method(m)}/{m}")):
            mine = sorted((p for p in timed if p.get("method") == method), key=lambda p: float(p["wall_time_s"]))
            cost.append(colours.series(method, [float(p["wall_time_s"]) for p in mine],
                                       [float(p["metric"]) for p in mine], markers=True,
                                       point_labels=[str(p["parameters"][name]) for p in mine],
                                       x_spread=[wall_time_range(p) for p in mine]))
        front = sorted((p for p in timed if p.get("pareto")), key=lambda p: float(p["wall_time_s"]))
        if front:
            cost.append(Series("Pareto front", [float(p["wall_time_s"]) for p in front],
                               [float(p["metric"]) for p in front], "#000000"))
        svg = line_plot(cost, title=f"{title}: cost", xlabel="wall time per run (s)", ylabel=y_label,
                        logx=True, logy=True, width=900, height=400, legend_width=330)
        file = f"sweep-{slug(path.name)}-cost.svg"
        write(figures / file, svg)
        passes = max((len(p.get("wall_times_s") or [0]) for p in timed), default=1)
        timing = (f"each point's wall time is the median of its {passes} passes, the bar through it their range"
                  if passes > 1 else "wall times are single runs (a sweep before pbdval sweep --repeat)")
        body.append(f"<figure>{svg}<figcaption>Error against wall time per run, every method, each point "
                    f"labelled with its {escape(name)}; {timing}; the black line joins the Pareto front "
                    f"({len(front)} points: none is beaten in both by another) "
                    f"(<a href='figures/{file}' download>SVG</a>)</figcaption></figure>")
    return page("pbdval report: convergence", "\n".join(body))


# ---- parity ------------------------------------------------------------------------------------

def parity_page() -> str:
    """The parity page: the engines' feature tables side by side (pbdval.parity renders them; the
    same tables generate docs/parity*.md)."""
    body = [nav(),
            ("<h1>Parity</h1><p>How each engine maps the scene's features: <b>native</b> (its own feature with the "
            "scene's meaning), <b>approximated</b> (the closest feature; the tooltip says how it differs) or "
            "<b>unsupported</b> (the run is reported unsupported, naming the feature by its JSON path). Each engine "
            "declares this once, in its feature table (docs/engines.md#features): the built-in engines in code, the "
            "external ones in their catalogue entry. A cell that differs between an engine's methods names them.</p>")]
    try:
        from pbdval.parity import html_table

        body.append(html_table())
    except (ImportError, OSError, ValueError) as error:
        body.append(f"<p class='badge warn'>the feature tables could not be read: {escape(str(error))}</p>")
    return page("pbdval report: parity", "\n".join(body))


# ---- the whole report ----------------------------------------------------------------------------


def build_report(results_dir: Path, out: Path, *, baseline: Path | None = None, sweeps: Sequence[Path] = (),
                 quiet: bool = False, gate_json: Path | None = None,
                 cases: Sequence[str] | None = None) -> Path:
    """Writes the report into `out` and returns the path of its index.html. With `baseline`, runs
    the gate; with `gate_json`, shows the verdicts a `pbdval gate --json` wrote instead. A results
    folder of another schema version gives a report that says so (nothing else can be read from
    it); a folder that is not a results folder, or a gate_json that is not such verdicts, raises
    ResultsError. With `cases`, the report (and the gate it runs) covers those cases only; a name
    the results do not hold raises ResultsError naming the cases they do hold."""
    try:
        results = load_results(results_dir)
    except ResultsError as error:
        if "schemaVersion" not in str(error):
            raise
        write(out / "index.html", page("pbdval report", f"<h1>pbdval report</h1><p class='badge warn'>"
                                       f"{escape(str(error))}: re-run the cases with this pbdval to report "
                                       f"them.</p>"))
        write(out / "report.md", f"# pbdval report\n\n{error}\n")
        progress(f"pbdval report: {error}", quiet)
        return out / "index.html"
    if cases:
        results = only_cases(results, cases)
    progress(f"pbdval report: {len(results)} runs of {len(results.cases)} cases from {results_dir}", quiet)
    colours = Colours()
    labels = sorted({r.label for r in results}, key=declared_order)
    figures = out / "figures"
    # The verdicts are read (or the gate run) before anything is written: a bad --gate-json or
    # baseline leaves no half-made report folder behind.
    verdicts = (read_gate_json(gate_json) if gate_json
                else run_gate(results_dir, baseline, cases) if baseline else None)
    three = copy_assets(out)
    if not three:
        progress("pbdval report: three.js is not installed (scripts/install-deps): no 3D replay", quiet)
    gate = gate_section(verdicts, baseline, results) if verdicts else None
    checks, checks_note = case_checks(results, verdicts)
    if checks_note:
        progress(f"pbdval report: {checks_note}", quiet)
    body, markdown = overview(results, labels, gate, checks, run_verdicts(verdicts), checks_note)
    by_case: dict[str, list[RunResult]] = {}
    for r in results:
        by_case.setdefault(r.case, []).append(r)
    for case, runs in sorted(by_case.items()):
        write(out / "cases" / f"{slug(case)}.html",
              case_page(case, runs, results, colours, figures, quiet, out=out, three=three))
    write(out / "convergence.html", convergence_page(sweeps, colours, figures))
    write(out / "parity.html", parity_page())
    write(out / "index.html", page("pbdval report", body))
    write(out / "report.md", markdown)
    progress(f"pbdval report: wrote {out / 'index.html'}", quiet)
    return out / "index.html"


def only_cases(results: Results, cases: Sequence[str]) -> Results:
    """The runs and case entries of `cases` alone; raises ResultsError for a name the results do
    not hold (with the closest known names)."""
    unknown = [c for c in cases if c not in results.cases]
    if unknown:
        known = sorted(results.cases)
        hints = "; ".join(f"{c!r}" + (f" (did you mean {', '.join(difflib.get_close_matches(c, known, 3))}?)"
                                      if difflib.get_close_matches(c, known, 3) else "") for c in unknown)
        raise ResultsError(f"{results.folder}: no case {hints} in these results; they hold {len(known)} "
                           f"cases: {', '.join(known)}")
    wanted = set(cases)
    return Results(results.folder, results.metadata, {c: v for c, v in results.cases.items() if c in wanted},
                   [r for r in results.runs if r.case in wanted])


def build_convergence_report(sweeps: Sequence[Path], out: Path, *, quiet: bool = False) -> Path:
    """The convergence page of sweep folders on its own (`pbdval sweep --report`): writes
    out/convergence.html and its figures and returns its path."""
    colours = Colours()
    page_text = convergence_page(sweeps, colours, out / "figures", standalone=True)
    write(out / "convergence.html", page_text)
    progress(f"pbdval report: wrote {out / 'convergence.html'}", quiet)
    return out / "convergence.html"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="pbdval report", description=__doc__.splitlines()[0])
    if argv is None:
        argv = sys.argv[1:]
    if argv and argv[0] == "--convergence":
        # pbdval sweep --report: python -m pbdval.report --convergence SWEEP_DIR --out DIR
        only = argparse.ArgumentParser(prog="pbdval report --convergence")
        only.add_argument("--convergence", type=Path, nargs="+", required=True, help="sweep folders")
        only.add_argument("--out", type=Path, required=True)
        only.add_argument("--quiet", action="store_true")
        known = only.parse_args(argv)
        print(build_convergence_report(known.convergence, known.out, quiet=known.quiet))
        return 0
    parser.add_argument("results", type=Path, help="a results folder (pbdval run --out)")
    parser.add_argument("--out", type=Path, default=None, help="report folder (default: RESULTS/report)")
    parser.add_argument("--baseline", type=Path, default=None, help="gate against this baseline")
    parser.add_argument("--gate-json", type=Path, default=None,
                        help="show these verdicts (pbdval gate --json) instead of running the gate")
    parser.add_argument("--sweeps", type=Path, nargs="*", default=[], help="sweep folders (with sweep.json)")
    parser.add_argument("--cases", type=str, default=None,
                        help="report only these cases (comma-separated; the gate too); default: all")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    cases = [c for c in args.cases.split(",") if c] if args.cases is not None else None
    if cases is not None and not cases:
        parser.error("--cases: expected a comma-separated list of case names")
    try:
        index = build_report(args.results, args.out or args.results / "report", baseline=args.baseline,
                             sweeps=args.sweeps, quiet=args.quiet, gate_json=args.gate_json, cases=cases)
    except ResultsError as error:
        print(f"pbdval report: error: {error}", file=sys.stderr)
        return 2
    print(index)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
