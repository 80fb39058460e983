"""Running cases like ``pbdval run`` and reading its results folder (docs/results.md).

:func:`run` calls the pbdval command itself (same isolation per run, timeouts, statuses and
results.json), so a study scripted in Python gets exactly the numbers the suite gates on.
:func:`load_results` reads a results folder into typed objects with numpy-friendly tables.
"""

from __future__ import annotations

import functools
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from pbdval.api import ParameterValue, Trajectory
from pbdval.errors import BuildMissingError, CommandError, ResultsError

RESULTS_SCHEMA = "pbdval-results"
SUPPORTED_SCHEMA_VERSIONS = (1,)


def pbdval_binary() -> Path:
    """The pbdval command of the build the C++ core was loaded from (<build>/bin/pbdval)."""
    try:
        from pbdval import _core
    except ImportError as error:
        raise BuildMissingError(f"pbdval._core is not built ({error}); build with scripts/test") from error
    binary = Path(_core.__file__).resolve().parents[2] / "bin" / "pbdval"
    if not binary.is_file():
        raise BuildMissingError(f"{binary}: the pbdval command is missing; build it with scripts/test")
    return binary


#: The statuses of runs that completed and were measured (adapters/engine.h isMeasured).
MEASURED_STATUSES = ("ok", "suspect")


@dataclass
class RunResult:
    """One run of results.json (docs/results.md): case × engine × method."""

    case: str
    engine: str
    method: str
    status: str
    reason: str
    metrics: dict[str, float]
    parameters: dict[str, Any] = field(default_factory=dict)
    settings: dict[str, str] = field(default_factory=dict)
    facts: dict[str, Any] = field(default_factory=dict)
    joint_error_by_type: dict[str, dict[str, Any]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    reference: str = ""
    trajectory_path: Path | None = None
    assignments: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def measured(self) -> bool:
        """Completed and measured: ok, or suspect (its metrics are kept; `reason` says which
        sanity bound it broke)."""
        return self.status in MEASURED_STATUSES

    @property
    def label(self) -> str:
        """"engine/method", or "engine/method [a=1,b=2]" for a run with --set assignments."""
        base = f"{self.engine}/{self.method}"
        return f"{base} [{','.join(self.assignments)}]" if self.assignments else base

    def _beside_trajectory(self, infix: str) -> Path | None:
        """ENGINE-METHOD<infix>.csv/.npy beside the trajectory (validation/run/run_plan.h), or None
        when the run wrote none."""
        if self.trajectory_path is None:
            return None
        path = self.trajectory_path.with_name(
            self.trajectory_path.stem + infix + self.trajectory_path.suffix)
        return path if path.is_file() else None

    @property
    def particles_path(self) -> Path | None:
        """The run's particle file (ENGINE-METHOD.particles.csv/.npy, docs/cli.md#run)."""
        return self._beside_trajectory(".particles")

    @property
    def segments_path(self) -> Path | None:
        """The run's Cosserat-rod segment file (ENGINE-METHOD.segments.csv/.npy)."""
        return self._beside_trajectory(".segments")

    def trajectory(self) -> Trajectory:
        """The run's trajectory (CSV or NPY), read with the suite's reader, with its particles
        and rod segments attached when the run wrote them."""
        if self.trajectory_path is None or not self.trajectory_path.is_file():
            raise ResultsError(f"run {self.case} {self.label}: no trajectory file ({self.trajectory_path})")
        return Trajectory.read(self.trajectory_path, particles=self.particles_path, segments=self.segments_path)


@dataclass
class Results:
    """A results folder: its metadata, cases and runs."""

    folder: Path
    metadata: dict[str, Any]
    cases: dict[str, dict[str, Any]]
    runs: list[RunResult]

    def __iter__(self) -> Iterator[RunResult]:
        return iter(self.runs)

    def __len__(self) -> int:
        return len(self.runs)

    def select(
        self, *, case: str | None = None, engine: str | None = None, method: str | None = None
    ) -> list[RunResult]:
        return [
            r
            for r in self.runs
            if (case is None or r.case == case)
            and (engine is None or r.engine == engine)
            and (method is None or r.method == method)
        ]

    def run(self, case: str, method: str) -> RunResult:
        """The one run of `case` with `method` (no assignments)."""
        found = [r for r in self.runs if r.case == case and r.method == method and not r.assignments]
        if len(found) != 1:
            raise KeyError(f"{len(found)} runs of case {case!r} with method {method!r} in {self.folder}")
        return found[0]

    def table(self, metric: str) -> tuple[list[str], list[str], NDArray[np.float64]]:
        """(case names, run labels, values): a (cases × labels) array of `metric`, NaN where a
        run is missing, failed or lacks the metric."""
        case_names = sorted({r.case for r in self.runs})
        labels = sorted({r.label for r in self.runs})
        values = np.full((len(case_names), len(labels)), np.nan)
        row = {c: i for i, c in enumerate(case_names)}
        col = {m: j for j, m in enumerate(labels)}
        for r in self.runs:
            v = r.metrics.get(metric)
            if r.measured and v is not None:
                values[row[r.case], col[r.label]] = v
        return case_names, labels, values


def _number(value: Any) -> float:
    return math.nan if value is None else float(value)


def load_results(folder: str | Path) -> Results:
    """Reads FOLDER/results.json. Raises ResultsError naming the path and what was expected."""
    if not isinstance(folder, (str, os.PathLike)) or "\x00" in os.fspath(folder):
        raise ResultsError(f"{folder!r}: expected the path of a results folder")
    folder = Path(folder)
    path = folder / "results.json"
    if not folder.is_dir():
        raise ResultsError(f"{folder}: expected a results folder (the --out of pbdval run), found no folder")
    if not path.is_file():
        raise ResultsError(f"{folder}: expected a results folder with results.json (pbdval run --out), none found")
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ResultsError(f"{path}: cannot be read as JSON: {error}") from error
    if not isinstance(document, dict) or document.get("schema") != RESULTS_SCHEMA:
        raise ResultsError(f"{path}: expected schema {RESULTS_SCHEMA!r}, got {document.get('schema')!r}"
                           if isinstance(document, dict) else f"{path}: expected a JSON object")
    version = document.get("schemaVersion")
    if version not in SUPPORTED_SCHEMA_VERSIONS:
        raise ResultsError(f"{path}: schemaVersion {version!r} is not one this pbdval reads "
                           f"({', '.join(map(str, SUPPORTED_SCHEMA_VERSIONS))})")
    for key, kind in (("runs", list), ("metadata", dict), ("cases", dict)):
        if not isinstance(document.get(key, kind()), kind):
            raise ResultsError(f"{path}: {key}: expected a JSON {'array' if kind is list else 'object'}, "
                               f"got {type(document[key]).__name__}")
    runs: list[RunResult] = []
    for index, r in enumerate(document.get("runs", [])):
        try:
            trajectory = r.get("trajectory") or ""
            trajectory_path: Path | None = None
            if trajectory:
                candidate = Path(trajectory)
                # results.json names trajectories as given on the command line; resolve them
                # against the folder when the folder was moved.
                if not candidate.is_file():
                    candidate = folder / "trajectories" / r["case"] / Path(trajectory).name
                trajectory_path = candidate
            runs.append(
                RunResult(
                    case=r["case"],
                    engine=r["engine"],
                    method=r["method"],
                    status=r["status"],
                    reason=r.get("reason", ""),
                    metrics={k: _number(v) for k, v in r.get("metrics", {}).items()},
                    parameters=dict(r.get("parameters", {})),
                    settings=dict(r.get("settings", {})),
                    facts=dict(r.get("facts", {})),
                    joint_error_by_type=dict(r.get("joint_error_by_type", {})),
                    notes=list(r.get("notes", [])),
                    reference=r.get("reference", ""),
                    trajectory_path=trajectory_path,
                    assignments=list(r.get("assignments", [])),
                )
            )
        except (AttributeError, KeyError, TypeError, ValueError) as error:
            raise ResultsError(f"{path}: runs[{index}]: expected an object with case, engine, method and status "
                               f"({error})") from error
    return Results(folder=folder, metadata=dict(document.get("metadata", {})),
                   cases=dict(document.get("cases", {})), runs=runs)


def _assignment(key: str, value: ParameterValue) -> str:
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, (list, tuple)):
        text = ",".join(repr(float(v)) for v in value)
    else:
        text = str(value)
    return f"{key}={text}"


