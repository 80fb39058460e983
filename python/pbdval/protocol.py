"""The external-engine protocol, version 1, from the engine's side (docs/external-engines.md).

An engine is run as

    <command...> --scene RESOLVED.json --out OUTDIR

with its catalogue's folder as working directory and PBDVAL_PROTOCOL=1 in its environment. It
reads the resolved scene (`pbdval export-scene`, schema docs/schemas/resolved-scene.schema.json),
writes its trajectory, OUTDIR/trajectory.csv (the CSV of `pbdval simulate`) or the same rows as
OUTDIR/trajectory.npy (binary; what TrajectoryWriter writes), and OUTDIR/status.json, and exits 0
whenever status.json was written, whatever the status.

This module holds everything an engine shares: typed dataclasses for the resolved scene and a
reader that checks it (errors name the file and the JSON path), the step plan, a trajectory
writer, the status writer (atomic), and the command-line parser; and `serve_runs`, the loop of
a persistent engine process (serve protocol 1: imports paid once, each run a forked child).
"""

from __future__ import annotations

# What an engine server imports is paid in every `pbdval run` that starts one: argparse and
# traceback are imported where they are used (a command line that is not the runner's own form,
# a failed run), and temporary files are made without tempfile (docs/benchmarks.md, seventh pass).
import ctypes
import gc
import itertools
import json
import math
import os
import select
import signal
import socket
import sys
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, BinaryIO, Self

import numpy as np
from numpy.typing import NDArray

PROTOCOL_VERSION = 1
RESOLVED_SCENE_FORMAT = "pbdval.resolved-scene"
RESOLVED_SCENE_VERSION = 1
TRAJECTORY_FILE = "trajectory.csv"
#: The binary form of the same rows (an NPY file of float64, shape (rows, 15)), which
#: TrajectoryWriter writes by default: formatting every number as text costs more per sample
#: than most engines' step (docs/benchmarks.md#python).
TRAJECTORY_NPY_FILE = "trajectory.npy"
STATUS_FILE = "status.json"
#: Particle states (cloth, solids), when the scene has particles: the CSV of
#: `pbdval simulate --particles`, or the same rows as NPY, shape (rows, 8).
PARTICLES_FILE = "particles.csv"
PARTICLES_NPY_FILE = "particles.npy"
PARTICLES_HEADER = "t,index,x,y,z,vx,vy,vz"
TRAJECTORY_HEADER = "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"
STATUSES = ("ok", "unsupported", "diverged", "error")
#: Positions beyond this many metres or speeds beyond this many m/s count as a blow-up
#: (validation/run/simulation.h, kDivergenceLimit).
DIVERGENCE_LIMIT = 1e6

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]  # w, x, y, z
# A vector or quaternion as the engines hold it: a tuple or list of floats, or a numpy array.
FloatVector = Sequence[float] | NDArray[np.floating[Any]]
ParameterValue = bool | int | float | str


class SceneError(ValueError):
    """A resolved scene that does not match the format: names the file and the JSON path."""


# ---------------------------------------------------------------------------------------------
# Reading JSON with paths in the messages


class _Reader:
    def __init__(self, source: str) -> None:
        self.source = source

    def fail(self, path: str, expected: str, got: Any) -> SceneError:
        shown = json.dumps(got) if not isinstance(got, _Missing) else "nothing"
        if len(shown) > 60:
            shown = shown[:57] + "..."
        return SceneError(f"{self.source}: {path}: expected {expected}, got {shown}")

    def get(self, obj: Mapping[str, Any], key: str, path: str) -> Any:
        if key not in obj:
            raise self.fail(f"{path}.{key}" if path else key, "a value", _MISSING)
        return obj[key]

    def obj(self, value: Any, path: str) -> Mapping[str, Any]:
        if not isinstance(value, dict):
            raise self.fail(path, "an object", value)
        return value

    def arr(self, value: Any, path: str) -> list[Any]:
        if not isinstance(value, list):
            raise self.fail(path, "an array", value)
        return value

    def num(self, value: Any, path: str) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise self.fail(path, "a finite number", value)
        return float(value)

    def integer(self, value: Any, path: str) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.fail(path, "an integer", value)
        return value

    def boolean(self, value: Any, path: str) -> bool:
        if not isinstance(value, bool):
            raise self.fail(path, "true or false", value)
        return value

    def string(self, value: Any, path: str) -> str:
        if not isinstance(value, str):
            raise self.fail(path, "a string", value)
        return value

    def vec(self, value: Any, path: str, size: int = 3) -> tuple[float, ...]:
        items = self.arr(value, path)
        if len(items) != size:
            raise self.fail(path, f"an array of {size} numbers", value)
        for i, v in enumerate(items):  # self.num's test, each element's path made on failure only
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise self.fail(f"{path}[{i}]", "a finite number", v)
        return tuple(map(float, items))


class _Missing:
    pass


_MISSING = _Missing()


# ---------------------------------------------------------------------------------------------
# The resolved scene


@dataclass(frozen=True)
class Shape:
    """A collision shape in the body's scene frame. `type`: none, sphere, box, cylinder, torus,
    sdf, hollowSphere, hollowBox. Only the fields of the type are set."""

    type: str
    inverted: bool = False
    radius: float | None = None  # sphere, cylinder, hollowSphere
    half_extents: Vec3 | None = None  # box, hollowBox
    height: float | None = None  # cylinder (along axis)
    axis: Vec3 | None = None  # cylinder, torus (the y axis of the scene frame)
    major_radius: float | None = None  # torus
    minor_radius: float | None = None  # torus
    wall_half_thickness: float | None = None  # hollowSphere, hollowBox
    mesh_file: str | None = None  # sdf: absolute path of the OBJ
    mesh_scale: Vec3 | None = None  # sdf


@dataclass(frozen=True)
class Material:
    friction: float
    restitution: float


@dataclass(frozen=True)
class Body:
    id: int
    index: int
    json_path: str
    dynamic: bool
    mass: float  # kg, 0 for static bodies
    principal_inertia: Vec3  # kg m², about the centre of mass along the principal axes
    principal_com: Vec3  # centre of mass in the scene frame
    principal_rotation: Quat  # principal frame → scene frame
    position: Vec3  # centre of mass, world, t = 0
    rotation: Quat  # scene frame → world, t = 0
    scene_origin: Vec3  # the scene frame's origin in world, t = 0
    world_principal_rotation: Quat  # principal frame → world, t = 0
    velocity: Vec3  # of the centre of mass, world
    angular_velocity: Vec3  # world
    shape: Shape
    material: Material
    geometry_file: str | None = None  # absolute path of the body's OBJ (scene frame, unscaled)
    geometry_scale: Vec3 | None = None  # applied to the OBJ's vertices


@dataclass(frozen=True)
class BodyCoordinates:
    """A point or direction in one body's scene frame and principal frame."""

    scene: Vec3
    principal: Vec3


@dataclass(frozen=True)
class JointVector:
    """A joint's point or axis: in world at t = 0 and in each body's frames (None: no body)."""

    world: Vec3
    body1: BodyCoordinates | None
    body2: BodyCoordinates | None


@dataclass(frozen=True)
class MotorTarget:
    constant: float
    times: tuple[float, ...]
    values: tuple[float, ...]
    repeat: bool

    def value_at(self, time: float) -> float:
        """The set point at `time`: piecewise linear in the samples, held before the first and
        after the last, repeated with period t_last - t_first when `repeat` (pbd/model/scene.h)."""
        if not self.times:
            return self.constant
        first, last = self.times[0], self.times[-1]
        t = time
        if self.repeat and last > first and t > last:
            t = first + math.fmod(t - first, last - first)
        if t <= first:
            return self.values[0]
        if t >= last:
            return self.values[-1]
        for i in range(1, len(self.times)):
            if t <= self.times[i]:
                t0, t1 = self.times[i - 1], self.times[i]
                s = (t - t0) / (t1 - t0)
                return self.values[i - 1] + s * (self.values[i] - self.values[i - 1])
        return self.values[-1]


@dataclass(frozen=True)
class Joint:
    type: str  # ball, hinge, slider, universal, ... (pbd::jointTypeName)
    block: str  # the scene block, e.g. "HingeJoints"
    json_path: str
    body1: int | None  # scene ids
    body2: int | None
    points: dict[str, JointVector]  # anchor | anchor1, anchor2
    axes: dict[str, JointVector]  # axis | axis1, axis2
    rest_length: float | None = None
    stiffness: float | None = None
    target: MotorTarget | None = None
    particle: int | None = None


@dataclass(frozen=True)
class ContactPair:
    bodies: tuple[int, int]  # scene ids
    friction: float
    restitution: float
    explicit: bool


@dataclass(frozen=True)
class Particle:
    position: Vec3
    velocity: Vec3
    mass: float


@dataclass(frozen=True)
class ParticleModel:
    """What cloth and solids share: the model's particles are `particles[first_particle :
    first_particle + particle_count]`, its elements and `static_particles` index them locally;
    `simulation_method`/`method_name` is the scene's method (docs/methods.md), `material` its
    settings resolved for it (the seed's forced defaults applied)."""

    id: int
    json_path: str
    first_particle: int
    particle_count: int
    static_particles: tuple[int, ...]
    density: float | None  # kg/m^2 (cloth) or kg/m^3 (solids); None: every vertex mass 1 (the seed's)
    friction: float
    restitution: float
    simulation_method: int
    method_name: str
    material: dict[str, ParameterValue]


@dataclass(frozen=True)
class TriangleModel(ParticleModel):
    """A cloth (`TriangleModels[i]`). `material`: stiffness (N/m per edge for xpbd_distance, a
    fraction per iteration for distance), bendingStiffness, xxStiffness, yyStiffness,
    xyStiffness, xyPoissonRatio, yxPoissonRatio, normalizeStretch, normalizeShear."""

    triangles: np.ndarray = field(repr=False, kw_only=True)  # (n, 3) int64, local indices
    bending_method: int = field(kw_only=True)
    bending_method_name: str = field(kw_only=True)


