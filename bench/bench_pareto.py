#!/usr/bin/env python3
"""The error–time Pareto front of every method on one case per family (docs/benchmarks.md#pareto-fronts).

    scripts/bench --pareto [--families A,B,...] [--engines A,B,...] [--repeat N] [--jobs N]
        [--binary PBDVAL] [--include-newton] [--quick] [--svg-dir DIR] [--markdown FILE] [--out FILE.json]
    scripts/bench --pareto --from RECORD.json... [--svg-dir DIR] [--markdown FILE]

For every family (FAMILIES: pendulum, chain, stack, pile, resting contact, sliding contact,
cloth) `pbdval sweep` runs the family's case, shortened to the family's duration, with every
method of every engine that runs by default (newton only with --include-newton; --engines
chooses others), and measures each point's error against the family's reference:

- a method of the PBD engine sweeps its substep count (`subSteps` for `pbd`, `substeps` for
  `pbd.xpbd`: SUBSTEPS) at one frame step FRAME_STEP, as PBD is used (collision detection and
  the frame's work once per frame, the substeps buying the accuracy: Macklin et al., "Small
  Steps in Physics Simulation", SCA 2019);
- every other method sweeps `timeStepSize` (STEPS); the largest is FRAME_STEP and SUBSTEPS
  divide it into substeps as short as the others' steps and shorter, so both kinds of method
  cover the same range of step lengths over the same simulated duration.

Each point's time is the median of --repeat passes (`pbdval sweep --repeat`, ≥ 3), the runner's
`wall_time_s` (the engine's own work: loading the scene and stepping it; for the external
Python engines the whole round trip to their process, which a C++ engine does not pay). The
front is computed over all methods (python/pbdval/pareto.py) and each PBD method's distance from
it: the time ratio at equal error, both interpolated in log error–log time between points.

Writes bench/results/<host>/pareto-<stamp>.json (or --out) with the machine, build and
parameters; --svg-dir writes one figure per family (pareto-<family>.svg); --markdown the table
of distances that docs/benchmarks.md shows. --quick runs a small plan (two families, two
settings, the built-in C++ engines, 0.2 s) for the test of this script.
"""

from __future__ import annotations

import argparse
import copy
import datetime as dt
import json
import math
import os
import re
import socket
import statistics
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from bench_record import machine, write_record  # bench/, the script's own folder

from pbdval import pareto
from pbdval import protocol as pp
from pbdval.svg import Series, line_plot

REPO = Path(__file__).resolve().parents[1]

#: The frame step of the PBD methods' substep sweeps and the largest step of the others (s).
FRAME_STEP = 0.01
#: The step sizes every method outside the PBD engine sweeps (s): four, halving.
STEPS = (0.01, 0.005, 0.0025, 0.00125)
#: The substep counts per FRAME_STEP the PBD methods sweep: substeps of 2, 1, 0.5, 0.25 ms
#: (pbd.xpbd's default, 20 substeps per 5 ms step, is the last).
SUBSTEPS = (5, 10, 20, 40)
#: The substep parameter of each PBD method (`pbdval methods`).
SUBSTEP_PARAMETER = {"pbd": "subSteps", "pbd.xpbd": "substeps"}
#: Wall seconds a run may take (`pbdval sweep --timeout`): a 1–2 s simulation that takes longer
#: runs 10–20× slower than real time, three orders of magnitude behind the fastest engines on
#: every family, so it is on no front; Drake's error-controlled integrators on the contact
#: families take minutes per run (stiff contact forces, tiny steps) and would take hours.
TIMEOUT = 20.0
#: The engine whose methods' distances from the front are reported.
PBD_ENGINE = "pbd"


@dataclass(frozen=True)
class Family:
    """One case per family: the case file, the simulated duration it is cut to, the error
    metric, the reference that metric is measured against, and why that metric."""

    name: str
    case: str
    duration: float
    metric: str
    sweep_reference: str  # `pbdval sweep --reference`: "case" (the case's) or "fine"
    why: str
    reference: dict[str, Any] | None = None  # replaces the case's Validation.reference
    built_for: tuple[str, ...] = field(default_factory=tuple)  # PBD methods built for it


