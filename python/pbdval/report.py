"""`pbdval report RESULTS_DIR [--out DIR] [--baseline FILE] [--sweeps DIR...]` (docs/report.md).

A static, self-contained, offline report of a results folder: `index.html` (the overview: the
cases × engine/method matrix coloured by status with the key metric, the gate's verdicts when a
baseline is given, the run's metadata), one page per case (its metrics, the energy drift over
time of every run overlaid, each engine's effective settings), one convergence page per sweep
(error against the swept parameter, log-log, with the fitted order, R², the local orders, the
points left out and the flags), every figure a standalone SVG file; and `report.md`, the same
overview for a pull request. Nothing here computes a metric: the numbers come from
results.json, the energy series from the suite's own code (`pbdval.energy`), every verdict
from `pbdval gate` (its --json output: the report decides none).
"""

from __future__ import annotations

import argparse
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
from pbdval.replay import replay_data, replay_script
from pbdval.results import Results, RunResult, load_results, pbdval_binary
from pbdval.svg import PALETTE, Series, line_plot

#: The report's browser code: three.js from npm (python/pbdval/web, `npm ci` by
#: scripts/install-deps) and the replay viewer, copied into the report's assets/.
WEB = Path(__file__).resolve().parent / "web"
THREE_FILES = {"three.min.js": "node_modules/three/build/three.min.js",
               "OrbitControls.js": "node_modules/three/examples/js/controls/OrbitControls.js",
               "three-LICENSE.txt": "node_modules/three/LICENSE"}

STATUS_COLOURS = {"ok": "#d9f2d9", "suspect": "#ffc8a0", "unsupported": "#eeeeee", "diverged": "#ffd9b3", "timeout": "#ffe9a8",
                  "error": "#f7c6c6"}
#: Points per series in a time plot (every k-th sample beyond it: a 600-pixel-wide figure shows no
#: more, and a 39-case report stays small).
MAX_PLOT_POINTS = 400
#: The metric shown in a cell of the overview, in order of preference.
KEY_METRICS = ("trajectory_error_max", "joint_error_linear_max", "penetration_max", "energy_drift_max")

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


@dataclass
class Colours:
    """One colour per engine/method label across the whole report."""

    labels: list[str]

    def of(self, label: str) -> str:
        if label not in self.labels:
            self.labels.append(label)
        return PALETTE[self.labels.index(label) % len(PALETTE)]


def key_metric(run: RunResult) -> tuple[str, float | None]:
    for name in KEY_METRICS:
        if name in run.metrics and math.isfinite(run.metrics[name]):
            return name, run.metrics[name]
    return "", None


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