@dataclass(frozen=True)
class TetModel(ParticleModel):
    """A solid (`TetModels[i]`): `tets` positively oriented, `boundary_faces` counter-clockwise
    seen from outside. `material`: stiffness (Young's modulus in Pa for fem_xpbd, N/m per edge
    for xpbd_distance_volume, else a fraction per iteration), poissonRatio, volumeStiffness,
    normalizeStretch, normalizeShear."""

    tets: np.ndarray = field(repr=False, kw_only=True)  # (n, 4) int64, local indices
    boundary_faces: np.ndarray = field(repr=False, kw_only=True)  # (m, 3) int64, local indices


@dataclass(frozen=True)
class Method:
    name: str
    parameters: dict[str, ParameterValue]


@dataclass(frozen=True)
class ResolvedScene:
    source: str
    name: str
    method: Method
    gravity: Vec3
    time_step_size: float
    duration: float
    sample_interval: float
    steps: int
    sample_stride: int
    contact_tolerance: float
    contact_combine_rule: str
    bodies: tuple[Body, ...]
    joints: tuple[Joint, ...]
    contact_pairs: tuple[ContactPair, ...]
    particles: tuple[Particle, ...]
    triangle_models: tuple[TriangleModel, ...]
    tet_models: tuple[TetModel, ...]
    line_models: int  # Cosserat rods (counted; their particles follow the tet models')
    fluid_models: int  # position-based fluids (counted; their particles come last)
    document: dict[str, Any] = field(repr=False, compare=False, default_factory=dict)

    def body_by_id(self, body_id: int) -> Body:
        for b in self.bodies:
            if b.id == body_id:
                return b
        raise KeyError(f"no body with id {body_id}")

    def pair(self, id_a: int, id_b: int) -> ContactPair | None:
        for p in self.contact_pairs:
            if p.bodies in ((id_a, id_b), (id_b, id_a)):
                return p
        return None

    def jointed(self, id_a: int, id_b: int) -> bool:
        """Whether a joint connects the bodies with these ids (either way round). Such bodies
        collide with each other like any others: the seed's rule, kept by every engine."""
        return any({j.body1, j.body2} == {id_a, id_b} for j in self.joints)

    def sample_steps(self) -> list[int]:
        """The step numbers after which a sample is written (0: the initial state): every
        `sample_stride`-th step and the last (validation/run/simulation.cpp)."""
        steps = list(range(0, self.steps + 1, self.sample_stride))  # the stride is >= 1
        if steps[-1] != self.steps:
            steps.append(self.steps)
        return steps

    def parameter(self, name: str, default: ParameterValue) -> ParameterValue:
        """A method parameter, or `default` when the runner did not give it."""
        return self.method.parameters.get(name, default)


def _shape(r: _Reader, s: Mapping[str, Any], path: str) -> Shape:
    kind = r.string(r.get(s, "type", path), f"{path}.type")
    known = ("none", "sphere", "box", "cylinder", "torus", "sdf", "hollowSphere", "hollowBox")
    if kind not in known:
        raise r.fail(f"{path}.type", "one of " + ", ".join(known), kind)
    if kind == "none":
        return Shape(type="none")

    def num(key: str) -> float:
        return r.num(r.get(s, key, path), f"{path}.{key}")

    def vec(key: str) -> Vec3:
        return r.vec(r.get(s, key, path), f"{path}.{key}")  # type: ignore[return-value]

    inverted = r.boolean(s.get("inverted", False), f"{path}.inverted")
    if kind == "sphere":
        return Shape(kind, inverted, radius=num("radius"))
    if kind == "box":
        return Shape(kind, inverted, half_extents=vec("halfExtents"))
    if kind == "cylinder":
        return Shape(kind, inverted, radius=num("radius"), height=num("height"), axis=vec("axis"))
    if kind == "torus":
        return Shape(kind, inverted, major_radius=num("majorRadius"),
                     minor_radius=num("minorRadius"), axis=vec("axis"))
    if kind == "hollowSphere":
        return Shape(kind, inverted, radius=num("radius"),
                     wall_half_thickness=num("wallHalfThickness"))
    if kind == "hollowBox":
        return Shape(kind, inverted, half_extents=vec("halfExtents"),
                     wall_half_thickness=num("wallHalfThickness"))
    return Shape(kind, inverted, mesh_file=r.string(r.get(s, "meshFile", path), f"{path}.meshFile"),
                 mesh_scale=vec("meshScale"))


def _body(r: _Reader, b: Mapping[str, Any], path: str) -> Body:
    pf = r.obj(r.get(b, "principalFrame", path), f"{path}.principalFrame")
    geometry = r.obj(b.get("geometry", {}), f"{path}.geometry")
    gp = f"{path}.geometry"
    pose = r.obj(r.get(b, "pose", path), f"{path}.pose")
    mat = r.obj(r.get(b, "material", path), f"{path}.material")
    pp, mp, pr = f"{path}.pose", f"{path}.material", f"{path}.principalFrame"
    return Body(
        id=r.integer(r.get(b, "id", path), f"{path}.id"),
        index=r.integer(r.get(b, "index", path), f"{path}.index"),
        json_path=r.string(b.get("jsonPath", ""), f"{path}.jsonPath"),
        dynamic=r.boolean(r.get(b, "dynamic", path), f"{path}.dynamic"),
        mass=r.num(r.get(b, "mass", path), f"{path}.mass"),
        principal_inertia=r.vec(r.get(b, "principalInertia", path), f"{path}.principalInertia"),  # type: ignore[arg-type]
        principal_com=r.vec(r.get(pf, "centerOfMass", pr), f"{pr}.centerOfMass"),  # type: ignore[arg-type]
        principal_rotation=r.vec(r.get(pf, "rotation", pr), f"{pr}.rotation", 4),  # type: ignore[arg-type]
        position=r.vec(r.get(pose, "position", pp), f"{pp}.position"),  # type: ignore[arg-type]
        rotation=r.vec(r.get(pose, "rotation", pp), f"{pp}.rotation", 4),  # type: ignore[arg-type]
        scene_origin=r.vec(r.get(pose, "sceneOrigin", pp), f"{pp}.sceneOrigin"),  # type: ignore[arg-type]
        world_principal_rotation=r.vec(r.get(pose, "principalRotation", pp),  # type: ignore[arg-type]
                                       f"{pp}.principalRotation", 4),
        velocity=r.vec(r.get(b, "velocity", path), f"{path}.velocity"),  # type: ignore[arg-type]
        angular_velocity=r.vec(r.get(b, "angularVelocity", path), f"{path}.angularVelocity"),  # type: ignore[arg-type]
        shape=_shape(r, r.obj(r.get(b, "shape", path), f"{path}.shape"), f"{path}.shape"),
        material=Material(friction=r.num(r.get(mat, "friction", mp), f"{mp}.friction"),
                          restitution=r.num(r.get(mat, "restitution", mp), f"{mp}.restitution")),
        geometry_file=(r.string(r.get(geometry, "file", gp), f"{gp}.file") if geometry else None),
        geometry_scale=(r.vec(r.get(geometry, "scale", gp), f"{gp}.scale")  # type: ignore[arg-type]
                        if geometry else None),
    )


def _coords(r: _Reader, v: Any, path: str) -> BodyCoordinates | None:
    if v is None:
        return None
    o = r.obj(v, path)
    return BodyCoordinates(scene=r.vec(r.get(o, "scene", path), f"{path}.scene"),  # type: ignore[arg-type]
                           principal=r.vec(r.get(o, "principal", path), f"{path}.principal"))  # type: ignore[arg-type]


def _vectors(r: _Reader, v: Any, path: str) -> dict[str, JointVector]:
    out: dict[str, JointVector] = {}
    for name, item in r.obj(v, path).items():
        p = f"{path}.{name}"
        o = r.obj(item, p)
        out[name] = JointVector(world=r.vec(r.get(o, "world", p), f"{p}.world"),  # type: ignore[arg-type]
                                body1=_coords(r, o.get("body1"), f"{p}.body1"),
                                body2=_coords(r, o.get("body2"), f"{p}.body2"))
    return out


def _optional_id(r: _Reader, v: Any, path: str) -> int | None:
    return None if v is None else r.integer(v, path)


def _joint(r: _Reader, j: Mapping[str, Any], path: str) -> Joint:
    target = None
    if "target" in j:
        t = r.obj(j["target"], f"{path}.target")
        tp = f"{path}.target"
        times = tuple(r.num(x, f"{tp}.times[{i}]")
                      for i, x in enumerate(r.arr(r.get(t, "times", tp), f"{tp}.times")))
        values = tuple(r.num(x, f"{tp}.values[{i}]")
                       for i, x in enumerate(r.arr(r.get(t, "values", tp), f"{tp}.values")))
        if len(times) != len(values):
            raise r.fail(f"{tp}.values", f"{len(times)} values (one per time)", list(values))
        target = MotorTarget(constant=r.num(r.get(t, "constant", tp), f"{tp}.constant"),
                             times=times, values=values,
                             repeat=r.boolean(r.get(t, "repeat", tp), f"{tp}.repeat"))
    return Joint(
        type=r.string(r.get(j, "type", path), f"{path}.type"),
        block=r.string(r.get(j, "block", path), f"{path}.block"),
        json_path=r.string(j.get("jsonPath", ""), f"{path}.jsonPath"),
        body1=_optional_id(r, r.get(j, "body1", path), f"{path}.body1"),
        body2=_optional_id(r, r.get(j, "body2", path), f"{path}.body2"),
        points=_vectors(r, r.get(j, "points", path), f"{path}.points"),
        axes=_vectors(r, r.get(j, "axes", path), f"{path}.axes"),
        rest_length=r.num(j["restLength"], f"{path}.restLength") if "restLength" in j else None,
        stiffness=r.num(j["stiffness"], f"{path}.stiffness") if "stiffness" in j else None,
        target=target,
        particle=r.integer(j["particle"], f"{path}.particle") if "particle" in j else None,
    )