FAMILIES: tuple[Family, ...] = (
    Family("pendulum", "joint_hinge", 2.0, "trajectory_error_max", "case",
           "the hinge pendulum's closed form (references.md#pendulum): the largest distance of "
           "the link's centre of mass from the exact motion"),
    Family("chain", "chain_10", 1.0, "trajectory_error_max", "case",
           "no closed form: a converged reference, mujoco.rk4 (fourth order) at 1/16 of each "
           "point's step (at the PBD methods' frame step 0.01 s: 0.625 ms, whose own error on this "
           "chain is below 1e-6 m by RK4's measured order, docs/convergence.md); the largest "
           "distance of any link's centre of mass from it",
           reference={"type": "engine", "method": "mujoco.rk4", "stepDivisor": 16},
           built_for=("pbd.xpbd",)),
    Family("stack", "xpbd_stack_10", 1.0, "trajectory_error_max", "case",
           "ten boxes placed in contact at rest: the exact motion is rest (the sliding-block "
           "closed form on a flat support); measured on the top box, whose displacement adds up "
           "every contact's sinking and slipping below it",
           reference={"type": "analytic", "model": "sliding_block", "bodies": [10]},
           built_for=("pbd.xpbd",)),
    Family("pile", "contact_pile", 2.0, "penetration_max", "case",
           "18 bodies dropped into a heap: the trajectory is chaotic (no reference converges over "
           "seconds), but the exact motion never interpenetrates, so the deepest penetration "
           "(FCL's exact distance) is the error"),
    Family("resting", "xpbd_incline_stick", 1.0, "trajectory_error_max", "case",
           "a block in contact on an incline below its friction angle: the exact motion is rest "
           "(the sliding-block closed form); the largest drift",
           built_for=("pbd.xpbd",)),
    Family("sliding", "xpbd_incline_slide", 1.0, "trajectory_error_max", "case",
           "a block sliding down an incline above its friction angle: the closed form "
           "x = g (sin θ − μ cos θ) t² / 2",
           built_for=("pbd.xpbd",)),
    Family("cloth", "cloth_hanging", 1.0, "particle_trajectory_error_max", "fine",
           "engines model cloth differently (XPBD distance and bending constraints, pybullet's "
           "springs, MuJoCo's flex), so there is no common exact motion: each method against "
           "itself at 1/16 of its smallest swept step (the consistency measure of Erez, Tassa "
           "and Todorov 2015), the largest particle distance",
           built_for=("pbd", "pbd.xpbd")),
)

QUICK_FAMILIES = ("pendulum", "stack")
QUICK_ENGINES = ("pbd", "ode", "bullet")
QUICK_DURATION = 0.2


def write_text_atomically(path: Path, text: str) -> None:
    """`text` into a temporary file beside `path`, then renamed over it: never half a file."""
    fd, temporary = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=str(path.parent))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def finite_or_none(v: Any) -> float | None:
    return float(v) if isinstance(v, (int, float)) and math.isfinite(v) else None


def family_by_name(name: str) -> Family:
    for f in FAMILIES:
        if f.name == name:
            return f
    raise SystemExit(f"--families: unknown family {name!r}; expected names from "
                     f"{', '.join(f.name for f in FAMILIES)}")


def engine_methods(binary: Path) -> list[tuple[str, list[str]]]:
    """(engine, its methods) in `pbdval methods`' order."""
    text = subprocess.run([str(binary), "methods"], capture_output=True, text=True, check=True).stdout
    engines: list[tuple[str, list[str]]] = []
    for line in text.splitlines():
        header = re.match(r"^(\S+) \(default method: \S+\)$", line)
        if header:
            engines.append((header.group(1), []))
        elif engines and re.match(r"^  [A-Za-z][\w.\-]*$", line):
            engines[-1][1].append(line.strip())
    return engines


def runs_by_default(engine: str) -> bool:
    """False for an external engine declared `"runByDefault": false` (engines/<name>.json)."""
    declaration = REPO / "engines" / f"{engine}.json"
    if not declaration.exists():
        return True
    return bool(json.loads(declaration.read_text()).get("runByDefault", True))


def shortened_case(family: Family, duration: float, folder: Path) -> Path:
    """The family's case cut to `duration` (and its reference replaced when the family says so),
    written into `folder` beside a link to cases/models, so that its relative paths resolve."""
    source = REPO / "cases" / f"{family.case}.json"
    scene = json.loads(source.read_text())
    validation = scene.setdefault("Validation", {})
    validation["duration"] = duration
    if family.reference is not None:
        validation["reference"] = copy.deepcopy(family.reference)
    models = folder / "models"
    if not models.exists():
        models.symlink_to(REPO / "cases" / "models")
    path = folder / f"{family.case}.json"
    pp.write_json_atomically(path, scene)
    return path


