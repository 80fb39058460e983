"""Scenes, engines, stepping and metrics from Python: typed wrappers of the C++ core.

Everything here goes through the same C++ code as the pbdval command: the scene loader, the
engine registry (built-in engines and the external-engine catalogue), the stepping loop with its
divergence checks (validation/run/simulation.h) and the one measurement path
(validation/run/run_execution.h ``measureSamples``). Nothing in Python computes a metric.

Conventions (docs/python.md): SI units; world frame; quaternions in (w, x, y, z) order, the
body's scene frame to world; bodies in scene order; a trajectory stacks samples on axis 0.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from pbdval.errors import ArgumentError, BuildMissingError, ResultsError, SceneError

if TYPE_CHECKING:  # pragma: no cover
    from types import ModuleType

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
ParameterValue = bool | int | float | str | Sequence[float]


def _core() -> ModuleType:
    try:
        from pbdval import _core as core
    except ImportError as error:  # the extension is built by CMake, not by pip
        raise BuildMissingError(
            "pbdval._core is not built: run 'cmake --build --preset release' (or scripts/test) "
            "and 'scripts/install-deps' (it puts the build folder on the venv's path); "
            f"import failed with: {error}"
        ) from error
    return core


# ---- argument checks (docs/python.md#errors) ---------------------------------------------------


def _seconds(name: str, value: object, *, zero: bool = False) -> float:
    """`value` as a finite number of seconds > 0 (>= 0 with `zero`), else ArgumentError."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ArgumentError(f"{name}: expected a number of seconds, got {value!r}")
    seconds = float(value)
    if not math.isfinite(seconds) or seconds < 0 or (seconds == 0 and not zero):
        expected = ">= 0" if zero else "> 0"
        raise ArgumentError(f"{name}: expected a finite number of seconds {expected}, got {value!r}")
    return seconds


def _instance(name: str, value: object, kind: type) -> None:
    if not isinstance(value, kind):
        raise ArgumentError(f"{name}: expected a pbdval.{kind.__name__}, got {type(value).__name__}")


def _file_name(path: object) -> str:
    """A path argument as text; ArgumentError for what is not a path."""
    if not isinstance(path, (str, os.PathLike)):
        raise ArgumentError(f"path: expected a str or os.PathLike, got {type(path).__name__}")
    text = os.fspath(path)
    if not isinstance(text, str):
        raise ArgumentError(f"path: expected a text path, got {type(text).__name__}")
    return text


# ---- engines and methods -------------------------------------------------------------------


@dataclass(frozen=True)
class Parameter:
    """A method parameter's declaration (adapters/parameters.h)."""

    name: str
    kind: str  # real, integer, bool, choice, duration
    default: str
    expected: str  # "a number in (0, 2)", ...
    unit: str
    description: str
    choices: tuple[str, ...] = ()
    minimum: float | None = None
    maximum: float | None = None


@dataclass(frozen=True)
class MethodInfo:
    name: str
    engine: str
    description: str
    default: bool  # the engine's default method
    parameters: tuple[Parameter, ...]


@dataclass(frozen=True)
class FeatureSupport:
    """One entry of an engine's feature table (docs/engines.md#features): how the engine maps a
    scene feature or a group of features (a dotted prefix), for some or every method."""

    feature: str
    support: str  # native | approximated | unsupported
    text: str
    methods: tuple[str, ...] = ()  # empty: every method


@dataclass(frozen=True)
class EngineInfo:
    name: str
    default_method: str
    run_by_default: bool
    honoured_settings: tuple[str, ...]
    methods: tuple[MethodInfo, ...]
    #: The engine's feature table (empty for a catalogue entry that declares none).
    features: tuple[FeatureSupport, ...] = ()