def parse_resolved_scene(document: Any, source: str = "<resolved scene>") -> ResolvedScene:
    """Checks and converts a resolved-scene document. Raises SceneError naming `source` and the
    JSON path of the first problem."""
    r = _Reader(source)
    d = r.obj(document, "(document)")
    fmt = r.get(d, "format", "")
    if fmt != RESOLVED_SCENE_FORMAT:
        raise r.fail("format", f'"{RESOLVED_SCENE_FORMAT}"', fmt)
    version = r.get(d, "version", "")
    if version != RESOLVED_SCENE_VERSION:
        raise r.fail("version", str(RESOLVED_SCENE_VERSION), version)
    method = r.obj(r.get(d, "method", ""), "method")
    name = method.get("name", "")
    if name is None:
        name = ""
    params = r.obj(method.get("parameters", {}), "method.parameters")
    for key, value in params.items():
        if not isinstance(value, (bool, int, float, str)):
            raise r.fail(f"method.parameters.{key}", "a number, true/false or a string", value)
    deform = r.obj(d.get("deformables", {}), "deformables")
    h = r.num(r.get(d, "timeStepSize", ""), "timeStepSize")
    if h <= 0:
        raise r.fail("timeStepSize", "a positive number", h)
    stride = r.integer(r.get(d, "sampleStride", ""), "sampleStride")
    if stride < 1:
        raise r.fail("sampleStride", "an integer >= 1", stride)
    steps = r.integer(r.get(d, "steps", ""), "steps")
    if steps < 1:
        raise r.fail("steps", "an integer >= 1", steps)
    particle_count = len(r.arr(d.get("particles", []), "particles"))
    for key in ("triangleModels", "tetModels"):
        given = len(r.arr(d.get(key, []), key))
        counted = r.integer(deform.get(key, given), f"deformables.{key}")
        if counted != given:
            raise r.fail(f"deformables.{key}", f"{given} (the length of {key})", counted)
    return ResolvedScene(
        source=r.string(d.get("source", ""), "source"),
        name=r.string(d.get("name", ""), "name"),
        method=Method(name=r.string(name, "method.name"), parameters=dict(params)),
        gravity=r.vec(r.get(d, "gravity", ""), "gravity"),  # type: ignore[arg-type]
        time_step_size=h,
        duration=r.num(r.get(d, "duration", ""), "duration"),
        sample_interval=r.num(r.get(d, "sampleInterval", ""), "sampleInterval"),
        steps=steps,
        sample_stride=stride,
        contact_tolerance=r.num(r.get(d, "contactTolerance", ""), "contactTolerance"),
        contact_combine_rule=r.string(r.get(d, "contactCombineRule", ""), "contactCombineRule"),
        bodies=tuple(_body(r, r.obj(b, f"bodies[{i}]"), f"bodies[{i}]")
                     for i, b in enumerate(r.arr(r.get(d, "bodies", ""), "bodies"))),
        joints=tuple(_joint(r, r.obj(j, f"joints[{i}]"), f"joints[{i}]")
                     for i, j in enumerate(r.arr(r.get(d, "joints", ""), "joints"))),
        contact_pairs=tuple(
            ContactPair(
                bodies=_pair_ids(r, p, i),
                friction=r.num(r.get(p, "friction", f"contactPairs[{i}]"), f"contactPairs[{i}].friction"),
                restitution=r.num(r.get(p, "restitution", f"contactPairs[{i}]"),
                                  f"contactPairs[{i}].restitution"),
                explicit=r.boolean(p.get("explicit", False), f"contactPairs[{i}].explicit"))
            for i, p in enumerate(r.arr(r.get(d, "contactPairs", ""), "contactPairs"))),
        particles=tuple(
            Particle(position=r.vec(r.get(p, "position", f"particles[{i}]"), f"particles[{i}].position"),  # type: ignore[arg-type]
                     velocity=r.vec(r.get(p, "velocity", f"particles[{i}]"), f"particles[{i}].velocity"),  # type: ignore[arg-type]
                     mass=r.num(r.get(p, "mass", f"particles[{i}]"), f"particles[{i}].mass"))
            for i, p in enumerate(r.arr(d.get("particles", []), "particles"))),
        triangle_models=tuple(
            _triangle_model(r, r.obj(m, f"triangleModels[{i}]"), f"triangleModels[{i}]", particle_count)
            for i, m in enumerate(r.arr(d.get("triangleModels", []), "triangleModels"))),
        tet_models=tuple(
            _tet_model(r, r.obj(m, f"tetModels[{i}]"), f"tetModels[{i}]", particle_count)
            for i, m in enumerate(r.arr(d.get("tetModels", []), "tetModels"))),
        line_models=r.integer(deform.get("lineModels", 0), "deformables.lineModels"),
        fluid_models=r.integer(deform.get("fluidModels", 0), "deformables.fluidModels"),
        document=dict(d),
    )


def _elements(r: _Reader, v: Any, path: str, size: int, vertices: int) -> np.ndarray:
    """An (n, size) array of local vertex indices, each in [0, vertices)."""
    items = r.arr(v, path)
    out = np.empty((len(items), size), dtype=np.int64)
    for e, element in enumerate(items):
        indices = r.arr(element, f"{path}[{e}]")
        if len(indices) != size:
            raise r.fail(f"{path}[{e}]", f"{size} vertex indices", indices)
        for k, index in enumerate(indices):
            value = r.integer(index, f"{path}[{e}][{k}]")
            if not 0 <= value < vertices:
                raise r.fail(f"{path}[{e}][{k}]", f"a vertex index in [0, {vertices})", value)
            out[e, k] = value
    return out


def _model_common(r: _Reader, m: Mapping[str, Any], path: str,
                  particle_count: int) -> dict[str, Any]:
    first = r.integer(r.get(m, "firstParticle", path), f"{path}.firstParticle")
    count = r.integer(r.get(m, "particleCount", path), f"{path}.particleCount")
    if first < 0 or count < 0 or first + count > particle_count:
        raise r.fail(f"{path}.particleCount",
                     f"a range of particles[] (firstParticle {first}, {particle_count} particles)", count)
    statics = tuple(r.integer(i, f"{path}.staticParticles[{k}]")
                    for k, i in enumerate(r.arr(m.get("staticParticles", []), f"{path}.staticParticles")))
    for k, i in enumerate(statics):
        if not 0 <= i < count:
            raise r.fail(f"{path}.staticParticles[{k}]", f"a vertex index in [0, {count})", i)
    density = m.get("density")
    material = r.obj(r.get(m, "material", path), f"{path}.material")
    for key, value in material.items():
        if not isinstance(value, (bool, int, float)):
            raise r.fail(f"{path}.material.{key}", "a number or true/false", value)
    return {
        "id": r.integer(r.get(m, "id", path), f"{path}.id"),
        "json_path": r.string(m.get("jsonPath", ""), f"{path}.jsonPath"),
        "first_particle": first, "particle_count": count, "static_particles": statics,
        "density": None if density is None else r.num(density, f"{path}.density"),
        "friction": r.num(r.get(m, "friction", path), f"{path}.friction"),
        "restitution": r.num(r.get(m, "restitution", path), f"{path}.restitution"),
        "simulation_method": r.integer(r.get(m, "simulationMethod", path), f"{path}.simulationMethod"),
        "method_name": r.string(r.get(m, "methodName", path), f"{path}.methodName"),
        "material": dict(material)}


def _triangle_model(r: _Reader, m: Mapping[str, Any], path: str, particle_count: int) -> TriangleModel:
    common = _model_common(r, m, path, particle_count)
    return TriangleModel(
        triangles=_elements(r, r.get(m, "triangles", path), f"{path}.triangles", 3,
                            common["particle_count"]),
        bending_method=r.integer(r.get(m, "bendingMethod", path), f"{path}.bendingMethod"),
        bending_method_name=r.string(r.get(m, "bendingMethodName", path), f"{path}.bendingMethodName"),
        **common)


def _tet_model(r: _Reader, m: Mapping[str, Any], path: str, particle_count: int) -> TetModel:
    common = _model_common(r, m, path, particle_count)
    return TetModel(
        tets=_elements(r, r.get(m, "tets", path), f"{path}.tets", 4, common["particle_count"]),
        boundary_faces=_elements(r, r.get(m, "boundaryFaces", path), f"{path}.boundaryFaces", 3,
                                 common["particle_count"]),
        **common)


def _pair_ids(r: _Reader, p: Any, i: int) -> tuple[int, int]:
    path = f"contactPairs[{i}].bodies"
    ids = r.arr(r.get(r.obj(p, f"contactPairs[{i}]"), "bodies", f"contactPairs[{i}]"), path)
    if len(ids) != 2:
        raise r.fail(path, "two body ids", ids)
    return (r.integer(ids[0], f"{path}[0]"), r.integer(ids[1], f"{path}[1]"))


def read_resolved_scene(path: str | os.PathLike[str]) -> ResolvedScene:
    """Reads and checks a resolved-scene file; SceneError names the file and the JSON path."""
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as e:
        raise SceneError(f"{source}: cannot read: {e.strerror}") from e
    try:
        document = json.loads(text)
    except json.JSONDecodeError as e:
        raise SceneError(f"{source}: line {e.lineno}: not JSON: {e.msg}") from e
    return parse_resolved_scene(document, source)