def sweep(binary: Path, case: Path, methods: list[str], parameters: list[str], family: Family,
          repeat: int, jobs: int, timeout: float, out: Path) -> dict[str, Any]:
    command = [str(binary), "sweep", str(case), *[a for p in parameters for a in ("--param", p)],
               "--methods", ",".join(methods), "--metric", family.metric,
               "--reference", family.sweep_reference, "--repeat", str(repeat), "--jobs", str(jobs),
               "--timeout", f"{timeout:g}", "--out", str(out), "--force"]
    result = subprocess.run(command, capture_output=True, text=True, check=False)
    if result.returncode != 0 or not (out / "sweep.json").exists():
        raise RuntimeError(f"{' '.join(command)} exited {result.returncode}: {result.stderr[-3000:]}")
    document: dict[str, Any] = json.loads((out / "sweep.json").read_text())
    return document


def is_number(text: Any) -> bool:
    """Whether a parameter's value reads as a number (a choice such as "start" does not)."""
    try:
        float(text)
    except (TypeError, ValueError):
        return False
    return True


def method_parameters(entries: list[str]) -> dict[str, list[str]]:
    """`--method-param METHOD:KEY=VALUE` entries by method: each a fixed `--param KEY=VALUE` of
    that method's sweep. Raises ValueError naming the entry when it is not of that form."""
    by_method: dict[str, list[str]] = {}
    for entry in entries:
        method, _, assignment = entry.partition(":")
        key, equals, value = assignment.partition("=")
        if not method or not key or not equals or not value or "," in value:
            raise ValueError(f"--method-param: expected METHOD:KEY=VALUE (one value), got {entry!r}")
        by_method.setdefault(method, []).append(f"{key}={value}")
    return by_method


def point_record(point: dict[str, Any], engine: str, duration: float) -> dict[str, Any]:
    """What the front needs of a sweep point, and what a reader needs to check it."""
    run = point.get("run", {})
    settings = {k: float(v) for k, v in point.get("parameters", {}).items() if is_number(v)}
    frame = settings.get("timeStepSize", math.nan)
    substeps = next((settings[p] for p in SUBSTEP_PARAMETER.values() if p in settings), 1.0)
    metric = point.get("metric")
    wall = point.get("wall_time_s")
    steps = run.get("metrics", {}).get("steps")
    return {"method": point["method"], "engine": engine, "parameters": point.get("parameters", {}),
            "step_s": frame, "substeps": substeps, "effective_step_s": frame / substeps,
            "status": point.get("status"), "reason": point.get("reason", ""),
            "error": finite_or_none(metric),
            "wall_time_s": wall, "wall_times_s": point.get("wall_times_s", []),
            "time_per_simulated_s": (wall / duration) if isinstance(wall, (int, float)) else None,
            "steps": steps,
            "time_per_step_s": (wall / steps) if isinstance(wall, (int, float)) and steps else None}


def on_front_candidate(p: dict[str, Any]) -> bool:
    return (p["status"] == "ok" and isinstance(p["error"], (int, float)) and math.isfinite(p["error"])
            and isinstance(p["wall_time_s"], (int, float)) and p["wall_time_s"] > 0)


def analyse(points: list[dict[str, Any]]) -> tuple[list[int], dict[str, dict[str, Any]]]:
    """The front (indices into `points`, of `ok` points only) and each PBD method's distance."""
    candidates = [i for i, p in enumerate(points) if on_front_candidate(p)]
    as_points = [pareto.Point(points[i]["error"], points[i]["wall_time_s"], points[i]["method"],
                              json.dumps(points[i]["parameters"], sort_keys=True)) for i in candidates]
    on = [candidates[k] for k in pareto.front(as_points)]
    distances: dict[str, dict[str, Any]] = {}
    front_methods = sorted({points[i]["method"] for i in on})
    for method in sorted({p["method"] for p in points if p["engine"] == PBD_ENGINE}):
        mine = [p for p in as_points if p.method == method]
        d = pareto.distance(as_points, method)
        distances[method] = {"on_front": d.on_front, "best_ratio": d.best_ratio, "best_error": d.best_error,
                             "points": [{"parameters": json.loads(p.setting), "error": p.error, "wall_time_s": p.time,
                                         "time_ratio": r} for p, r in zip(mine, d.point_ratios, strict=True)],
                             "front_errors": sorted(points[i]["error"] for i in on if points[i]["method"] == method),
                             "front_methods": front_methods, "ok_points": len(mine)}
    return on, distances