class Engines:
    """The engines the pbdval command sees: built in, and the external engines of the catalogue
    (``engines/*.json``, then the folders of ``$PBDVAL_ENGINE_CATALOGUE``, which add to them), read when
    this object is created."""

    def __init__(self) -> None:
        core = _core()
        self._registry = core._Registry()
        infos: list[EngineInfo] = []
        for e in core._engines(self._registry):
            methods = tuple(
                MethodInfo(
                    name=m["name"],
                    engine=m["engine"],
                    description=m["description"],
                    default=m["default"],
                    parameters=tuple(
                        Parameter(
                            name=p["name"],
                            kind=p["kind"],
                            default=p["default"],
                            expected=p["expected"],
                            unit=p["unit"],
                            description=p["description"],
                            choices=tuple(p.get("choices", ())),
                            minimum=p.get("minimum"),
                            maximum=p.get("maximum"),
                        )
                        for p in m["parameters"]
                    ),
                )
                for m in e["methods"]
            )
            infos.append(
                EngineInfo(
                    name=e["name"],
                    default_method=e["default_method"],
                    run_by_default=e["run_by_default"],
                    honoured_settings=tuple(e["honoured_settings"]),
                    methods=methods,
                    features=tuple(FeatureSupport(feature=f["feature"], support=f["support"], text=f["text"],
                                                  methods=tuple(f["methods"])) for f in e["features"]),
                )
            )
        self._engines = {info.name: info for info in infos}

    def names(self) -> list[str]:
        """Engine names in registration order."""
        return list(self._engines)

    def __iter__(self) -> Iterator[EngineInfo]:
        return iter(self._engines.values())

    def engine(self, name: str) -> EngineInfo:
        try:
            return self._engines[name]
        except KeyError:
            raise ValueError(f"unknown engine {name!r}; known: {', '.join(self._engines)}"
                             + _core()._did_you_mean(name, list(self._engines))) from None

    def methods(self, engine: str | None = None) -> list[MethodInfo]:
        """Every method, or those of one engine."""
        engines = [self.engine(engine)] if engine else list(self._engines.values())
        return [m for e in engines for m in e.methods]

    def method(self, name: str) -> MethodInfo:
        """A method by name; an engine name gives its default method."""
        if name in self._engines:
            name = self._engines[name].default_method
        for m in self.methods():
            if m.name == name:
                return m
        names = [m.name for m in self.methods()]
        raise ValueError(f"unknown method {name!r}; known: {', '.join(names)}" + _core()._did_you_mean(name, names))


def engines() -> Engines:
    """The engines and their methods (a new registry, catalogue read now)."""
    return Engines()


def _method_name(method: str, registry: Engines) -> str:
    return registry.method(method).name


def _parameters(parameters: Mapping[str, ParameterValue] | None) -> dict[str, ParameterValue]:
    return dict(parameters or {})


# ---- scenes ----------------------------------------------------------------------------------


class Scene:
    """A scene file loaded by the pbdval loader (the seed's JSON format, docs/scene-format.md).

    Raises :class:`pbdval.SceneError` (file, JSON path, message) for a file it cannot load.
    """

    def __init__(self, path: str | Path, *, strict: bool = False) -> None:
        core = _core()
        file = _file_name(path)
        if "\x00" in file:  # a C path ends at the NUL: "x.json\0junk" would load x.json
            raise SceneError(repr(file), "", "a file name cannot contain a NUL character")
        self._handle = core._load_scene(file, bool(strict))
        summary = core._scene_summary(self._handle)
        self.file: str = summary["file"]
        self.body_ids: IntArray = np.asarray(summary["body_ids"], dtype=np.int64)
        self.time_step: float = float(summary["time_step"])
        self.gravity: FloatArray = np.asarray(summary["gravity"], dtype=np.float64)
        #: unknown keys and other warnings, "FILE: PATH: MESSAGE" (strict=True makes them errors)
        self.warnings: list[str] = list(summary["warnings"])

    @property
    def body_count(self) -> int:
        return int(self.body_ids.size)

    def run_length(self, engines: Engines | None = None) -> tuple[float, float]:
        """(duration, sample interval) in seconds, from the Validation block (0: every step)."""
        registry = engines or Engines()
        duration, interval = _core()._run_length(registry._registry, self._handle)
        return float(duration), float(interval)

    def resolved(
        self,
        method: str = "pbd",
        parameters: Mapping[str, ParameterValue] | None = None,
        *,
        duration: float | None = None,
        sample_interval: float | None = None,
        engines: Engines | None = None,
    ) -> dict[str, Any]:
        """The resolved scene (docs/external-engines.md) as a dict: what `pbdval export-scene`
        writes, with `method` and its parameters (defaults, then `parameters`)."""
        registry = engines or Engines()
        resolved: dict[str, Any] = _core()._resolved_scene(
            registry._registry,
            self._handle,
            _method_name(method, registry),
            _parameters(parameters),
            0.0 if duration is None else _seconds("duration", duration),
            -1.0 if sample_interval is None else _seconds("sample_interval", sample_interval, zero=True),
        )
        return resolved

    def __repr__(self) -> str:
        return f"Scene({self.file!r}, bodies={self.body_count})"