def combine_friction(rule: str, a: float, b: float) -> float:
    """pbd::combineMaterials (contactCombineRule) for friction: the friction PBD uses for a
    contact between two materials, e.g. a cloth's and a rigid body's (Scene::particleMaterial).
    Restitution combines otherwise under the seed rule (a product)."""
    if rule == "seed":
        return a + b
    if rule == "product":
        return a * b
    if rule == "average":
        return (a + b) / 2
    if rule == "min":
        return min(a, b)
    if rule == "max":
        return max(a, b)
    raise ValueError(f"contactCombineRule: unknown rule {rule!r}")


def unsupported_particle_models(scene: ResolvedScene, engine: str, cloth_methods: Iterable[int],
                                bending_methods: Iterable[int],
                                solid_methods: Iterable[int]) -> list[str]:
    """The particle models an engine cannot represent, each naming its JSON path and method
    ("TriangleModels[0]: cloth method 2 (fem): ..."), given the cloth, bending and solid methods
    it maps (docs/external-engines.md#particles); rods and fluids always."""
    cloth, bending, solid = set(cloth_methods), set(bending_methods), set(solid_methods)
    fraction = f"a fraction per iteration of the PBD solver, not a stiffness {engine} can take"
    missing: list[str] = []
    for m in scene.triangle_models:
        if m.simulation_method not in cloth:
            missing.append(f"{m.json_path}: cloth method {m.simulation_method} ({m.method_name}): "
                           f"{engine} maps cloth methods {sorted(cloth)} only")
        if m.bending_method not in bending:
            missing.append(f"{m.json_path}: bending method {m.bending_method} "
                           f"({m.bending_method_name}): {fraction}")
    for t in scene.tet_models:
        if t.simulation_method not in solid:
            missing.append(f"{t.json_path}: solid method {t.simulation_method} ({t.method_name}): "
                           f"{engine} maps solid methods {sorted(solid)} only")
    if scene.line_models:
        missing.append(f"LineModels: rods ({scene.line_models} models; {engine} has no rod model)")
    if scene.fluid_models:
        missing.append(f"FluidModels: fluids ({scene.fluid_models} models; {engine} has no fluid model)")
    return missing


def particles_outside_models(scene: ResolvedScene) -> list[str]:
    """The refusal of a scene whose particles are not all in its triangle and tet models (an
    engine that builds its particles from those models would drop the others), or none; scenes
    with rods or fluids, whose particles no model lists here, are not judged."""
    counted = sum(m.particle_count for m in (*scene.triangle_models, *scene.tet_models))
    if scene.line_models or scene.fluid_models or counted == len(scene.particles):
        return []
    return [f"particles: {len(scene.particles)} in the scene, {counted} in its triangle and tet models"]


# ---------------------------------------------------------------------------------------------
# Output: the trajectory CSV and status.json


def format_number(value: float) -> str:
    """The shortest decimal text that reads back to `value` exactly, as validation/io/trajectory.cpp
    writes it (integral values without ".0", so 2.0 is "2")."""
    return repr(float(value)).removesuffix(".0")


def format_time(time: float) -> str:
    """Sample times to 12 significant digits, so that 0.3 is 0.3 (validation/io/trajectory.cpp)."""
    return f"{time:.12g}"


@dataclass(frozen=True)
class BodyState:
    """One body at one sample. position: centre of mass (world); rotation: the body's scene
    frame → world (w, x, y, z); velocity of the centre of mass and angular velocity (world)."""

    id: int
    position: FloatVector
    rotation: FloatVector
    velocity: FloatVector
    angular_velocity: FloatVector


def divergence_reason(time: float, bodies: Iterable[BodyState]) -> str | None:
    """Why a state counts as diverged (non-finite, |x| or |v| above DIVERGENCE_LIMIT), or None;
    the same test as validation/run/simulation.cpp."""
    return rows_divergence_reason(time, state_rows(time, list(bodies)))


def state_rows(time: float, bodies: Sequence[BodyState]) -> np.ndarray:
    """The trajectory rows of one sample: (len(bodies), 15) float64, columns as the CSV's
    (t, id, x y z, qw qx qy qz, vx vy vz, wx wy wz), quaternions flipped to w >= 0."""
    rows = np.empty((len(bodies), 15))
    for i, b in enumerate(bodies):
        row = [time, b.id, *b.position, *b.rotation, *b.velocity, *b.angular_velocity]
        if len(row) != 15:
            raise ValueError(f"body {b.id}: expected 3+4+3+3 state values, got {len(row) - 2}")
        rows[i] = row
    flip = rows[:, 5] < 0  # q and -q are one rotation
    rows[flip, 5:9] *= -1.0
    return rows


_QUARTER_SQUARED_LIMIT = (0.5 * DIVERGENCE_LIMIT) ** 2


def _blow_up_reason(time: float, name: Callable[[int], str], positions: np.ndarray,
                    velocities: np.ndarray, state: np.ndarray) -> str | None:
    """The runner's divergence test (validation/run/simulation.cpp) on the states named by `name`
    (row index → "body 3", "particle 5"): any of `state` (every value, row per state)
    non-finite, or |x| or |v| above DIVERGENCE_LIMIT. First one cheap look, sufficient but not
    necessary: the sum of the squares of every value below the square of half the limit, so
    every value finite and below half the limit in magnitude (so |x|, |v| <= sqrt(3)/2 of it);
    NaN and infinity fail the comparison, so does a sum that overflows. One BLAS call, no
    temporary array. Only a state that fails it takes the exact test, which decides."""
    if np.vdot(state, state) < _QUARTER_SQUARED_LIMIT:
        return None
    finite = np.isfinite(state).all(axis=1)
    if not finite.all():
        return f"non-finite state of {name(int(np.argmin(finite)))} at t = {time:g} s"
    x = np.linalg.norm(positions, axis=1)
    v = np.linalg.norm(velocities, axis=1)
    bad = (x > DIVERGENCE_LIMIT) | (v > DIVERGENCE_LIMIT)
    if bad.any():
        i = int(np.argmax(bad))
        return f"{name(i)} blew up at t = {time:g} s (|x| = {x[i]:g} m, |v| = {v[i]:g} m/s)"
    return None


#: The columns of a state array (`simulate`'s `states` may return one, a row per body):
#: the trajectory's columns after t and id.
STATE_COLUMNS = 13


def state_array_rows(time: float, ids: np.ndarray, states: np.ndarray) -> np.ndarray:
    """The trajectory rows of one sample from a state array: `states` (len(ids), 13) float64,
    columns x y z, qw qx qy qz, vx vy vz, wx wy wz per body in `ids`' order; the same rows,
    bit for bit, as state_rows on BodyStates holding the same numbers (quaternions flipped to
    w >= 0). The engines' fast path: a few array operations per sample instead of Python
    objects per body (docs/benchmarks.md#persistent-engines)."""
    if states.shape != (len(ids), STATE_COLUMNS):
        raise ValueError(f"expected a state array of shape ({len(ids)}, {STATE_COLUMNS}), "
                         f"got {states.shape}")
    rows = np.empty((len(ids), 15))
    rows[:, 0] = time
    rows[:, 1] = ids
    rows[:, 2:] = states
    flip = rows[:, 5] < 0  # q and -q are one rotation
    rows[flip, 5:9] *= -1.0
    return rows


def rows_divergence_reason(time: float, rows: np.ndarray) -> str | None:
    """divergence_reason on state_rows."""
    if not len(rows):
        return None
    return _blow_up_reason(time, lambda i: f"body {int(rows[i, 1])}", rows[:, 2:5], rows[:, 9:12], rows[:, 2:])


def _new_file_beside(target: Path) -> tuple[int, Path]:
    """A new, empty file in `target`'s folder named after it (`target`.<pid>-<n>.tmp), created
    exclusively (O_EXCL, mode 0600) and open for writing: what tempfile.mkstemp makes, without
    importing tempfile (2-3 ms of an engine server's start). FileExistsError after 100 names
    taken."""
    for _ in range(100):
        temporary = target.parent / f"{target.name}.{os.getpid()}-{next(_TEMPORARY_NUMBERS)}.tmp"
        try:
            flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC
            return os.open(temporary, flags, 0o600), temporary
        except FileExistsError:
            continue
    raise FileExistsError(f"{target.parent}: no free temporary name for {target.name}")


_TEMPORARY_NUMBERS = itertools.count()