def figure(record: dict[str, Any]) -> str:
    """The family's error against time per method, PBD points labelled with their substeps,
    and the front as a black line."""
    from pbdval.palette import style_of

    points: list[dict[str, Any]] = record["points"]
    front: list[int] = record["front"]

    series: list[Series] = []
    front_methods = {points[i]["method"] for i in front}
    methods = sorted({p["method"] for p in points if on_front_candidate(p)},
                     key=lambda m: (m.split(".")[0] == PBD_ENGINE, m in front_methods, m))  # PBD drawn last, on top
    others = [m for m in methods if m.split(".")[0] != PBD_ENGINE and m not in front_methods]
    for method in methods:
        mine = sorted((p for p in points if p["method"] == method and on_front_candidate(p)),
                      key=lambda p: p["error"])
        pbd = mine[0]["engine"] == PBD_ENGINE
        labels = [f"{int(p['substeps'])}" for p in mine] if pbd else []
        x = [p["time_per_simulated_s"] for p in mine]
        y = [max(p["error"], pareto.ERROR_FLOOR) for p in mine]
        if method in others:  # on no front and no PBD method: grey, one legend entry for all
            series.append(Series(f"{len(others)} other methods", x, y, "#c4c4c4", markers=True, marker="circle",
                                 legend=method == others[0]))
            continue
        style = style_of(mine[0]["engine"], method)
        series.append(Series(method, x, y, style.colour, markers=True, dash=style.dash, marker=style.marker,
                             point_labels=labels))
    frontier = sorted((points[i] for i in front), key=lambda p: p["wall_time_s"])
    series.append(Series("Pareto front", [p["time_per_simulated_s"] for p in frontier],
                         [max(p["error"], pareto.ERROR_FLOOR) for p in frontier], "#000000"))
    return line_plot(series, title=f"{record['family']}: {record['case']}, {record['duration_s']:g} s simulated "
                                   f"(PBD points labelled with substeps per {FRAME_STEP * 1e3:g} ms)",
                     xlabel="wall time per simulated second (s/s, median of the passes)",
                     ylabel=record["metric"], logx=True, logy=True, width=760, height=440)


def ratio_text(r: float | None) -> str:
    return "—" if r is None else ("1 (on the front)" if abs(r - 1) < 1e-9 else f"{r:.3g}×")


def substep_count(parameters: dict[str, str]) -> str:
    """The substep count of a PBD point's parameters ("" when it has none)."""
    return next((parameters[p] for p in SUBSTEP_PARAMETER.values() if p in parameters), "")