def load_scene(path: str | Path, *, strict: bool = False) -> Scene:
    """Loads a scene file; see :class:`Scene`."""
    return Scene(path, strict=strict)


# ---- states and trajectories -------------------------------------------------------------------


class BodyStates:
    """All bodies' states at one time, as views into one (N, 14) array ``packed``:
    id, position (3), quaternion w x y z (4), velocity (3), angular velocity (3)."""

    def __init__(self, body_count: int) -> None:
        self.time: float = 0.0
        self.packed: FloatArray = np.zeros((body_count, 14), dtype=np.float64)

    @property
    def ids(self) -> IntArray:
        return self.packed[:, 0].astype(np.int64)

    @property
    def positions(self) -> FloatArray:
        """(N, 3) centres of mass, m."""
        return self.packed[:, 1:4]

    @property
    def quaternions(self) -> FloatArray:
        """(N, 4) orientations (w, x, y, z): the body's scene frame to world."""
        return self.packed[:, 4:8]

    @property
    def velocities(self) -> FloatArray:
        """(N, 3) linear velocities of the centres of mass, m/s."""
        return self.packed[:, 8:11]

    @property
    def angular_velocities(self) -> FloatArray:
        """(N, 3) angular velocities, rad/s, world frame."""
        return self.packed[:, 11:14]