_Function = TypeVar("_Function", bound=Callable[..., Any])


def _temporary_out_removed_on_failure(function: _Function) -> _Function:
    """Without `out`, `function` (run) gets a new temporary folder as `out`, removed again when
    the call fails (raises): a failed run leaves no $TMPDIR/pbdval-run-* behind; a successful
    one keeps it (it is Results.folder)."""

    @functools.wraps(function)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        if kwargs.get("out") is not None:
            return function(*args, **kwargs)
        folder = Path(tempfile.mkdtemp(prefix="pbdval-run-"))
        try:
            return function(*args, **{**kwargs, "out": folder})
        except BaseException:
            shutil.rmtree(folder, ignore_errors=True)
            raise

    return wrapper  # type: ignore[return-value]


@_temporary_out_removed_on_failure
def run(
    cases: str | Path | Iterable[str | Path] | None = None,
    *,
    engines: Sequence[str] | None = None,
    methods: Sequence[str] | None = None,
    settings: Mapping[str, ParameterValue] | None = None,
    out: str | Path | None = None,
    jobs: int | None = None,
    timeout: float | None = None,
    quiet: bool = True,
    force: bool = False,
) -> Results:
    """Runs cases like ``pbdval run`` (every case of cases/ when `cases` is None) and returns
    the results of this call, never older ones. `settings` are ``--set`` assignments. Without
    `out`, results go to a new temporary folder (kept: its path is Results.folder); an `out`
    holding another plan's results is refused unless `force`. Raises :class:`pbdval.CommandError`
    (a subprocess.CalledProcessError) when the command itself fails: bad arguments, an `out`
    that another pbdval command is writing or that holds another plan's results, a signal.
    Failed runs are statuses, not errors."""
    command: list[str] = [str(pbdval_binary()), "run"]
    if cases is not None:
        items = [cases] if isinstance(cases, (str, Path)) else list(cases)
        command += [str(c) for c in items]
    if engines:
        command += ["--engines", ",".join(engines)]
    if methods:
        command += ["--methods", ",".join(methods)]
    for key, value in (settings or {}).items():
        command += ["--set", _assignment(key, value)]
    folder = Path(out) if out is not None else Path(tempfile.mkdtemp(prefix="pbdval-run-"))
    command += ["--out", str(folder)]
    if jobs is not None:
        command += ["--jobs", str(jobs)]
    if timeout is not None:
        command += ["--timeout", repr(float(timeout))]
    if force:
        command += ["--force"]
    completed = subprocess.run(command, stdout=subprocess.PIPE if quiet else None,
                               stderr=subprocess.PIPE, text=True, check=False)
    # Exit status 0 is the command's word that it wrote results.json now; any other status
    # leaves whatever `out` held before, which is not this call's result.
    if completed.returncode != 0:
        if not quiet:
            sys.stderr.write(completed.stderr or "")
        raise CommandError(completed.returncode, command, completed.stdout, completed.stderr)
    return load_results(folder)