class _RowWriter:
    """Rows of `columns` float64 into OUTDIR/`npy_name` (binary: an NPY file of shape (rows,
    columns)) or, with `binary=False`, OUTDIR/`csv_name` under `header`, the first two columns
    (time, id or index) written as the C++ writers write them. Written to a temporary file and
    renamed on close(), so the file is never half-written (not fsync'ed: the runner reads it
    as soon as the engine ends and removes it with the scratch folder; the rename alone makes
    it whole to a reader)."""

    def __init__(self, out_dir: str | os.PathLike[str], *, binary: bool, npy_name: str,
                 csv_name: str, header: str, columns: int, capacity: int = 0) -> None:
        self.binary = binary
        self.columns = columns
        # Binary: the rows expected (`capacity`) go into one array allocated here, the rest
        # (a run that writes more than it said) into a list after them.
        self._buffer = np.empty((capacity if binary else 0, columns))
        self._filled = 0
        self.path = Path(out_dir) / (npy_name if binary else csv_name)
        fd, self._temporary = _new_file_beside(self.path)
        self._file: BinaryIO = os.fdopen(fd, "wb")
        self._rows: list[np.ndarray] = []
        if not binary:
            self._file.write((header + "\n").encode("ascii"))
        self.samples = 0

    def write_rows(self, rows: np.ndarray) -> None:
        """One sample's rows, written as they are."""
        if rows.ndim != 2 or rows.shape[1] != self.columns:
            raise ValueError(f"expected rows of shape (n, {self.columns}), got {rows.shape}")
        if self.binary:
            if not self._rows and self._filled + len(rows) <= len(self._buffer):
                self._buffer[self._filled:self._filled + len(rows)] = rows
                self._filled += len(rows)
            else:
                self._rows.append(np.array(rows, dtype=np.float64))
        else:
            t = format_time(float(rows[0, 0])) if len(rows) else ""
            lines = [f"{t},{int(r[1])}," + ",".join(format_number(v) for v in r[2:]) + "\n" for r in rows]
            self._file.write("".join(lines).encode("ascii"))
        self.samples += 1

    def close(self) -> None:
        """Writes out and renames the file into place."""
        if self._file.closed:
            return
        if self.binary:
            data = self._buffer[:self._filled]
            if self._rows:
                data = np.concatenate([data, *self._rows])
            np.save(self._file, np.ascontiguousarray(data, dtype="<f8"), allow_pickle=False)
        self._file.close()
        os.replace(self._temporary, self.path)

    def discard(self) -> None:
        if not self._file.closed:
            self._file.close()
        self._temporary.unlink(missing_ok=True)

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class TrajectoryWriter(_RowWriter):
    """Writes the run's samples into OUTDIR: by default OUTDIR/trajectory.npy (binary: float64
    rows of shape (rows, 15), one per body per sample, columns as the CSV's), or with
    `binary=False` OUTDIR/trajectory.csv in the format of `pbdval simulate` (docs/cli.md#csv).
    Bodies in the resolved scene's order, quaternions with w >= 0."""

    def __init__(self, out_dir: str | os.PathLike[str], *, binary: bool = True,
                 capacity: int = 0) -> None:
        super().__init__(out_dir, binary=binary, npy_name=TRAJECTORY_NPY_FILE,
                         csv_name=TRAJECTORY_FILE, header=TRAJECTORY_HEADER, columns=15,
                         capacity=capacity)

    def write(self, time: float, bodies: Sequence[BodyState]) -> None:
        self.write_rows(state_rows(time, bodies))


def particle_rows(time: float, states: np.ndarray) -> np.ndarray:
    """The particle rows of one sample: (P, 8) float64 (t, index, x y z, vx vy vz) from the
    (P, 6) array of positions and velocities of every particle in scene order."""
    states = np.asarray(states, dtype=np.float64)
    if states.ndim != 2 or states.shape[1] != 6:
        raise ValueError(f"expected particle states of shape (particles, 6), got {states.shape}")
    rows = np.empty((len(states), 8))
    rows[:, 0] = time
    rows[:, 1] = np.arange(len(states))
    rows[:, 2:] = states
    return rows


def particle_rows_divergence_reason(time: float, rows: np.ndarray) -> str | None:
    """The runner's divergence test on particle rows (validation/run/simulation.cpp)."""
    if not len(rows):
        return None
    return _blow_up_reason(time, lambda i: f"particle {i}", rows[:, 2:5], rows[:, 5:8], rows[:, 2:])


class ParticleTrajectoryWriter(_RowWriter):
    """Writes the particles' samples: OUTDIR/particles.npy (float64, shape (rows, 8)), or with
    `binary=False` OUTDIR/particles.csv (header t,index,x,y,z,vx,vy,vz, docs/cli.md#particles):
    every particle of the resolved scene's `particles`, in order, at every sample."""

    def __init__(self, out_dir: str | os.PathLike[str], *, binary: bool = True,
                 capacity: int = 0) -> None:
        super().__init__(out_dir, binary=binary, npy_name=PARTICLES_NPY_FILE,
                         csv_name=PARTICLES_FILE, header=PARTICLES_HEADER, columns=8,
                         capacity=capacity)

    def write(self, time: float, states: np.ndarray) -> None:
        self.write_rows(particle_rows(time, states))


@dataclass
class Status:
    """The content of status.json (docs/external-engines.md)."""

    status: str  # ok | unsupported | diverged | error
    reason: str = ""
    unsupported: list[str] = field(default_factory=list)
    diverged_at: float | None = None  # s
    engine_version: str = ""
    effective_settings: dict[str, ParameterValue] = field(default_factory=dict)
    integrator_steps_per_scene_step: int = 1
    contact_margin: float | None = None  # m
    #: Generalised coordinates: the scene's initial velocities are projected onto the joints'
    #: free motions, so the runner does not compare the first sample's velocities with them.
    initial_velocities_projected: bool = False

    def to_json(self) -> dict[str, Any]:
        if self.status not in STATUSES:
            raise ValueError(f"status: expected one of {', '.join(STATUSES)}, got {self.status!r}")
        return {
            "protocol": PROTOCOL_VERSION,
            "status": self.status,
            "reason": self.reason,
            "unsupported": list(self.unsupported),
            "divergedAt": self.diverged_at,
            "engineVersion": self.engine_version,
            "effectiveSettings": dict(self.effective_settings),
            "integratorStepsPerSceneStep": int(self.integrator_steps_per_scene_step),
            "contactMargin": self.contact_margin,
            "initialVelocitiesProjected": bool(self.initial_velocities_projected),
        }


def write_json_atomically(path: str | os.PathLike[str], document: Any, *, durable: bool = True) -> None:
    """Writes `document` as JSON to a temporary file beside `path`, then renames it over `path`.
    Refuses to replace anything but a regular file. `durable`: fsync'ed before the rename, so
    that it survives a crash of the machine (results); an engine's status.json, read at once
    and removed with the run's scratch folder, need not be."""
    target = Path(path)
    if target.exists() and not target.is_file():
        raise OSError(f"{target}: exists and is not a regular file; not replaced")
    text = json.dumps(document, indent=1, allow_nan=False) + "\n"
    fd, temporary = _new_file_beside(target)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
            if durable:
                f.flush()
                os.fsync(f.fileno())
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_status(out_dir: str | os.PathLike[str], status: Status) -> None:
    write_json_atomically(Path(out_dir) / STATUS_FILE, status.to_json(), durable=False)


# ---------------------------------------------------------------------------------------------
# Command line


@dataclass(frozen=True)
class EngineArguments:
    scene: Path
    out: Path


def parse_arguments(argv: Sequence[str] | None, description: str) -> EngineArguments:
    """Parses `--scene RESOLVED.json --out OUTDIR`; OUTDIR must be an existing directory. Bad
    usage exits with status 2 (argparse), which the runner reads as "no status.json"."""
    if (argv is not None and len(argv) == 4 and argv[0] == "--scene" and argv[2] == "--out"
            and not argv[1].startswith("-") and not argv[3].startswith("-") and Path(argv[3]).is_dir()):
        # The runner's own form (a served run's too), valid: the same result without building a
        # parser in every run's child; anything else goes to the parser, which says what is wrong.
        return EngineArguments(scene=Path(argv[1]), out=Path(argv[3]))
    import argparse

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--scene", required=True, type=Path,
                        help="the resolved scene (pbdval export-scene)")
    parser.add_argument("--out", required=True, type=Path,
                        help="an existing directory for trajectory.csv and status.json")
    ns = parser.parse_args(argv)
    if not ns.out.is_dir():
        parser.error(f"--out {ns.out}: not an existing directory")
    return EngineArguments(scene=ns.scene, out=ns.out)


def _no_failure(time: float) -> str | None:
    """`simulate`'s `failure` when the engine gives none: it never finds one (and `simulate`
    skips the call)."""
    return None