@dataclass
class Trajectory:
    """Samples of a run: times (T,), body ids (N,), positions (T, N, 3), quaternions (T, N, 4)
    in (w, x, y, z), velocities (T, N, 3), angular velocities (T, N, 3); and, when the engine
    reads particles back (cloth and solid vertices, in the scene's particle order), particle
    positions and velocities (T, P, 3), else None; when it reads Cosserat-rod segments back
    (the PBD library), segment rotations (T, S, 4) in (w, x, y, z), director frame -> world, and
    angular velocities (T, S, 3), world, else None."""

    times: FloatArray
    ids: IntArray
    positions: FloatArray
    quaternions: FloatArray
    velocities: FloatArray
    angular_velocities: FloatArray
    particle_positions: FloatArray | None = None
    particle_velocities: FloatArray | None = None
    segment_rotations: FloatArray | None = None
    segment_angular_velocities: FloatArray | None = None

    @classmethod
    def _from_core(cls, d: Mapping[str, Any]) -> Trajectory:
        return cls(
            times=np.asarray(d["times"]),
            ids=np.asarray(d["ids"], dtype=np.int64),
            positions=np.asarray(d["positions"]),
            quaternions=np.asarray(d["quaternions"]),
            velocities=np.asarray(d["velocities"]),
            angular_velocities=np.asarray(d["angular_velocities"]),
            particle_positions=np.asarray(d["particle_positions"]) if "particle_positions" in d else None,
            particle_velocities=np.asarray(d["particle_velocities"]) if "particle_velocities" in d else None,
            segment_rotations=np.asarray(d["segment_rotations"]) if "segment_rotations" in d else None,
            segment_angular_velocities=(
                np.asarray(d["segment_angular_velocities"]) if "segment_angular_velocities" in d else None
            ),
        )

    @classmethod
    def read(
        cls, path: str | Path, *, particles: str | Path | None = None, segments: str | Path | None = None
    ) -> Trajectory:
        """Reads a trajectory file of `pbdval simulate`/`run` with the suite's own reader: NPY
        when the name ends in .npy (`pbdval run --trajectory-format npy`), else CSV. Errors name
        the file and the line or row. `particles`: the file of `pbdval simulate --particles`
        written with it (CSV or NPY), attached as particle_positions/velocities; `segments`: the
        file of `pbdval simulate --segments`, attached as segment_rotations/angular_velocities;
        their sample times must be the trajectory's."""
        trajectory = cls._from_core(_core()._read_trajectory(_file_name(path)))

        def attached_times(file: str | Path, times: FloatArray) -> None:
            nonlocal trajectory
            if trajectory.ids.size == 0:
                # A scene without rigid bodies: the body file has no rows, the times come from
                # the particle or segment file.
                count = times.size
                trajectory = replace(
                    trajectory, times=times, positions=np.zeros((count, 0, 3)),
                    quaternions=np.zeros((count, 0, 4)), velocities=np.zeros((count, 0, 3)),
                    angular_velocities=np.zeros((count, 0, 3)))
            if times.shape != trajectory.times.shape or not np.allclose(times, trajectory.times, rtol=0, atol=1e-9):
                raise ResultsError(
                    f"{file}: its {times.size} sample times are not those of {path} "
                    f"({trajectory.times.size} samples)"
                )

        if particles is not None:
            times, positions, velocities = read_particles(particles)
            attached_times(particles, times)
            trajectory.particle_positions = positions
            trajectory.particle_velocities = velocities
        if segments is not None:
            times, rotations, angular = read_segments(segments)
            attached_times(segments, times)
            trajectory.segment_rotations = rotations
            trajectory.segment_angular_velocities = angular
        return trajectory

    @classmethod
    def read_csv(cls, path: str | Path) -> Trajectory:
        """Reads a trajectory CSV (or NPY, by its extension): the same as `read`."""
        return cls.read(path)

    def __len__(self) -> int:
        return int(self.times.size)

    def _arrays(self) -> tuple[FloatArray | None, ...]:
        """The arrays the core takes: the body arrays, then the particle arrays and the segment
        arrays (or None)."""
        bodies = tuple(
            np.ascontiguousarray(a, dtype=np.float64)
            for a in (self.times, self.positions, self.quaternions, self.velocities, self.angular_velocities)
        )
        optional = tuple(
            None if a is None else np.ascontiguousarray(a, dtype=np.float64)
            for a in (self.particle_positions, self.particle_velocities,
                      self.segment_rotations, self.segment_angular_velocities)
        )
        return bodies + optional


def _read_indexed_table(path: str | Path, header: str, what: str) -> FloatArray:
    """A file of `pbdval simulate --particles` or `--segments`: CSV with exactly `header`, or NPY
    of the same table by the extension, as (T, count, columns): every sample lists its `what`
    0..count-1 in order at one time. Errors name the file."""
    path = Path(_file_name(path))
    if "\x00" in str(path):
        raise ResultsError(f"{path!r}: a file name cannot contain a NUL character")
    columns = len(header.split(","))
    try:
        if path.suffix == ".npy":
            table = np.load(path, allow_pickle=False)
        else:
            with path.open() as f:
                line = f.readline().strip()
                if line != header:
                    raise ValueError(f"line 1: expected the header {header}, got {line!r}")
                table = np.loadtxt(f, delimiter=",", ndmin=2)
    except (OSError, ValueError) as error:
        raise ResultsError(f"{path}: {error}") from None
    if table.ndim != 2 or table.shape[1] != columns:
        raise ResultsError(f"{path}: expected rows of {columns} columns ({header}), got shape {table.shape}")
    if table.shape[0] == 0:
        raise ResultsError(f"{path}: no rows")
    count = int(np.count_nonzero(table[:, 0] == table[0, 0]))
    if table.shape[0] % count != 0:
        raise ResultsError(f"{path}: {table.shape[0]} rows are not whole samples of {count} {what}")
    samples: FloatArray = table.reshape(-1, count, columns)
    if not np.array_equal(samples[:, :, 1], np.tile(np.arange(count), (samples.shape[0], 1))):
        raise ResultsError(f"{path}: every sample must list {what} 0..{count - 1} in order")
    if not np.all(samples[:, :, 0] == samples[:, :1, 0]):
        raise ResultsError(f"{path}: the rows of a sample must share its time")
    return samples