def markdown(families: list[dict[str, Any]]) -> str:
    lines = [("| family (case) | PBD method | on the front (at errors) | best time ratio at equal error (at error) | "
              "time ratio at each substep count | built for it | front held by |"),
             "|---|---|---|---|---|---|---|"]
    for f in families:
        for method, d in f["distances"].items():
            per_point = ", ".join(f"{substep_count(p['parameters'])}: "
                                  f"{'—' if p['time_ratio'] is None else format(p['time_ratio'], '.3g')}"
                                  for p in d["points"])
            best = ratio_text(d["best_ratio"])
            if d["best_error"] is not None:
                best += f" ({d['best_error']:.2g})"
            built = "yes" if method in f["built_for"] else ""
            holders = ", ".join(f"`{m}`" for m in d["front_methods"])
            errors = d.get("front_errors", [])
            on = (f"yes, at {errors[0]:.2g}" + (f"–{errors[-1]:.2g}" if len(errors) > 1 else "")) if errors else "no"
            lines.append(f"| {f['family']} (`{f['case']}`) | `{method}` | {on} | "
                         f"{best} | {per_point or 'no ok point'} | {built} | {holders} |")
    return "\n".join(lines) + "\n"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", type=Path, default=REPO / "build" / "release" / "bin" / "pbdval")
    parser.add_argument("--families", default="", help="comma-separated family names (default: all)")
    parser.add_argument("--engines", default="", help="comma-separated engines (default: those run by default)")
    parser.add_argument("--include-newton", action="store_true", help="add newton (runByDefault false)")
    parser.add_argument("--repeat", type=int, default=3, help="passes per point, the time is their median (≥ 3)")
    parser.add_argument("--jobs", type=int, default=1, help="pbdval sweep --jobs (1: points timed one at a time)")
    parser.add_argument("--timeout", type=float, default=TIMEOUT,
                        help=f"wall seconds a run may take before it is stopped (a `timeout` point, on no front; "
                             f"default {TIMEOUT:g})")
    parser.add_argument("--method-param", action="append", default=[], metavar="METHOD:KEY=VALUE",
                        help="a fixed parameter of one PBD method's sweep (repeatable), e.g. "
                             "pbd.xpbd:jointDirections=start")
    parser.add_argument("--quick", action="store_true", help="a small plan for the test of this script")
    parser.add_argument("--svg-dir", type=Path, help="write pareto-<family>.svg here")
    parser.add_argument("--markdown", type=Path, help="write the table of distances here")
    parser.add_argument("--out", type=Path, help="the JSON (default bench/results/<host>/pareto-<stamp>.json)")
    parser.add_argument("--from", dest="sources", type=Path, nargs="+",
                        help="render --svg-dir and --markdown from recorded JSON files (their families in "
                             "order; a family recorded twice: the later file's), running nothing")
    args = parser.parse_args()
    if args.sources:
        by_family: dict[str, dict[str, Any]] = {}
        for source in args.sources:
            recorded_document = json.loads(source.read_text())
            if recorded_document.get("schema") != "pbdval-bench-pareto":
                parser.error(f"--from: {source} is no pbdval-bench-pareto record (its schema: "
                             f"{recorded_document.get('schema')!r})")
            by_family.update((f["family"], f) for f in recorded_document["families"])
        order = [f.name for f in FAMILIES]
        render(sorted(by_family.values(), key=lambda f: order.index(f["family"]) if f["family"] in order
                      else len(order)), args.svg_dir, args.markdown)
        return 0
    try:
        fixed = method_parameters(args.method_param)
    except ValueError as error:
        parser.error(str(error))
    if args.repeat < 3:
        parser.error("--repeat: at least 3 (each time is the median of the passes)")
    if not args.timeout > 0:
        parser.error("--timeout: seconds > 0")
    if args.jobs < 1:
        parser.error("--jobs: at least 1")
    if not args.binary.exists():
        parser.error(f"--binary: {args.binary} does not exist "
                     "(build it: cmake --build --preset release --target pbdval)")

    families = ([family_by_name(n) for n in args.families.split(",") if n] if args.families
                else [family_by_name(n) for n in QUICK_FAMILIES] if args.quick else list(FAMILIES))
    declared = engine_methods(args.binary)
    names = [e for e, _ in declared]
    if args.engines:
        chosen = [e for e in args.engines.split(",") if e]
        unknown = [e for e in chosen if e not in names]
        if unknown:
            parser.error(f"--engines: unknown engine(s) {', '.join(unknown)}; expected names from {', '.join(names)}")
    elif args.quick:
        chosen = list(QUICK_ENGINES)
    else:
        chosen = [e for e in names if runs_by_default(e) or (e == "newton" and args.include_newton)]
    if PBD_ENGINE not in chosen:
        parser.error(f"--engines: must include {PBD_ENGINE} (its methods' distances are the point)")
    steps = STEPS[:2] if args.quick else STEPS
    substeps = SUBSTEPS[:2] if args.quick else SUBSTEPS
    methods = {e: m for e, m in declared if e in chosen}
    stray = [m for m in fixed if m not in methods.get(PBD_ENGINE, [])]
    if stray:
        parser.error(f"--method-param: {', '.join(stray)} is no method of {PBD_ENGINE} "
                     f"(expected one of {', '.join(methods.get(PBD_ENGINE, []))})")

    commit = subprocess.run(["git", "-C", str(REPO), "rev-parse", "HEAD"], capture_output=True, text=True,
                            check=False).stdout.strip()
    dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True, check=False).stdout.strip() != ""
    out = args.out or REPO / "bench" / "results" / socket.gethostname() / (
        "pareto-" + dt.datetime.now(dt.UTC).strftime("%Y%m%dT%H%M%SZ") + ".json")
    recorded: list[dict[str, Any]] = []
    metadata: dict[str, Any] = {}
    started = machine()

    def save(complete: bool) -> None:
        """The record so far (after each family: an interrupted run keeps the families it
        finished; `complete` says whether every family of the plan is in)."""
        document = {"schema": "pbdval-bench-pareto", "schemaVersion": 1, "complete": complete,
                    "machine": started, "finished": machine() if complete else None,
                    "commit": commit, "dirty": dirty, "build": metadata,
                    "parameters": {"families": [f.name for f in families], "engines": chosen,
                                   "repeat": args.repeat, "jobs": args.jobs, "timeout_s": args.timeout,
                                   "quick": args.quick,
                                   "frame_step_s": FRAME_STEP, "steps_s": list(steps), "substeps": list(substeps),
                                   "substep_parameter": SUBSTEP_PARAMETER, "binary": str(args.binary),
                                   "method_parameters": fixed},
                    "families": recorded}
        write_record("pareto", document, out)

    with tempfile.TemporaryDirectory(prefix="pbdval-bench-pareto-") as scratch:
        folder = Path(scratch)
        for family in families:
            duration = QUICK_DURATION if args.quick else family.duration
            case = shortened_case(family, duration, folder)
            engine_of = {m: e for e, ms in methods.items() for m in ms}
            points: list[dict[str, Any]] = []
            notes: list[str] = []
            plans: list[tuple[list[str], list[str]]] = []
            others = [m for e, ms in methods.items() if e != PBD_ENGINE for m in ms]
            if others:
                plans.append((others, ["timeStepSize=" + ",".join(f"{h:g}" for h in steps)]))
            for m in methods.get(PBD_ENGINE, []):
                parameter = SUBSTEP_PARAMETER.get(m)
                if parameter is None:
                    notes.append(f"{m}: no substep parameter declared in SUBSTEP_PARAMETER; left out")
                    continue
                counts = ",".join(str(n) for n in substeps)
                plans.append(([m], [f"timeStepSize={FRAME_STEP:g}", f"{parameter}={counts}", *fixed.get(m, [])]))
            for k, (plan_methods, parameters) in enumerate(plans):
                print(f"[{family.name}] {', '.join(plan_methods)}: {' '.join(parameters)}", file=sys.stderr, flush=True)
                document = sweep(args.binary, case, plan_methods, parameters, family, args.repeat, args.jobs,
                                 args.timeout, folder / f"{family.name}-{k}")
                metadata = metadata or document.get("metadata", {})
                notes.extend(document.get("notes", []))
                points.extend(point_record(p, engine_of.get(p["method"], ""), duration) for p in document["points"])
            front, distances = analyse(points)
            for i, p in enumerate(points):
                p["on_front"] = i in front
            record = {"family": family.name, "case": family.case, "caseFile": f"cases/{family.case}.json",
                      "duration_s": duration, "metric": family.metric, "reference": family.sweep_reference,
                      "referenceOverride": family.reference, "why": family.why, "built_for": list(family.built_for),
                      "points": points, "front": front, "distances": distances, "notes": sorted(set(notes))}
            recorded.append(record)
            save(complete=False)
            statuses = statistics.multimode([p["status"] for p in points]) if points else []
            print(f"[{family.name}] {len(points)} points ({', '.join(map(str, statuses))} most), front: "
                  + ", ".join(f"{points[i]['method']}@{points[i]['effective_step_s']:.3g}" for i in front),
                  file=sys.stderr, flush=True)
    save(complete=True)
    render(recorded, args.svg_dir, args.markdown)
    return 0


def render(recorded: list[dict[str, Any]], svg_dir: Path | None, markdown_file: Path | None) -> None:
    """The figures (one per family) and the table of distances, from the recorded families."""
    if svg_dir:
        svg_dir.mkdir(parents=True, exist_ok=True)
        for f in recorded:
            write_text_atomically(svg_dir / f"pareto-{f['family']}.svg", figure(f) + "\n")
    table = markdown(recorded)
    print(table)
    if markdown_file:
        write_text_atomically(markdown_file, table)


if __name__ == "__main__":
    sys.exit(main())