def simulate(scene: ResolvedScene, out_dir: str | os.PathLike[str], step: Callable[[], None],
             states: Callable[[float], list[BodyState] | np.ndarray],
             failure: Callable[[float], str | None] = _no_failure,
             check: Callable[[float], str | None] | None = None,
             particles: Callable[[float], np.ndarray] | None = None,
             finish_states: Callable[[np.ndarray], np.ndarray] | None = None) -> Status:
    """The run every engine makes: the state at t = 0, then `scene.steps` calls of `step`
    (one scene step each), writing the samples the runner asks for (`scene.sample_steps()`).

    `states(t)` gives every body's state in scene order: BodyStates, or (cheaper) one state
    array, (bodies, 13) float64 (state_array_rows), which `simulate` copies before the next call.
    The samples are kept and the trajectory's rows made from all of them at once when the run
    ends (the same rows, bit for bit, as state_array_rows of each: element-wise operations).
    `finish_states`, with state arrays: what turns the stacked (samples, bodies, 13) arrays
    `states` gave into the state arrays' columns, once for the whole trajectory instead of once
    per sample (e.g. principal_to_scene_states: a frame change). The divergence test is made on
    what `states` gave, so `finish_states` must keep the positions (columns 0-2) and velocities
    (7-12) as they are and a quaternion (3-6) finite exactly when it was.

    `particles(t)`, for a scene with particles, returns the (P, 6) positions and velocities of
    every particle in scene order; they are written to particles.npy at the same samples and
    checked like the bodies. A scene with particles needs it (ValueError otherwise).

    Divergence: every sample's states are checked against the runner's limits
    (`divergence_reason`) and `failure(t)`; between samples the states are not read (reading
    them is most of the protocol's cost per step), so an engine that can tell cheaply gives
    `check(t)`, called after every other step (e.g. a vectorised look at its state arrays).
    The run stops at the first divergence found, after writing that state, and the status is
    "diverged" with its time; otherwise "ok". The engine adds its version and settings."""
    if scene.particles and particles is None:
        raise ValueError(f"the scene has {len(scene.particles)} particles and the engine "
                         "reads none back (simulate's `particles`)")
    sample_steps = scene.sample_steps()  # ascending
    sampled = set(sample_steps)
    h = scene.time_step_size
    failing = failure is not _no_failure  # whether `failure` may find one (else not called)
    between_samples = check is not None or failing  # whether a step between samples is tested
    particle_writer = (ParticleTrajectoryWriter(out_dir, capacity=len(sampled) * len(scene.particles))
                       if particles is not None and scene.particles else None)
    ids = np.array([b.id for b in scene.bodies], dtype=np.float64)
    body_count = len(ids)
    # Every sample written (a diverged run's last one may fall between samples: one more).
    kept = np.empty((len(sampled) + 1, body_count, STATE_COLUMNS))
    kept_times: list[float] = []

    def body_name(i: int) -> str:
        return f"body {int(ids[i])}"

    state_shape = (body_count, STATE_COLUMNS)
    # A sample is the bodies' states alone (no particles to read, no `failure` to ask): it is
    # kept as soon as it is read (sample's short way: 0.6 us of Python less per sample).
    bodies_alone = particle_writer is None and not failing
    vdot = np.vdot

    def sample(t: float) -> str | None:
        """Reads the state at `t`, keeps it (and writes the particles') and returns the
        divergence found in it, if any."""
        given = states(t)
        if isinstance(given, np.ndarray):
            if given.shape != state_shape:
                raise ValueError(f"expected a state array of shape ({body_count}, {STATE_COLUMNS}), "
                                 f"got {given.shape}")
            state = given
        else:
            if finish_states is not None:
                raise TypeError("simulate's `finish_states` takes state arrays; `states` gave BodyStates")
            state = state_rows(t, given)[:, 2:]
        # The runner's test on the state (the rows' columns after t and id; the flip of a
        # quaternion's sign changes no magnitude). Its first cheap look here, before slicing:
        # a state that passes it passes the test.
        reason = (_blow_up_reason(t, body_name, state[:, 0:3], state[:, 7:10], state)
                  if body_count and not vdot(state, state) < _QUARTER_SQUARED_LIMIT else None)
        if bodies_alone:
            kept[len(kept_times)] = state
            kept_times.append(t)
            return reason
        particle_sample = None
        if particle_writer is not None and particles is not None:
            particle_sample = particle_rows(t, particles(t))
            if len(particle_sample) != len(scene.particles):
                raise ValueError(f"particles({t:g}) gave {len(particle_sample)} particles, "
                                 f"the scene has {len(scene.particles)}")
            reason = reason or particle_rows_divergence_reason(t, particle_sample)
        reason = reason or (failure(t) if failing else None)
        kept[len(kept_times)] = state
        kept_times.append(t)
        if particle_writer is not None and particle_sample is not None:
            particle_writer.write_rows(particle_sample)
        return reason

    def trajectory_rows() -> np.ndarray:
        """The rows of every sample kept, as state_array_rows makes them one sample at a time."""
        count = len(kept_times)
        final = kept[:count] if finish_states is None else finish_states(kept[:count])
        per_sample = np.empty((count, body_count, 15))
        per_sample[:, :, 0] = np.array(kept_times)[:, None]
        per_sample[:, :, 1] = ids
        per_sample[:, :, 2:] = final
        rows = per_sample.reshape(count * body_count, 15)
        flip = rows[:, 5] < 0  # q and -q are one rotation
        rows[flip, 5:9] *= -1.0
        return rows

    try:
        with TrajectoryWriter(out_dir, capacity=len(sampled) * body_count) as writer:
            try:
                sample(0.0)  # the start: its divergence test not used
                if not between_samples:
                    # Nothing to test between samples: the steps up to each sample in one loop
                    # without a test per step (the same calls, in the same order).
                    done = 0
                    for target in sample_steps:
                        for _ in itertools.repeat(None, target - done):
                            step()
                        done = target
                        if target:
                            t = target * h
                            reason = sample(t)
                            if reason:
                                return Status("diverged", reason=reason, diverged_at=t)
                    return Status("ok")
                for n in range(1, scene.steps + 1):
                    step()
                    if n in sampled:
                        t = n * h
                        reason = sample(t)
                        if reason:
                            return Status("diverged", reason=reason, diverged_at=t)
                    else:
                        t = n * h
                        reason = (check(t) if check is not None else None) or (failure(t) if failing else None)
                        if reason:
                            sample(t)  # the state that diverged, kept as the last sample
                            return Status("diverged", reason=reason, diverged_at=t)
            finally:
                writer.write_rows(trajectory_rows())
        return Status("ok")
    except BaseException:
        if particle_writer is not None:
            particle_writer.discard()
        raise
    finally:
        if particle_writer is not None:
            particle_writer.close()


def serve(argv: Sequence[str] | None, description: str,
          unsupported_features: Callable[[ResolvedScene], list[str]],
          run: Callable[[ResolvedScene, Path], Status], engine_version: str) -> int:
    """An engine's whole `main`: parses the arguments, reads the resolved scene, reports what
    `unsupported_features` names as `unsupported`, else calls `run(scene, out_dir)`; any
    exception becomes status "error" with its message. Writes status.json and returns 0, as the
    protocol asks (bad usage exits 2 from `parse_arguments`)."""
    args = parse_arguments(argv, description)
    try:
        scene = read_resolved_scene(args.scene)
        missing = unsupported_features(scene)
        if missing:
            status = Status("unsupported", reason="; ".join(missing), unsupported=missing,
                            engine_version=engine_version)
        else:
            status = run(scene, args.out)
    except Exception as e:  # noqa: BLE001 -- every failure becomes status "error" with its message
        status = Status("error", reason=f"{type(e).__name__}: {e}", engine_version=engine_version)
    write_status(args.out, status)
    return 0


# ---------------------------------------------------------------------------------------------
# A persistent engine process: serve protocol 1 (docs/external-engines.md#persistent-engines)

SERVE_PROTOCOL_VERSION = 1
_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_MAX_REQUEST_BYTES = 1 << 16