def read_particles(path: str | Path) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Reads a particle file of `pbdval simulate --particles` (CSV with the header
    t,index,x,y,z,vx,vy,vz, or NPY of the same (rows, 8) table, by the extension) into
    times (T,), positions (T, P, 3) and velocities (T, P, 3). Errors name the file."""
    samples = _read_indexed_table(path, "t,index,x,y,z,vx,vy,vz", "particles")
    return samples[:, 0, 0].copy(), samples[:, :, 2:5].copy(), samples[:, :, 5:8].copy()


def read_segments(path: str | Path) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Reads a segment file of `pbdval simulate --segments` (CSV with the header
    t,index,qw,qx,qy,qz,wx,wy,wz, or NPY of the same (rows, 9) table, by the extension) into
    times (T,), rotations (T, S, 4) as (w, x, y, z) and angular velocities (T, S, 3). Errors
    name the file."""
    samples = _read_indexed_table(path, "t,index,qw,qx,qy,qz,wx,wy,wz", "segments")
    return samples[:, 0, 0].copy(), samples[:, :, 2:6].copy(), samples[:, :, 6:9].copy()


# ---- stepping ------------------------------------------------------------------------------------


class Simulation:
    """A scene loaded into one engine with one method, stepped from Python.

    ``parameters`` are the method's parameters and the scene's Simulation settings, exactly as
    ``pbdval run --set`` takes them (``{"substeps": 40, "timeStepSize": 0.002}``). Engines that
    run in another process (the external engines) cannot be stepped: use :func:`simulate`.
    Raises :class:`pbdval.UnsupportedError` when the method cannot represent the scene.
    """

    def __init__(
        self,
        scene: Scene,
        method: str = "pbd",
        parameters: Mapping[str, ParameterValue] | None = None,
        *,
        engines: Engines | None = None,
    ) -> None:
        _instance("scene", scene, Scene)
        registry = engines or Engines()
        self.scene = scene
        self._stepper = _core()._Stepper(
            registry._registry, scene._handle, _method_name(method, registry), _parameters(parameters)
        )
        self.facts: dict[str, Any] = self._stepper.facts()

    @property
    def time(self) -> float:
        """Simulated time, s."""
        return float(self._stepper.time())

    def step(self, count: int = 1) -> None:
        """Advances `count` scene steps, 0 <= count <= 10^8 (the most steps of one run), with the
        GIL released; Ctrl-C interrupts it within about 50 ms (KeyboardInterrupt, the steps taken
        kept). Raises :class:`pbdval.DivergenceError` when the state becomes non-finite or blows
        up, :class:`pbdval.ArgumentError` for another count."""
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)):
            raise ArgumentError(f"step: count: expected an int, got {count!r}")
        limit = int(_core().max_steps_per_run)
        if not 0 <= int(count) <= limit:
            raise ArgumentError(f"step: count: expected 0 <= count <= {limit}, got {count}")
        self._stepper.step(int(count))

    def state(self) -> BodyStates:
        """The bodies' states now, in new arrays."""
        return self.read(BodyStates(self._stepper.body_count()))

    def read(self, out: BodyStates) -> BodyStates:
        """The bodies' states now, written into `out` (no allocation): the fast path.
        `out.packed` must be the writeable, C-contiguous float64 (N, 14) array it is made with;
        another array raises :class:`pbdval.ArgumentError` (it would be filled as a copy)."""
        _instance("out", out, BodyStates)
        packed = out.packed
        if (not isinstance(packed, np.ndarray) or packed.dtype != np.float64 or not packed.flags.c_contiguous
                or not packed.flags.writeable or packed.shape != (self._stepper.body_count(), 14)):
            described = (f"{packed.dtype} {packed.shape}{'' if packed.flags.c_contiguous else ' not C-contiguous'}"
                         f"{'' if packed.flags.writeable else ' read-only'}"
                         if isinstance(packed, np.ndarray) else type(packed).__name__)
            raise ArgumentError(f"read: out.packed: expected a writeable C-contiguous float64 array of shape "
                                f"({self._stepper.body_count()}, 14), got {described}")
        out.time = self._stepper.read_into(packed)
        return out

    def state_hash(self) -> str | None:
        """For the deterministic PBD engine: a hash of the complete state now."""
        state_hash = self._stepper.facts().get("state_hash")
        return None if state_hash is None else str(state_hash)