def run_gate(results_dir: Path, baseline: Path) -> GateVerdicts:
    """Runs `pbdval gate --json` on the results against the baseline."""
    with tempfile.TemporaryDirectory() as folder:
        verdicts = Path(folder) / "gate.json"
        done = subprocess.run([str(pbdval_binary()), "gate", "--baseline", str(baseline), "--results",
                               str(results_dir), "--json", str(verdicts), "--quiet"],
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


def gate_section(gate: GateVerdicts, baseline: Path | None) -> tuple[str, str]:
    """The gate's verdict, its counts and its table of every check that is not a plain pass (HTML
    and Markdown)."""
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
    rows = [c for kind in VERDICT_STYLE for c in document["checks"] if c["verdict"] == kind]
    if rows:
        html.append("<table class='gate'><tr><th>verdict</th><th>case</th><th>check</th><th>baseline</th>"
                    "<th>now</th><th>allowed</th><th>ratio</th><th>result</th></tr>")
        for check in rows:
            label, css = VERDICT_STYLE[check["verdict"]]
            before, now = check.get("baseline"), check.get("now")
            ratio = f"{now / before:.3g}×" if before not in (None, 0) and now is not None else ""
            html.append(f"<tr class='verdict-{check['verdict']}'><td><span class='badge {css}'>{label}</span></td>"
                        f"<td>{escape(check['case'])}</td><td>{escape(check['name'])}</td>"
                        f"<td class='num'>{number(before)}</td><td class='num'>{number(now)}</td>"
                        f"<td class='num'>{number(check.get('allowed'))}</td><td class='num'>{ratio}</td>"
                        f"<td>{escape(check['message'])}</td></tr>")
        html.append("</table>")
    if document["notes"]:
        html.append("<p><b>Notes:</b></p><ul>" + "".join(f"<li>{escape(n)}</li>" for n in document["notes"]) + "</ul>")
    # report.md is Markdown: the gate's own summary goes in as it is, under this page's heading.
    md.append(re.sub(r"\A# [^\n]*\n+", "", document["markdown"]))
    return "\n".join(html), "\n".join(md) + "\n"


# ---- pages ---------------------------------------------------------------------------------------


def overview(results: Results, labels: list[str], gate: tuple[str, str] | None) -> tuple[str, str]:
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
    md = ["# pbdval report", "", (f"{len(results)} runs of {len(cases)} cases; commit "
          f"`{str(build.get('commit', '?'))[:12]}` ({build.get('commitState', '?')}), {build.get('compiler', '')}."), ""]
    if gate is not None:
        html.append(gate[0])
        md += [gate[1], ""]
    html.append("<h2>Runs</h2><p>Each cell: status (colour) and the case's key metric "
                "(trajectory error, else joint error, else penetration, else energy drift; units in the "
                "case page). Unsupported runs name what is missing on the case page.</p><table><tr><th>case</th>")
    html += [f"<th>{escape(label)}</th>" for label in labels]
    html.append("</tr>")
    md += ["## Runs", "", "| case | " + " | ".join(labels) + " |", "|---" * (len(labels) + 1) + "|"]
    for case in cases:
        html.append(f"<tr><td><a href='cases/{slug(case)}.html'>{escape(case)}</a></td>")
        row = [case]
        for label in labels:
            run = cell.get((case, label))
            if run is None:
                html.append("<td></td>")
                row.append("")
                continue
            name, value = key_metric(run)
            colour = STATUS_COLOURS.get(run.status, "#ffffff")
            text = number(value) if run.measured else run.status
            if run.status == "suspect":
                text += " (suspect)"
            tooltip = run.reason if run.status == "suspect" else (name or run.reason)
            html.append(f"<td class='num' style='background:{colour}' title='{escape(tooltip)}'>{escape(text)}</td>")
            row.append(text)
        html.append("</tr>")
        md.append("| " + " | ".join(row) + " |")
    html.append("</table>")
    return "\n".join(html), "\n".join(md) + "\n"


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
    from pbdval.api import load_scene, measure

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
                target.append(Series(r.label, thinned_times, thinned, colours.of(r.label)))
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
    if out is not None and scene is not None and replayed:
        write(out / "replay" / f"{slug(case)}.js", replay_script(replay_data(case, scene, replayed)))
        body.append("<p>Every ok run's bodies together, one colour per engine/method (static bodies grey): "
                    "drag to turn, wheel to zoom, the slider to scrub.</p><div id='replay'></div>")
        if three:
            body.append("<script src='../assets/three.min.js'></script>"
                        "<script src='../assets/OrbitControls.js'></script>")
        body.append(f"<script src='../replay/{slug(case)}.js'></script><script src='../assets/replay.js'></script>")
    else:
        body.append("<p class='badge warn'>no replay: no ok run with a trajectory, or the scene could not be "
                    "loaded</p>")
    # Metrics table.
    metrics = sorted({m for r in runs for m in r.metrics})
    body.append("<h2>Metrics</h2><table><tr><th>engine/method</th><th>status</th>"
                + "".join(f"<th>{escape(m)}</th>" for m in metrics) + "</tr>")
    for r in runs:
        body.append(f"<tr><td>{escape(r.label)}</td><td style='background:{STATUS_COLOURS.get(r.status, '#fff')}'>"
                    f"{escape(r.status)}</td>"
                    + "".join(f"<td class='num'>{number(r.metrics.get(m))}</td>" for m in metrics) + "</tr>")
    body.append("</table>")
    suspect = [r for r in runs if r.status == "suspect"]
    if suspect:
        body.append("<h2>Runs held suspect</h2><p>They completed and were measured, but broke a "
                    "sanity bound or a velocity check (docs/metrics.md).</p><ul>"
                    + "".join(f"<li><b>{escape(r.label)}</b>: {escape(r.reason)}</li>" for r in suspect)
                    + "</ul>")
    failed = [r for r in runs if not r.measured]
    if failed:
        body.append("<h2>Runs that did not complete</h2><ul>"
                    + "".join(f"<li><b>{escape(r.label)}</b> {escape(r.status)}: {escape(r.reason)}</li>" for r in failed)
                    + "</ul>")
    # Parity record.
    body.append("<h2>Effective settings (the parity record)</h2>")
    for r in runs:
        settings = "".join(f"<tr><td>{escape(k)}</td><td>{escape(str(v))}</td></tr>" for k, v in sorted(r.settings.items()))
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
        names = sorted({k for p in points for k in p.get("parameters", {})})
        title = f"{document.get('case', '?')}: {document.get('metric', '?')}"
        if len(names) != 1 or not points:
            body.append(f"<h2>{escape(title)}</h2><p class='badge warn'>"
                        f"{'no points' if not points else 'a grid of several parameters: see sweep.json'}</p>")
            continue
        name = names[0]
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
            series.append(Series(label, xs, ys, colours.of(method), markers=True,
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
            step_like = name in ("timeStepSize", "tolerance")
            for p in (1, 2, 4):
                xs = sorted(first.x)
                series.append(Series(f"slope {p}", xs,
                                     [y0 * (x / x0) ** (p if step_like else -p) for x in xs], "#999999", dashed=True))
        svg = line_plot(series, title=title, xlabel=name, ylabel=str(document.get("metric", "")), logx=True, logy=True,
                        width=900, height=400, legend_width=330)
        file = f"sweep-{slug(path.name)}.svg"
        write(figures / file, svg)
        body.append(f"<h2>{escape(title)}</h2><p>{' '.join(badges)}</p><figure>{svg}<figcaption>"
                    f"<code>{escape(str(document.get('metadata', {}).get('command', '')))}</code> "
                    f"(<a href='figures/{file}' download>SVG</a>)</figcaption></figure>")
        # Error against wall time: the cost of accuracy, with the sweep's Pareto front (the points
        # no other point beats in both, marked by `pbdval sweep` in sweep.json).
        cost: list[Series] = []
        for method in sorted({str(p.get("method", "?")) for p in points}):
            mine = sorted((p for p in points if p.get("method") == method and p.get("metric") is not None
                           and p.get("wall_time_s") is not None), key=lambda p: float(p["wall_time_s"]))
            cost.append(Series(method, [float(p["wall_time_s"]) for p in mine], [float(p["metric"]) for p in mine],
                               colours.of(method), markers=True))
        front = sorted((p for p in points if p.get("pareto") and p.get("metric") is not None
                        and p.get("wall_time_s") is not None), key=lambda p: float(p["wall_time_s"]))
        if front:
            cost.append(Series("Pareto front", [float(p["wall_time_s"]) for p in front],
                               [float(p["metric"]) for p in front], "#000000", dashed=True, markers=True,
                               hollow=[True] * len(front)))
        svg = line_plot(cost, title=f"{title}: cost", xlabel="wall time per run (s)",
                        ylabel=str(document.get("metric", "")), logx=True, logy=True, width=900, height=400,
                        legend_width=330)
        file = f"sweep-{slug(path.name)}-cost.svg"
        write(figures / file, svg)
        body.append(f"<figure>{svg}<figcaption>Error against wall time per run, every method; the dashed "
                    f"line joins the Pareto front ({len(front)} points: none is beaten in both by another) "
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
                 quiet: bool = False, gate_json: Path | None = None) -> Path:
    """Writes the report into `out` and returns the path of its index.html. With `baseline`, runs
    the gate; with `gate_json`, shows the verdicts a `pbdval gate --json` wrote instead. A results
    folder of another schema version gives a report that says so (nothing else can be read from
    it); a folder that is not a results folder, or a gate_json that is not such verdicts, raises
    ResultsError."""
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
    progress(f"pbdval report: {len(results)} runs of {len(results.cases)} cases from {results_dir}", quiet)
    colours = Colours([])
    labels = sorted({r.label for r in results}, key=lambda l: (l.split("/")[0] != "pbd", l))
    for label in labels:
        colours.of(label)
    figures = out / "figures"
    three = copy_assets(out)
    if not three:
        progress("pbdval report: three.js is not installed (scripts/install-deps): no 3D replay", quiet)
    verdicts = read_gate_json(gate_json) if gate_json else run_gate(results_dir, baseline) if baseline else None
    gate = gate_section(verdicts, baseline) if verdicts else None
    body, markdown = overview(results, labels, gate)
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


def build_convergence_report(sweeps: Sequence[Path], out: Path, *, quiet: bool = False) -> Path:
    """The convergence page of sweep folders on its own (`pbdval sweep --report`): writes
    out/convergence.html and its figures and returns its path."""
    colours = Colours([])
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
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    try:
        index = build_report(args.results, args.out or args.results / "report", baseline=args.baseline,
                             sweeps=args.sweeps, quiet=args.quiet, gate_json=args.gate_json)
    except ResultsError as error:
        print(f"pbdval report: error: {error}", file=sys.stderr)
        return 2
    print(index)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