def _die_with_parent() -> None:
    """SIGKILL when the process that forked this one dies (Linux prctl PR_SET_PDEATHSIG)."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)


def _read_request(connection: socket.socket) -> bytes:
    """The request line (without its newline); empty for a connection closed without one (the
    runner's probe that the server listens)."""
    data = b""
    while b"\n" not in data and len(data) < _MAX_REQUEST_BYTES:
        chunk = connection.recv(4096)
        if not chunk:
            break
        data += chunk
    return data.split(b"\n", 1)[0]


def _send(connection: socket.socket, reply: Mapping[str, Any]) -> None:
    """One reply line; a runner that went away (its run was stopped) is no error."""
    try:
        connection.sendall((json.dumps(reply) + "\n").encode())
    except OSError:
        pass


def _request_fields(line: bytes) -> tuple[str, str, str]:
    """scene, out and stderr of a request; ValueError naming what is wrong."""
    try:
        request = json.loads(line)
    except (ValueError, UnicodeDecodeError) as e:
        raise ValueError(f"the request is not JSON ({e})") from None
    if not isinstance(request, dict):
        raise TypeError("the request is not a JSON object")
    if request.get("protocol") != SERVE_PROTOCOL_VERSION:
        raise ValueError(f"protocol: expected {SERVE_PROTOCOL_VERSION}, got {request.get('protocol')!r}")
    fields = []
    for key in ("scene", "out", "stderr"):
        value = request.get(key)
        if not isinstance(value, str) or not value:
            raise ValueError(f"{key}: expected a path, got {value!r}")
        fields.append(value)
    return fields[0], fields[1], fields[2]


def _run_in_child(main: Callable[[list[str]], int], request: bytes, stdout_to_stderr: bool,
                  preparation_failure: str | None) -> tuple[int, str | None]:
    """In the run's child, once its request has come: the single-shot run, exactly as
    `<command> --scene S --out O` makes it, with the child's standard error in the request's
    file (where a failed preparation is reported). Returns its exit status and its output folder
    (None when the request named none)."""
    out: str | None = None
    try:
        scene, out, stderr_path = _request_fields(request)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        error = os.open(stderr_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        null = os.open(os.devnull, os.O_RDWR)
        os.dup2(error, 2)
        os.dup2(null, 0)
        os.dup2(error if stdout_to_stderr else null, 1)
        os.close(error)
        os.close(null)
        if preparation_failure is not None:
            print(f"the engine's preparation for the run failed:\n{preparation_failure}", file=sys.stderr)
            return 1, out
        return int(main(["--scene", scene, "--out", out]) or 0), out
    except SystemExit as e:  # argparse's usage error (2), an engine's sys.exit
        if e.code is None or isinstance(e.code, int):
            return int(e.code or 0), out
        print(e.code, file=sys.stderr)
        return 1, out
    except BaseException:  # noqa: BLE001 -- as an uncaught exception ends the single-shot interpreter
        import traceback

        traceback.print_exc()
        return 1, out


#: A child that serves several runs (`--runs-per-child`) is retired when its resident memory has
#: grown by more than this since its first run, bytes: what a run leaks is bounded by it.
RETIRE_RESIDENT_GROWTH = 64 << 20
#: The run statuses after which a child may serve another run (any other, or an exit status
#: other than 0, retires it: docs/external-engines.md#persistent-engines).
_STATUSES_A_CHILD_SURVIVES = ("ok", "unsupported")


def _resident_bytes() -> int:
    """This process's resident memory (Linux /proc/self/statm)."""
    with open("/proc/self/statm", "rb") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def _has_processes_of_its_own() -> bool:
    """Whether this process has a child process (running, or ended and not reaped)."""
    try:
        os.waitpid(-1, os.WNOHANG)
    except ChildProcessError:
        return False
    return True


def _may_serve_another_run(code: int, out: str | None) -> bool:
    """After a run in a child that may serve several: whether the run ended as a clean run does
    (exit status 0, status.json readable with status ok or unsupported) and left no process."""
    if code != 0 or out is None or _has_processes_of_its_own():
        return False
    try:
        with open(os.path.join(out, "status.json"), "rb") as status_file:
            status = json.load(status_file)
    except (OSError, ValueError):
        return False
    return isinstance(status, dict) and status.get("status") in _STATUSES_A_CHILD_SURVIVES


def _read_line(fd: int) -> bytes:
    """One request line from the server's pipe (without its newline); empty at the pipe's end
    (the server closed it: there is no further run)."""
    data = b""
    while not data.endswith(b"\n"):
        chunk = os.read(fd, 65536)
        if not chunk:
            return b""
        data += chunk
    return data[:-1]


@dataclass(frozen=True)
class _ChildRule:
    """What a run's child does besides the run (serve_runs' arguments, the same for every child)."""

    main: Callable[[list[str]], int]
    prepare: Callable[[], None] | None
    stdout_to_stderr: bool
    runs_per_child: int  # the most runs one child serves in turn (1: a child per run)
    between_runs: Callable[[], bool] | None  # readies the engine for another run; False: cannot


def _serve_in_child(rule: _ChildRule, requests: int, reports: int) -> int:
    """A run's child, from its start to its last run: `prepare()`, then the runs the server
    hands it on `requests` (one, or up to `rule.runs_per_child`), each reported on `reports` as
    two bytes (exit status, 1 when the child stays for another run) but the last, which the
    caller reports as it exits. Returns the last run's exit status (0 without a run: the server
    stopped)."""
    failure = None
    try:
        if rule.prepare is not None:
            rule.prepare()
    except BaseException:  # noqa: BLE001 -- reported on the run's standard error
        import traceback

        failure = traceback.format_exc()
    # The child's own standard streams (the server's log), put back between runs.
    standard = [os.dup(fd) for fd in (0, 1, 2)] if rule.runs_per_child > 1 else []
    resident_at_first_run = 0
    runs = 0
    while request := _read_line(requests):
        if runs == 0 and standard:
            resident_at_first_run = _resident_bytes()
        code, out = _run_in_child(rule.main, request, rule.stdout_to_stderr, failure)
        runs += 1
        if runs >= rule.runs_per_child or failure is not None or not _may_serve_another_run(code, out):
            return code
        sys.stdout.flush()
        sys.stderr.flush()
        for fd, saved in enumerate(standard):
            os.dup2(saved, fd)
        if _resident_bytes() - resident_at_first_run > RETIRE_RESIDENT_GROWTH:
            return code
        try:
            if rule.between_runs is not None and not rule.between_runs():
                return code
        except Exception:  # noqa: BLE001 -- an engine that cannot be readied again retires the child
            import traceback

            traceback.print_exc()
            return code
        os.write(reports, bytes([code & 0xFF, 1]))
    return 0


class _Standby:
    """A run's child, forked ahead from the pristine server: in a process group of its own,
    SIGKILL when the server dies, `prepare()` done (what every run does first whatever its
    scene), waiting on a pipe for its request. Forking, the copies of the pages its run would
    write first, and preparing are then off the run's critical path; the child is as fresh as
    one forked at the request. When its run is over it reports its exit status on a second pipe
    (before it exits, so that the reply need not wait for the kernel to tear down a large
    process: milliseconds), and whether it stays for another run: with `runs_per_child` > 1 a
    child that ended its run cleanly (_may_serve_another_run), has served fewer runs than that,
    has not grown by RETIRE_RESIDENT_GROWTH and whose engine is ready again (`between_runs`)
    waits for the next request instead of exiting (docs/external-engines.md#persistent-engines)."""

    def __init__(self, inherited: Sequence[socket.socket | int], rule: _ChildRule) -> None:
        read_end, self._write_end = os.pipe()
        self._report_read, report_write = os.pipe()
        self.reaped = False
        self.runs = 0  # runs handed to it
        sys.stdout.flush()
        sys.stderr.flush()
        server = os.getpid()
        # Every object the server holds goes to the collector's permanent generation: the
        # child's collections never walk them, so the pages it copies are those its run
        # writes, not every page with an object on it (measured with served runs of three
        # scenes, 24 runs: the CPU time of server and children 1.15 -> 1.02 s for
        # mujoco-python, 1.24 -> 1.15 s for pybullet; docs/benchmarks.md#persistent-engines).
        # What the server makes later is frozen by the next call too: between runs it makes
        # almost nothing (a request line, a reply), freed by reference counting, not the collector.
        gc.freeze()
        self.pid = os.fork()
        if self.pid == 0:
            code = 1
            try:
                os.close(self._write_end)
                os.close(self._report_read)
                for inherited_end in inherited:  # the server's and the other runs', not this run's
                    if isinstance(inherited_end, socket.socket):
                        inherited_end.close()  # the object knows it is closed: nothing closes its number again
                    else:
                        os.close(inherited_end)
                os.setpgid(0, 0)
                _die_with_parent()
                if os.getppid() == server:  # else the server died before prctl
                    code = _serve_in_child(rule, read_end, report_write)
            finally:
                try:
                    sys.stdout.flush()
                    sys.stderr.flush()
                    os.write(report_write, bytes([code & 0xFF, 0]))
                finally:
                    os._exit(code & 0xFF)
        os.close(read_end)
        os.close(report_write)
        try:
            os.setpgid(self.pid, self.pid)  # also here: whichever of the two runs first
        except OSError:
            pass  # it has set its group itself, or ended
        self._write_end_open = True

    def start(self, request: bytes) -> None:
        """Hands the child its request (it starts the run). OSError when the child has ended
        (its pipe's read end is closed)."""
        line = memoryview(request + b"\n")
        while line:
            line = line[os.write(self._write_end, line):]
        self.runs += 1

    @property
    def write_fd(self) -> int:
        """The pipe on which the server sends it requests (-1 once closed)."""
        return self._write_end if self._write_end_open else -1

    @property
    def report_fd(self) -> int:
        """The pipe on which the child reports its exit status (readable when its run is over)."""
        return self._report_read

    def poll_end(self) -> tuple[bool, int | None, bool]:
        """Whether the run is over, without waiting for it; then its exit status as the child
        reported it, or None when the child ended without one (a crash, a kill; it is then a
        zombie, not reaped); and whether the child stays for another run."""
        readable, _, _ = select.select([self._report_read], [], [], 0)
        if readable:
            report = os.read(self._report_read, 2)
            if len(report) == 2:
                return True, report[0], report[1] == 1
            os.waitid(os.P_PID, self.pid, os.WEXITED | os.WNOWAIT)  # it is ending: its pipe closed
            return True, None, False
        ended = os.waitid(os.P_PID, self.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT)
        if ended is not None and ended.si_pid == self.pid:
            # A process the run left may hold the pipe open: the child's end decides.
            readable, _, _ = select.select([self._report_read], [], [], 0)
            report = os.read(self._report_read, 2) if readable else b""
            return True, report[0] if len(report) == 2 else None, False
        return False, None, False

    def alive(self) -> bool:
        """False once it has ended (it is then reaped)."""
        try:
            pid, _ = os.waitpid(self.pid, os.WNOHANG)
        except ChildProcessError:
            pid = self.pid
        self.reaped = pid != 0
        return not self.reaped

    def close_pipes(self) -> None:
        """Closes the server's ends of its pipes (its last run is over, or it is being discarded)."""
        if self._write_end_open:
            os.close(self._write_end)
            self._write_end_open = False
        if self._report_read >= 0:
            os.close(self._report_read)
            self._report_read = -1

    def discard(self) -> None:
        """Ends it, unless it was reaped already (its group id may then be another's)."""
        self.close_pipes()
        if self.reaped:
            return
        try:
            os.killpg(self.pid, signal.SIGKILL)
        except OSError:
            pass
        try:
            os.waitpid(self.pid, 0)
        except ChildProcessError:
            pass
        self.reaped = True


#: How long the server waits for a connection's request line, s: the runner sends it as soon as
#: it is connected; a connection that sends none in time is answered with an error, so that it
#: cannot hold up the other runs' replies.
_REQUEST_TIMEOUT = 10.0
#: How often the server looks at its runs' children when no pipe or socket wakes it, s: a run
#: whose child ended while a process it left holds its report pipe open.
_POLL_INTERVAL = 0.02


@dataclass
class _ServedRun:
    """A run in progress: the runner's connection and the child running it."""

    connection: socket.socket
    child: _Standby
    runner_gone: bool = False  # the runner closed its connection: the child was killed


def _finish(run: _ServedRun, code: int | None) -> None:
    """The run is over (`code`: its reported exit status, or None): its whole process group
    killed before the reply (whatever the run left running ends with it; the child is not
    reaped yet, so the group id is still the run's), then the reply."""
    pid = run.child.pid
    try:
        os.killpg(pid, signal.SIGKILL)
    except OSError:
        pass
    if code is not None:
        _send(run.connection, {"exited": code})
        return
    _, status = os.waitpid(pid, 0)
    run.child.reaped = True
    if os.WIFSIGNALED(status):
        _send(run.connection, {"signaled": os.WTERMSIG(status)})
    else:
        _send(run.connection, {"exited": os.waitstatus_to_exitcode(status)})


def _positive_integer(text: str) -> int:
    value = int(text)
    if value < 1:
        raise ValueError(text)
    return value


def _serve_arguments(argv: Sequence[str] | None, description: str) -> tuple[str, int]:
    """`--socket PATH [--runs-per-child N]`: the socket path and N (default 1). Bad usage exits
    with status 2 (argparse)."""
    options = dict(zip(argv[::2], argv[1::2], strict=False)) if argv is not None else {}
    runs = options.get("--runs-per-child", "1")
    if (argv is not None and len(argv) in (2, 4) and len(options) == len(argv) // 2
            and set(options) <= {"--socket", "--runs-per-child"} and options.get("--socket")
            and not options["--socket"].startswith("-") and runs.isascii() and runs.isdigit()
            and int(runs) >= 1):
        # The runner's own form, valid: the same result without building a parser (argparse
        # is 1-2 ms of the server's start); anything else goes to the parser, which says what
        # is wrong.
        return options["--socket"], int(runs)
    import argparse

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--socket", required=True, help="the Unix socket to listen on")
    parser.add_argument("--runs-per-child", type=_positive_integer, default=1, metavar="N",
                        help="the most runs one forked child serves in turn (default 1: a child per run)")
    args = parser.parse_args(argv)
    return str(args.socket), int(args.runs_per_child)


def serve_runs(argv: Sequence[str] | None, main: Callable[[list[str]], int], description: str,
               *, stdout_to_stderr: bool = False, prepare: Callable[[], None] | None = None,
               between_runs: Callable[[], bool] | None = None,
               fresh_child_for: Callable[[str], bool] | None = None) -> int:
    """A persistent engine process: the whole serve loop of a catalogue's `serve` command.

    Listens on the Unix socket `--socket PATH` and serves every connection, several at a time
    (one server serves all the workers of a `pbdval run`): the runner sends one line,
    {"protocol": 1, "scene": S, "out": O, "stderr": E}; a child forked from this process runs
    `main(["--scene", S, "--out", O])` exactly as the single-shot command would (in a process
    group of its own, standard error to E, standard input and output /dev/null, or output to E
    with `stdout_to_stderr`); the server replies {"started": pid}, and when the run is over
    kills the child's process group and replies {"exited": code} or {"signaled": signal}. A
    runner that closes its connection before that (it was stopped) has its run's process group
    killed. A bad request gets {"error": reason}.

    One child always waits for the next run, forked ahead (at start, and as soon as the waiting
    one takes a run); `prepare()`, when given, is what it does meanwhile: work every run does
    first whatever its scene (connecting to a physics server). Everything the engine imports
    before calling this is paid once; nothing a run does (a crash, a leak, a hang the runner
    kills) reaches another run: each is a fresh child of the pristine server, which runs no
    engine code itself.

    `--runs-per-child N` (the catalogue's `serve.runsPerChild`, default 1) lets one child serve
    up to N runs in turn, for an engine that rebuilds its world from scratch in every run and
    whose runs leave nothing behind: a child whose run ended cleanly is then not killed but kept
    for a later run (its group is killed when it retires), and `between_runs()` (in the child,
    after each such run) readies the engine for the next one, or returns False when it cannot
    (the child retires). `fresh_child_for(scene)` (in the server, with the request's resolved
    scene path) names the runs that must have a fresh child all the same: those a used child
    would not run as a new process does. A run that crashes, hangs, fails or leaves a process
    ends its child; the next run goes to a fresh one (_Standby,
    docs/external-engines.md#persistent-engines).
    Returns only on an error (bad usage exits 2)."""
    socket_path, runs_per_child = _serve_arguments(argv, description)
    rule = _ChildRule(main, prepare, stdout_to_stderr, runs_per_child, between_runs)
    _die_with_parent()
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(socket_path)
    listener.listen(16)
    runs: list[_ServedRun] = []
    idle: list[_Standby] = []  # children that served a run and wait for another
    unreaped: list[_Standby] = []  # runs over and replied to, their children not yet reaped
    standby = _Standby([listener], rule)  # the fresh child the next run goes to when none waits

    def server_ends(pending: socket.socket | None) -> list[socket.socket | int]:
        """What a new child must close: the listener, every other child's pipes (each child
        once: the fresh one may also be a run's), every run's connection and the one being
        handed over."""
        ends: list[socket.socket | int] = [listener]
        children = {id(child): child for child in [standby, *idle, *(run.child for run in runs)]}
        for child in children.values():
            ends += [fd for fd in (child.report_fd, child.write_fd) if fd >= 0]
        ends += [run.connection for run in runs]
        if pending is not None:
            ends.append(pending)
        return ends

    def new_standby(pending: socket.socket | None = None) -> _Standby:
        return _Standby(server_ends(pending), rule)

    def needs_a_fresh_child(line: bytes) -> bool:
        if fresh_child_for is None or not idle:
            return False
        try:
            return fresh_child_for(_request_fields(line)[0])
        except Exception:  # noqa: BLE001 -- a scene it cannot look at: the fresh child, which reports it
            return True

    def hand_over(line: bytes, connection: socket.socket) -> _Standby:
        """The child that runs this request: the most recently used of the waiting children that
        is still there, else (or when the run must have a fresh child) the fresh one."""
        nonlocal standby
        while idle and not needs_a_fresh_child(line):
            child = idle.pop()
            if child.alive():
                try:
                    child.start(line)
                    return child
                except OSError:  # it ended meanwhile
                    pass
            child.discard()
        if not standby.alive():  # it died while waiting (killed from outside): a new one
            standby.discard()
            standby = new_standby(connection)
        standby.start(line)
        return standby

    while True:
        watched: list[Any] = [listener]
        watched += [run.child.report_fd for run in runs]
        watched += [run.connection for run in runs if not run.runner_gone]
        timeout = _POLL_INTERVAL if runs or unreaped else None
        readable, _, _ = select.select(watched, [], [], timeout)
        for child in list(unreaped):
            if not child.alive():
                unreaped.remove(child)
        for run in [r for r in runs if r.connection in readable]:
            try:
                gone = not run.connection.recv(4096)
            except OSError:
                gone = True
            if gone:  # the runner went away (stopped): so does its run
                run.runner_gone = True
                try:
                    os.killpg(run.child.pid, signal.SIGKILL)
                except OSError:
                    pass
        for run in list(runs):
            over, code, stays = run.child.poll_end()
            if not over:
                continue
            runs.remove(run)
            if stays and not run.runner_gone:
                _send(run.connection, {"exited": code})
                run.connection.close()
                idle.append(run.child)
                continue
            _finish(run, code)
            run.connection.close()
            run.child.close_pipes()
            if not run.child.reaped:  # killed with its group: reaped as soon as it is gone
                unreaped.append(run.child)
        if listener in readable:
            connection, _ = listener.accept()
            try:
                connection.settimeout(_REQUEST_TIMEOUT)
                line = _read_request(connection)
                connection.settimeout(None)
                if line:
                    _request_fields(line)
            except (ValueError, TypeError) as e:
                _send(connection, {"error": str(e)})
                line = b""
            except OSError as e:  # a connection that broke or sent nothing: serve the others
                print(f"pbdval serve: {e}", file=sys.stderr)
                line = b""
            if not line:  # the runner's probe, or a request answered with an error
                connection.close()
                continue
            child = hand_over(line, connection)
            _send(connection, {"started": child.pid})
            runs.append(_ServedRun(connection, child))
            if child is standby:  # the next run's child, while this one runs (it closes this run's ends)
                standby = new_standby()


# ---------------------------------------------------------------------------------------------
# Quaternion helpers (w, x, y, z)


def quat_multiply(a: FloatVector, b: FloatVector) -> Quat:
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def quat_right_factors(b: np.ndarray) -> np.ndarray:
    """For quat_multiply_rows: the (4, n, 4) table F of the (n, 4) quaternions b (w, x, y, z)
    with a * b = ((a_w F[0] + a_x F[1]) + a_y F[2]) + a_z F[3] row by row. Each product and sum
    is quat_multiply's, in its order, a subtraction being the addition of the negated product
    (exact in IEEE 754), so the rows are bit for bit quat_multiply's."""
    bw, bx, by, bz = (np.asarray(b, dtype=np.float64).reshape(-1, 4)[:, k] for k in range(4))
    return np.stack([np.stack(column, axis=1) for column in
                     ((bw, bx, by, bz), (-bx, bw, -bz, by), (-by, bz, bw, -bx), (-bz, -by, bx, bw))])


def quat_multiply_rows(a: np.ndarray, right_factors: np.ndarray) -> np.ndarray:
    """quat_multiply(a[i], b[i]) for every row of the (n, 4) array a, b given as
    quat_right_factors(b) (computed once for a run): four array operations whatever n. `a` may
    also be (samples, n, 4), the same n quaternions b for every sample (the products of a whole
    trajectory at once, each element's the same as one sample's)."""
    batch = (slice(None),) + (None,) * (a.ndim - 2)
    products = np.moveaxis(a, -1, 0)[..., None] * right_factors[batch]
    out: np.ndarray = ((products[0] + products[1]) + products[2]) + products[3]
    return out


def quat_conjugates(quaternions: Iterable[FloatVector]) -> np.ndarray:
    """quat_conjugate of each, as an (n, 4) array."""
    out = np.array([quat_conjugate(q) for q in quaternions], dtype=np.float64)
    return out.reshape(-1, 4)


def principal_to_scene_factors(scene: ResolvedScene) -> np.ndarray:
    """quat_right_factors of the conjugates of the bodies' principal rotations: a body's scene
    frame rotation is q_principal * conj(principal_rotation)."""
    return quat_right_factors(quat_conjugates(b.principal_rotation for b in scene.bodies))


def principal_to_scene_states(read: np.ndarray, principal_factors: np.ndarray) -> np.ndarray:
    """State arrays (state_array_rows) from the states of the bodies' principal frames as
    pybullet reports them, (bodies, 13) or a whole trajectory's (samples, bodies, 13): x y z,
    qx qy qz qw (pybullet's order), v, w; the scene frame's rotation bit for bit
    quat_multiply's (`principal_factors`: principal_to_scene_factors). Positions and velocities
    are kept as they are, a quaternion's finiteness too (simulate's `finish_states`)."""
    out = np.empty_like(read)
    out[..., 0:3] = read[..., 0:3]
    out[..., 3:7] = quat_multiply_rows(read[..., [6, 3, 4, 5]], principal_factors)
    out[..., 7:13] = read[..., 7:13]
    return out


def quat_conjugate(q: FloatVector) -> Quat:
    return (q[0], -q[1], -q[2], -q[3])


def quat_rotate(q: FloatVector, v: FloatVector) -> Vec3:
    """q v q*: the vector v rotated by the unit quaternion q."""
    r = quat_multiply(quat_multiply(q, (0.0, v[0], v[1], v[2])), quat_conjugate(q))
    return (r[1], r[2], r[3])


def quat_normalized(q: FloatVector) -> Quat:
    n = math.sqrt(sum(c * c for c in q))
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)