@dataclass
class RunInfo:
    """How a run went: status ok/suspect/diverged/timeout/unsupported/error, and the parity record."""

    engine: str
    method: str
    status: str
    reason: str
    steps: int
    wall_time_s: float
    engine_version: str
    integrator_steps_per_scene_step: int
    contact_margin: float
    parameters: dict[str, str]
    settings: dict[str, str]
    state_hash: str | None = None

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def simulate(
    scene: Scene,
    method: str = "pbd",
    parameters: Mapping[str, ParameterValue] | None = None,
    *,
    duration: float | None = None,
    sample_interval: float | None = None,
    wall_time_limit: float | None = None,
    engines: Engines | None = None,
) -> tuple[RunInfo, Trajectory]:
    """Runs a scene as ``pbdval simulate`` does (the runner's stepping loop, external engines
    through their protocol) and returns the run's status and its samples. Duration (s, > 0)
    and sample interval (s, >= 0; 0: every step) default to the scene's Validation block;
    wall_time_limit (s, > 0; ``math.inf``: none) to ``pbdval run``'s 600 s. Engine failures
    are a status, not an exception; a NaN, zero or negative value raises
    :class:`pbdval.ArgumentError`."""
    _instance("scene", scene, Scene)
    registry = engines or Engines()
    limit = float(_core().default_wall_time_limit)
    if wall_time_limit is not None:
        limit = (0.0 if isinstance(wall_time_limit, (int, float)) and wall_time_limit == math.inf
                 else _seconds("wall_time_limit", wall_time_limit))
    run, states = _core()._simulate(
        registry._registry,
        scene._handle,
        _method_name(method, registry),
        _parameters(parameters),
        0.0 if duration is None else _seconds("duration", duration),
        -1.0 if sample_interval is None else _seconds("sample_interval", sample_interval, zero=True),
        limit,
    )
    return RunInfo(**run), Trajectory._from_core(states)


# ---- metrics -------------------------------------------------------------------------------------


def _check_trajectory(name: str, trajectory: object) -> None:
    """A Trajectory with at least one sample and finite times, else ArgumentError."""
    _instance(name, trajectory, Trajectory)
    assert isinstance(trajectory, Trajectory)
    times = np.asarray(trajectory.times)
    if times.ndim != 1 or times.size == 0:
        raise ArgumentError(f"{name}.times: expected a 1-D array of at least one sample time, got shape {times.shape}")
    if not np.issubdtype(times.dtype, np.number) or not np.all(np.isfinite(times.astype(np.float64))):
        raise ArgumentError(f"{name}.times: expected finite sample times, got {times!r}")


@dataclass
class Metrics:
    """Metrics by their stable names (docs/metrics.md), as in results.json."""

    values: dict[str, float]
    joint_error_by_type: dict[str, dict[str, Any]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    reference: str = ""
    #: The per-sample values behind the metrics, by name: "times", "energy_drift",
    #: "joint_error_linear/<type>" (m), "joint_error_angular/<type>" (rad),
    #: "motor_tracking/<quantity>", "penetration" (m), "trajectory_error" (m),
    #: "rotation_error" (rad); at each sample the largest value over the joints of a type, the
    #: overlapping pairs or the compared bodies; NaN where a sample has none. Absent with the metric.
    series: dict[str, FloatArray] = field(default_factory=dict)

    def __getitem__(self, name: str) -> float:
        return self.values[name]

    def __contains__(self, name: object) -> bool:
        return name in self.values

    def get(self, name: str, default: float | None = None) -> float | None:
        return self.values.get(name, default)


def measure(
    scene: Scene,
    trajectory: Trajectory,
    *,
    reference: Trajectory | bool | None = None,
    contact_margin: float = 0.0,
    integration_step: float | None = None,
    engines: Engines | None = None,
) -> Metrics:
    """The suite's metrics of `trajectory` (the runner's own measurement code).

    reference: None uses the case's analytic reference when its Validation block has one
    (integrated at `integration_step`, default the scene's step; the runner uses the engine's
    integrator step, e.g. h/subSteps for PBD); False: no trajectory metrics; a Trajectory: that
    run, resampled at `trajectory`'s times. contact_margin: the engine's designed overlap (m),
    subtracted from penetration depths (RunInfo.contact_margin).

    Raises :class:`pbdval.ArgumentError` for an empty trajectory, a NaN or infinite time,
    margin or integration step, or arguments of the wrong type; :class:`pbdval.DivergenceError`
    naming the first sample that holds NaN or Inf (or a blow-up beyond 1e6 m or m/s): a
    diverged run has no metrics, as in the runner.
    """
    _instance("scene", scene, Scene)
    _check_trajectory("trajectory", trajectory)
    if isinstance(contact_margin, bool) or not isinstance(contact_margin, (int, float, np.integer, np.floating)) \
            or not math.isfinite(float(contact_margin)):
        raise ArgumentError(f"contact_margin: expected a finite number of metres, got {contact_margin!r}")
    if integration_step is not None:
        _seconds("integration_step", integration_step)
    if not (reference is None or isinstance(reference, (bool, Trajectory))):
        raise ArgumentError(
            f"reference: expected None, False or a pbdval.Trajectory, got {type(reference).__name__}")
    if isinstance(reference, Trajectory):
        _check_trajectory("reference", reference)
    registry = engines or Engines()
    ref: Any
    if isinstance(reference, Trajectory):
        times, positions, quaternions, velocities, angular, particle_x, particle_v, _, _ = reference._arrays()
        ref = {
            "times": times,
            "positions": positions,
            "quaternions": quaternions,
            "velocities": velocities,
            "angular_velocities": angular,
        }
        if particle_x is not None:
            ref["particle_positions"] = particle_x
            ref["particle_velocities"] = particle_v
    else:
        ref = reference
    d = _core()._measure(
        registry._registry, scene._handle, *trajectory._arrays(), ref, float(contact_margin),
        float(integration_step or 0.0)
    )
    return Metrics(
        values={k: float(v) for k, v in d["values"].items()},
        joint_error_by_type={k: dict(v) for k, v in d["joint_error_by_type"].items()},
        notes=list(d["notes"]),
        reference=d["reference"],
        series={k: np.asarray(v, dtype=np.float64) for k, v in d["series"].items()},
    )


@dataclass
class Energy:
    """Energy terms per sample, J, and the scale E_ref the drift metrics divide by."""

    translational: FloatArray
    rotational: FloatArray
    gravitational: FloatArray
    spring: FloatArray
    total: FloatArray
    scale: float
    # XPBD particle constraints' ½ k C² and XPBD rods' ½ Cᵀ α⁻¹ C (0 without particles; the rods'
    # only with the segments)
    elastic: FloatArray | None = None

    @property
    def relative_drift(self) -> FloatArray:
        """(E(t) - E(0)) / E_ref per sample: the series behind energy_drift_*."""
        drift: FloatArray = (self.total - self.total[0]) / self.scale
        return drift


def energy(scene: Scene, trajectory: Trajectory, *, engines: Engines | None = None) -> Energy:
    """The energy of every sample (validation/measure/mechanics.h). Raises :class:`pbdval.ArgumentError`
    for an empty trajectory or a NaN or infinite time."""
    _instance("scene", scene, Scene)
    _check_trajectory("trajectory", trajectory)
    registry = engines or Engines()
    d = _core()._energy(registry._registry, scene._handle, *trajectory._arrays())
    return Energy(
        translational=d["translational"],
        rotational=d["rotational"],
        gravitational=d["gravitational"],
        spring=d["spring"],
        elastic=d["elastic"],
        total=d["total"],
        scale=float(d["scale"]),
    )
