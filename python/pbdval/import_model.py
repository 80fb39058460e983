"""Robots in: a URDF or MJCF model as a scene in the seed's format (docs/models.md).

    pbdval import MODEL.urdf|MODEL.xml [--out SCENE.json] [--fixed-base] [--no-collision]
    .venv/bin/python -m pbdval.import_model MODEL ...

Both formats are read into one description (`Model`: links with mass, centre of mass and
inertia tensor in world coordinates at the model's zero configuration, their collision shapes,
and the joints between them), from which `build_scene` writes the scene:

- a URDF with xml.etree: link frames composed along the joints (origin xyz, rpy as
  Rz(yaw) Ry(pitch) Rx(roll)), each `<inertial>` tensor rotated into the world;
- an MJCF by compiling it with MuJoCo (the installed `mujoco`, 4.x), which resolves defaults,
  includes, `fromto` and inertia-from-geoms, and reading the compiled model at qpos0
  (`xipos`, `ximat`, `body_inertia`, `xanchor`, `xaxis`, `geom_xpos`, `geom_xmat`).

Links joined by a fixed joint (URDF `fixed`, an MJCF body without joints) become one rigid
body with the exact composite inertia (parallel axis theorem). Each body's scene frame is its
principal frame (the eigenvectors of its inertia tensor about the centre of mass), so its
`mass` and `inertia` keys are exact. What the seed cannot represent is listed (`notes`),
printed and stored in the scene's `Validation.notes`; what makes the model unrepresentable is
an `ImportModelError` naming the file and the element.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

#: Shapes the seed has natively: its collisionObjectType for each.
SEED_SHAPE_TYPES = {"sphere": 1, "box": 2, "cylinder": 3}
#: Grid cells per axis of the SDF built for a mesh collision shape (collisionObjectType 5):
#: the finest the library's own mesh cases use (cases/contact_pile.json, 24 x 10 x 24).
SDF_RESOLUTION = 24
#: Relative tolerance under which a primitive's centre and axes count as the body's principal
#: frame (then it is written as the seed's primitive): far above the round-off of composing a
#: few frames (1e-15), far below any real offset.
FRAME_TOLERANCE = 1e-9
#: The scene loader's slack on the triangle inequality of principal moments (docs/scene-format.md,
#: "Checks on inertia").
TRIANGLE_SLACK = 1e-6
#: The seed's mass range for a dynamic body (docs/scene-format.md, Ranges).
MIN_MASS, MAX_MASS = 1e-12, 1e12
#: The frame step when the model gives none (URDF): the library's default timeStepSize.
DEFAULT_TIME_STEP = 0.005


class ImportModelError(ValueError):
    """A model the importer cannot read or the seed cannot represent; the message names the file
    and the element."""


@dataclass
class Shape:
    """A collision shape in world coordinates: `kind` sphere (size [r]), box (full extents),
    cylinder ([r, h], axis z of `rotation`), capsule ([r, h] of the cylinder part, axis z),
    ellipsoid (semi-axes), plane (half extents x, y; normal z), or mesh (`vertices` in the shape
    frame, `faces`)."""

    name: str
    kind: str
    position: np.ndarray
    rotation: np.ndarray
    size: list[float]
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None


@dataclass
class Link:
    """A rigid link: mass, centre of mass and inertia tensor about it, world coordinates."""

    name: str
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    shapes: list[Shape] = field(default_factory=list)
    static: bool = False


@dataclass
class Joint:
    """A joint between `parent` (a link name, or None: the world) and `child`: kind hinge,
    slider, ball, fixed or free; anchor and axis in world coordinates."""

    name: str
    kind: str
    parent: str | None
    child: str
    anchor: np.ndarray
    axis: np.ndarray
    axis2: np.ndarray | None = None  # universal joints: the axis fixed in the child


@dataclass
class Model:
    name: str
    path: Path
    links: list[Link]
    joints: list[Joint]
    gravity: list[float]
    time_step: float
    notes: list[str] = field(default_factory=list)
    world_shapes: list[Shape] = field(default_factory=list)
    collisions: bool = True


@dataclass
class Body:
    """One rigid body of the scene: links merged by fixed joints."""

    id: int
    links: list[str]
    mass: float
    com: np.ndarray
    rotation: np.ndarray  # principal frame → world, columns the principal axes
    moments: np.ndarray
    static: bool
    shapes: list[Shape]


@dataclass
class ImportResult:
    scene: dict[str, Any]
    notes: list[str]
    bodies: list[Body]
    body_of_link: dict[str, int]


# --- rotations --------------------------------------------------------------------------------

def rpy_matrix(rpy: list[float]) -> np.ndarray:
    """URDF's fixed-axis roll, pitch, yaw: Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def axis_angle(rotation: np.ndarray) -> tuple[np.ndarray, float]:
    """The axis and angle (rad, in [0, π]) of a rotation matrix, through its unit quaternion
    (Shepperd's branch choice, accurate at every angle)."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace >= max(m[0, 0], m[1, 1], m[2, 2]):
        w = math.sqrt(max(1.0 + trace, 0.0)) / 2
        q = np.array([w, (m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w),
                      (m[1, 0] - m[0, 1]) / (4 * w)])
    else:
        i = int(np.argmax([m[0, 0], m[1, 1], m[2, 2]]))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(max(1.0 + m[i, i] - m[j, j] - m[k, k], 0.0)) * 2
        v = np.zeros(3)
        v[i] = s / 4
        v[j] = (m[j, i] + m[i, j]) / s
        v[k] = (m[k, i] + m[i, k]) / s
        q = np.array([(m[k, j] - m[j, k]) / s, *v])
    q /= np.linalg.norm(q)
    if q[0] < 0:
        q = -q
    vector_norm = float(np.linalg.norm(q[1:]))
    if vector_norm == 0.0:
        return np.array([0.0, 0.0, 1.0]), 0.0
    return q[1:] / vector_norm, 2 * math.atan2(vector_norm, float(q[0]))


def principal_frame(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and axes (columns, a right-handed rotation) of a symmetric tensor."""
    moments, axes = np.linalg.eigh((inertia + inertia.T) / 2)
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    return moments, axes


def composite(links: list[Link]) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass, centre of mass and inertia about it of rigidly joined links (parallel axis theorem:
    I = Σ I_i + m_i (|d_i|² E − d_i d_iᵀ), d_i = c_i − c)."""
    mass = sum(link.mass for link in links)
    if mass <= 0:
        return 0.0, links[0].com.copy(), np.zeros((3, 3))
    com = sum((link.mass * link.com for link in links), np.zeros(3)) / mass
    inertia = np.zeros((3, 3))
    for link in links:
        d = link.com - com
        inertia += link.inertia + link.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


# --- URDF ---------------------------------------------------------------------------------------

def _floats(element: ET.Element, key: str, count: int, default: list[float] | None, where: str,
            path: Path) -> list[float]:
    text = element.get(key)
    if text is None:
        if default is None:
            raise ImportModelError(f"{path}: {where}: attribute '{key}' is missing")
        return list(default)
    try:
        values = [float(v) for v in text.split()]
    except ValueError:
        raise ImportModelError(f"{path}: {where}: attribute {key}=\"{text}\": expected {count} numbers") from None
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise ImportModelError(f"{path}: {where}: attribute {key}=\"{text}\": expected {count} finite numbers")
    return values


def _origin(element: ET.Element, where: str, path: Path) -> tuple[np.ndarray, np.ndarray]:
    origin = element.find("origin")
    if origin is None:
        return np.zeros(3), np.eye(3)
    xyz = _floats(origin, "xyz", 3, [0, 0, 0], f"{where}/origin", path)
    rpy = _floats(origin, "rpy", 3, [0, 0, 0], f"{where}/origin", path)
    return np.array(xyz), rpy_matrix(rpy)


def _mesh_file(filename: str, model_path: Path, where: str) -> Path:
    """A URDF mesh reference resolved as pybullet resolves it: package:// and file:// stripped,
    relative to the URDF's folder, then its parents."""
    name = filename
    for prefix in ("package://", "file://"):
        name = name.removeprefix(prefix)
    candidates = [model_path.parent / name]
    parts = Path(name).parts
    candidates += [model_path.parent / Path(*parts[i:]) for i in range(1, len(parts))]
    candidates += [parent / name for parent in model_path.parents]
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    raise ImportModelError(f"{model_path}: {where}: mesh file '{filename}' not found")


def read_mesh(file: Path, scale: np.ndarray, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (scaled) and triangles of an STL, OBJ or DAE (COLLADA) file, read with trimesh
    (COLLADA through pycollada); a DAE file's scenes are flattened into one mesh, each geometry
    placed by its node's transform, as trimesh's loader does."""
    suffix = file.suffix.lower()
    if suffix not in (".stl", ".obj", ".dae"):
        raise ImportModelError(f"{where}: mesh {file}: expected an STL, OBJ or DAE file")
    import trimesh

    try:
        loaded: Any = trimesh.load(file, force="mesh", process=False)
        vertices = np.asarray(loaded.vertices, dtype=np.float64) * scale
        faces = np.asarray(loaded.faces, dtype=np.int64)
    except Exception as error:  # noqa: BLE001 - a third-party reader: pycollada raises its own
        # DaeError kinds and AttributeError on a document without scenes; every failure is the file's
        raise ImportModelError(f"{where}: mesh {file}: cannot be read: {error}") from None
    if len(vertices) == 0 or len(faces) == 0:
        raise ImportModelError(f"{where}: mesh {file}: has no triangles")
    return vertices, faces


def _urdf_shapes(link_element: ET.Element, frame: tuple[np.ndarray, np.ndarray], path: Path) -> list[Shape]:
    name = link_element.get("name", "")
    shapes: list[Shape] = []
    for index, collision in enumerate(link_element.findall("collision")):
        where = f"link '{name}'/collision[{index}]"
        offset, rotation = _origin(collision, where, path)
        position = frame[0] + frame[1] @ offset
        world_rotation = frame[1] @ rotation
        geometry = collision.find("geometry")
        if geometry is None or len(geometry) == 0:
            raise ImportModelError(f"{path}: {where}: no <geometry>")
        g = geometry[0]
        label = collision.get("name") or f"{name}[{index}]"
        if g.tag == "box":
            size = _floats(g, "size", 3, None, f"{where}/box", path)
            shapes.append(Shape(label, "box", position, world_rotation, size))
        elif g.tag == "sphere":
            shapes.append(Shape(label, "sphere", position, world_rotation,
                                _floats(g, "radius", 1, None, f"{where}/sphere", path)))
        elif g.tag in ("cylinder", "capsule"):
            r = _floats(g, "radius", 1, None, f"{where}/{g.tag}", path)[0]
            h = _floats(g, "length", 1, None, f"{where}/{g.tag}", path)[0]
            shapes.append(Shape(label, g.tag, position, world_rotation, [r, h]))
        elif g.tag == "mesh":
            file = _mesh_file(g.get("filename", ""), path, f"{where}/mesh")
            scale = np.array(_floats(g, "scale", 3, [1, 1, 1], f"{where}/mesh", path))
            vertices, faces = read_mesh(file, scale, f"{path}: {where}")
            shapes.append(Shape(label, "mesh", position, world_rotation, [], vertices, faces))
        else:
            raise ImportModelError(f"{path}: {where}: geometry <{g.tag}>: expected box, sphere, "
                                   "cylinder, capsule or mesh")
    return shapes


def _urdf_inertial(link_element: ET.Element, frame: tuple[np.ndarray, np.ndarray], path: Path
                   ) -> tuple[float, np.ndarray, np.ndarray]:
    name = link_element.get("name", "")
    inertial = link_element.find("inertial")
    if inertial is None:
        return 0.0, frame[0].copy(), np.zeros((3, 3))
    where = f"link '{name}'/inertial"
    offset, rotation = _origin(inertial, where, path)
    mass_element = inertial.find("mass")
    mass = 0.0 if mass_element is None else _floats(mass_element, "value", 1, None, f"{where}/mass", path)[0]
    if mass < 0:
        raise ImportModelError(f"{path}: {where}/mass: expected a mass ≥ 0, got {mass}")
    tensor = np.zeros((3, 3))
    element = inertial.find("inertia")
    if element is not None:
        keys = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
        v = {k: _floats(element, k, 1, [0.0], f"{where}/inertia", path)[0] for k in keys}
        tensor = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]],
                           [v["ixz"], v["iyz"], v["izz"]]])
    world_rotation = frame[1] @ rotation
    return mass, frame[0] + frame[1] @ offset, world_rotation @ tensor @ world_rotation.T


URDF_JOINTS = {"revolute": "hinge", "continuous": "hinge", "prismatic": "slider", "fixed": "fixed",
               "floating": "free", "spherical": "ball", "ball": "ball"}


def axis_rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation by `angle` about the unit `axis` (Rodrigues)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation: np.ndarray = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
    return rotation


def _unused_positions(positions: dict[str, float], used: set[str], path: Path, notes: list[str]) -> None:
    """Refuses a position for a joint the model has not (as a hinge or slider); notes the others."""
    notes.extend(f"joint '{name}': starts at {value!r} (--joint)" for name, value in positions.items())
    unknown = sorted(set(positions) - used)
    if unknown:
        raise ImportModelError(f"{path}: --joint {unknown[0]}: no hinge or slider joint of this name")


def read_urdf(path: Path, fixed_base: bool = False, positions: dict[str, float] | None = None,
              inertia_from_collision: bool = False) -> Model:
    """The model at the joint positions `positions` (joint name → rad or m; 0 for the others).
    With `inertia_from_collision`, every link with collision shapes takes their inertia (as
    pybullet's loadURDF does without URDF_USE_INERTIA_FROM_FILE), not the file's."""
    positions = positions or {}
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as error:
        raise ImportModelError(f"{path}: not well-formed XML: {error}") from None
    if root.tag != "robot":
        raise ImportModelError(f"{path}: expected a <robot> root element, got <{root.tag}>")
    notes: list[str] = []
    link_elements: dict[str, ET.Element] = {}
    for element in root.findall("link"):
        name = element.get("name")
        if not name:
            raise ImportModelError(f"{path}: a <link> without a name")
        if name in link_elements:
            raise ImportModelError(f"{path}: link '{name}' defined twice")
        link_elements[name] = element
    if not link_elements:
        raise ImportModelError(f"{path}: the robot has no <link>")
    joint_elements = root.findall("joint")
    children: dict[str, list[ET.Element]] = {}
    parent_of: dict[str, str] = {}
    for element in joint_elements:
        name = element.get("name", "")
        parent, child = element.find("parent"), element.find("child")
        if parent is None or child is None:
            raise ImportModelError(f"{path}: joint '{name}': needs <parent> and <child>")
        p, c = parent.get("link", ""), child.get("link", "")
        for role, link in (("parent", p), ("child", c)):
            if link not in link_elements:
                raise ImportModelError(f"{path}: joint '{name}'/{role}: no link named '{link}'")
        if c in parent_of:
            raise ImportModelError(f"{path}: joint '{name}': link '{c}' is the child of two joints "
                                   "(a URDF is a tree)")
        parent_of[c] = p
        children.setdefault(p, []).append(element)
    roots = [n for n in link_elements if n not in parent_of]
    if len(roots) != 1:
        raise ImportModelError(f"{path}: expected one root link (a tree), got {len(roots)}: "
                               + ", ".join(roots[:5]))
    for element in root.findall("transmission"):
        notes.append(f"transmission '{element.get('name', '')}': dropped (the seed has no actuators)")
    for element in root.iter("gazebo"):
        notes.append("a <gazebo> block: dropped (simulator-specific settings)")
        break

    links: list[Link] = []
    joints: list[Joint] = []
    used: set[str] = set()
    frames: dict[str, tuple[np.ndarray, np.ndarray]] = {roots[0]: (np.zeros(3), np.eye(3))}
    order = [roots[0]]
    for name in order:  # breadth first: every parent's frame is known before its children's
        element = link_elements[name]
        frame = frames[name]
        mass, com, inertia = _urdf_inertial(element, frame, path)
        shapes = _urdf_shapes(element, frame, path)
        if mass > 0 and shapes and inertia_from_collision:
            com, inertia = _inertia_from_shapes(shapes, mass, f"{path}: link '{name}'")
            notes.append(f"link '{name}': --inertia-from-collision: the centre of mass and inertia of its "
                         "collision shapes as a uniform solid of its mass (approximated; pybullet's loadURDF "
                         "takes the shapes' inertia by default, at the file's inertial origin)")
        elif mass > 0 and shapes and not np.all(np.linalg.eigvalsh(inertia) > 0):
            inertia = _inertia_from_shapes(shapes, mass, f"{path}: link '{name}'")[1]
            notes.append(f"link '{name}': inertia not positive definite in the file: the inertia of its "
                         "collision shapes as a uniform solid of its mass, about their centroid, placed at "
                         "its centre of mass (approximated, as pybullet's loadURDF does by default)")
        if element.find("contact") is not None:
            notes.append(f"link '{name}': <contact> (pybullet's contact settings) dropped")
        links.append(Link(name, mass, com, inertia, shapes))
        for j in children.get(name, []):
            jname = j.get("name", "")
            where = f"joint '{jname}'"
            jtype = j.get("type", "")
            if jtype == "planar":
                raise ImportModelError(f"{path}: {where}: type 'planar' (2 translations and a "
                                       "rotation in one joint) has no joint of the seed")
            if jtype not in URDF_JOINTS:
                raise ImportModelError(f"{path}: {where}: unknown type '{jtype}'")
            offset, rotation = _origin(j, where, path)
            child_frame = (frame[0] + frame[1] @ offset, frame[1] @ rotation)
            child = j.find("child")
            assert child is not None
            child_name = child.get("link", "")
            axis_element = j.find("axis")
            axis = np.array([1.0, 0.0, 0.0]) if axis_element is None else np.array(
                _floats(axis_element, "xyz", 3, [1, 0, 0], f"{where}/axis", path))
            kind = URDF_JOINTS[jtype]
            if kind in ("hinge", "slider") and not np.linalg.norm(axis) > 0:
                raise ImportModelError(f"{path}: {where}/axis: a zero axis")
            world_axis = child_frame[1] @ axis
            joint_origin = child_frame[0].copy()
            if jname in positions and kind in ("hinge", "slider"):
                used.add(jname)
                unit = axis / np.linalg.norm(axis)
                if kind == "hinge":
                    child_frame = (child_frame[0], child_frame[1] @ axis_rotation(unit, positions[jname]))
                else:
                    child_frame = (child_frame[0] + child_frame[1] @ unit * positions[jname], child_frame[1])
            frames[child_name] = child_frame
            order.append(child_name)
            if kind in ("hinge", "slider"):
                world_axis = world_axis / np.linalg.norm(world_axis)
            joints.append(Joint(jname, kind, name, child_name, joint_origin, world_axis))
            limit = j.find("limit")
            if limit is not None and jtype in ("revolute", "prismatic") and (
                    limit.get("lower") is not None or limit.get("upper") is not None):
                notes.append(f"{where}: limits [{limit.get('lower', '0')}, {limit.get('upper', '0')}] "
                             "dropped (the seed's joints have no limits)")
            if limit is not None and (limit.get("effort") is not None or limit.get("velocity") is not None) \
                    and kind != "fixed":
                notes.append(f"{where}: effort and velocity limits dropped (no actuators)")
            dynamics = j.find("dynamics")
            if dynamics is not None:
                for key in ("damping", "friction"):
                    value = dynamics.get(key)
                    if value is not None and float(value) != 0:
                        notes.append(f"{where}: {key} {value} dropped (the seed's joints are ideal)")
            if j.find("mimic") is not None:
                notes.append(f"{where}: mimic dropped (the joint moves freely)")
            if j.find("safety_controller") is not None:
                notes.append(f"{where}: safety_controller dropped")
            if kind == "free":
                notes.append(f"{where}: floating: the child is a free body")
    _unused_positions(positions, used, path, notes)
    model = Model(root.get("name", path.stem), path, links, [j for j in joints if j.kind != "free"],
                  [0.0, 0.0, -9.81], DEFAULT_TIME_STEP, notes)
    for joint in joints:
        if joint.kind == "free":
            model.joints.append(Joint(joint.name, "free", None, joint.child, joint.anchor, joint.axis))
    root_link = links[0]
    if fixed_base or root_link.mass == 0:
        root_link.static = True
        notes.append(f"link '{root_link.name}' (the root): static ("
                     + ("--fixed-base" if fixed_base else "no mass, as pybullet's loadURDF takes it") + ")")
    else:
        notes.append(f"link '{root_link.name}' (the root): a free body (give --fixed-base to fix it)")
    notes.insert(0, "gravity: URDF has none; the scene uses [0, 0, -9.81] (z up, as pybullet)")
    return model


# --- MJCF ---------------------------------------------------------------------------------------

#: MuJoCo's joint types (mjtJoint) as the importer's kinds.
JOINT_KINDS = {0: "free", 1: "ball", 2: "slider", 3: "hinge"}
#: |cos| between two hinge axes below which they count as perpendicular: the scene loader's own
#: bound for a universal joint's axes (docs/scene-format.md, Joints).
PERPENDICULAR_COSINE = 1e-6


def _hinges_as_one_joint(m: Any, d: Any, first: int, count: int, kinds: list[str], parent: str | None,
                         child: str, path: Path, notes: list[str]) -> Joint:
    """Several joints of one MuJoCo body as one joint of the seed: two perpendicular hinges
    through one point are a universal joint (MuJoCo composes a body's joints in order, so the
    first axis is fixed in the parent and the second in the child, as the seed's axis1 and
    axis2), three mutually perpendicular ones a ball joint. Anything else is refused."""
    names = [m.joint(first + k).name or f"joint{first + k}" for k in range(count)]
    listed = ", ".join(f"'{n}' ({k})" for n, k in zip(names, kinds, strict=True))
    refusal = (f"{path}: body '{child}': {count} joints ({listed}); the seed joins two bodies by one joint "
               "(two perpendicular hinges through one point, a universal joint, and three, a ball joint, "
               "are the combinations it has)")
    if count > 3 or any(k != "hinge" for k in kinds):
        raise ImportModelError(refusal)
    anchors = [d.xanchor[first + k] for k in range(count)]
    axes = [d.xaxis[first + k] / np.linalg.norm(d.xaxis[first + k]) for k in range(count)]
    size = max(1.0, float(np.linalg.norm(anchors[0])))
    if any(np.linalg.norm(a - anchors[0]) > FRAME_TOLERANCE * size for a in anchors):
        raise ImportModelError(refusal + "; these hinges do not share a point")
    if any(abs(float(axes[i] @ axes[k])) > PERPENDICULAR_COSINE for i in range(count) for k in range(i)):
        raise ImportModelError(refusal + "; these hinges are not perpendicular")
    kind = "universal" if count == 2 else "ball"
    notes.append(f"body '{child}': hinges {', '.join(repr(n) for n in names)} through one point, perpendicular: "
                 f"the seed's {kind} joint (exact)")
    return Joint(" + ".join(names), kind, parent, child, anchors[0].copy(), axes[0].copy(),
                 axes[1].copy() if count == 2 else None)


def read_mjcf(path: Path, positions: dict[str, float] | None = None) -> Model:
    """The compiled model at qpos0, with the hinge and slide joints named in `positions` moved
    to these values (rad, m)."""
    import mujoco

    try:
        m = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as error:
        raise ImportModelError(f"{path}: MuJoCo cannot compile it: {' '.join(str(error).split())}") from None
    d = mujoco.MjData(m)
    notes: list[str] = []
    used: set[str] = set()
    for j in range(m.njnt):
        name = m.joint(j).name
        if name in (positions or {}) and JOINT_KINDS[int(m.jnt_type[j])] in ("hinge", "slider"):
            d.qpos[m.jnt_qposadr[j]] += (positions or {})[name]
            used.add(name)
    _unused_positions(positions or {}, used, path, notes)
    mujoco.mj_kinematics(m, d)
    mujoco.mj_comPos(m, d)
    names = [m.body(b).name or f"body{b}" for b in range(m.nbody)]

    def jname(j: int) -> str:
        return m.joint(j).name or f"joint{j}"

    def gname(g: int) -> str:
        return m.geom(g).name or f"geom{g}"

    contact_off = bool(m.opt.disableflags & (mujoco.mjtDisableBit.mjDSBL_CONTACT |
                                             mujoco.mjtDisableBit.mjDSBL_CONSTRAINT))
    if contact_off:
        notes.append("option/flag: contacts disabled in the model: the scene's bodies get no "
                     "collision shape")
    links: list[Link] = []
    joints: list[Joint] = []
    geom_kinds = {int(mujoco.mjtGeom.mjGEOM_SPHERE): "sphere", int(mujoco.mjtGeom.mjGEOM_BOX): "box",
                  int(mujoco.mjtGeom.mjGEOM_CYLINDER): "cylinder",
                  int(mujoco.mjtGeom.mjGEOM_CAPSULE): "capsule",
                  int(mujoco.mjtGeom.mjGEOM_ELLIPSOID): "ellipsoid",
                  int(mujoco.mjtGeom.mjGEOM_PLANE): "plane", int(mujoco.mjtGeom.mjGEOM_MESH): "mesh"}
    shapes_of: dict[int, list[Shape]] = {b: [] for b in range(m.nbody)}
    for g in range(m.ngeom):
        where = f"geom '{gname(g)}' of body '{names[m.geom_bodyid[g]]}'"
        if m.geom_contype[g] == 0 and m.geom_conaffinity[g] == 0:
            continue  # visual only: never collides in MuJoCo either
        if contact_off:
            continue
        kind = geom_kinds.get(int(m.geom_type[g]))
        if kind is None:
            notes.append(f"{where}: type {mujoco.mjtGeom(m.geom_type[g]).name} dropped (no such shape)")
            continue
        size = m.geom_size[g]
        position, rotation = d.geom_xpos[g].copy(), d.geom_xmat[g].reshape(3, 3).copy()
        shape: Shape
        if kind == "sphere":
            shape = Shape(gname(g), kind, position, rotation, [float(size[0])])
        elif kind == "box" or kind == "ellipsoid":
            shape = Shape(gname(g), kind, position, rotation, [float(2 * s) if kind == "box" else float(s)
                                                               for s in size])
        elif kind in ("cylinder", "capsule"):
            shape = Shape(gname(g), kind, position, rotation, [float(size[0]), float(2 * size[1])])
        elif kind == "plane":
            half = [float(size[0]) or 50.0, float(size[1]) or 50.0]
            shape = Shape(gname(g), kind, position, rotation, half)
        else:
            mesh = int(m.geom_dataid[g])
            first, count = int(m.mesh_vertadr[mesh]), int(m.mesh_vertnum[mesh])
            face_first, face_count = int(m.mesh_faceadr[mesh]), int(m.mesh_facenum[mesh])
            shape = Shape(gname(g), kind, position, rotation, [],
                          np.array(m.mesh_vert[first:first + count], dtype=float),
                          np.array(m.mesh_face[face_first:face_first + face_count], dtype=np.int64))
        if m.geom_contype[g] != 1 or m.geom_conaffinity[g] != 1:
            notes.append(f"{where}: contype {m.geom_contype[g]} / conaffinity {m.geom_conaffinity[g]}: "
                         "collision filtering dropped (every pair of bodies may collide)")
        shapes_of[int(m.geom_bodyid[g])].append(shape)
    world_shapes: list[Shape] = shapes_of[0]
    for b in range(1, m.nbody):
        tensor = d.ximat[b].reshape(3, 3) @ np.diag(m.body_inertia[b]) @ d.ximat[b].reshape(3, 3).T
        links.append(Link(names[b], float(m.body_mass[b]), d.xipos[b].copy(), tensor, shapes_of[b]))
        parent = int(m.body_parentid[b])
        parent_name = None if parent == 0 else names[parent]
        count, first = int(m.body_jntnum[b]), int(m.body_jntadr[b])
        if count == 0:
            if parent_name is None:
                links[-1].static = True
                notes.append(f"body '{names[b]}': no joint, welded to the world: static")
            else:
                joints.append(Joint(f"weld of '{names[b]}'", "fixed", parent_name, names[b], d.xipos[b].copy(),
                                    np.zeros(3)))
            continue
        kinds = [JOINT_KINDS[int(m.jnt_type[first + k])] for k in range(count)]
        if count == 1:
            joints.append(Joint(jname(first), kinds[0], parent_name, names[b], d.xanchor[first].copy(),
                                d.xaxis[first].copy()))
        else:
            joints.append(_hinges_as_one_joint(m, d, first, count, kinds, parent_name, names[b], path, notes))
        for j in range(first, first + count):
            where = f"joint '{jname(j)}'"
            if m.jnt_limited[j]:
                notes.append(f"{where}: range {list(map(float, m.jnt_range[j]))} dropped (no joint limits)")
            if float(m.jnt_stiffness[j]) != 0:
                notes.append(f"{where}: stiffness {float(m.jnt_stiffness[j])} dropped")
            kind = JOINT_KINDS[int(m.jnt_type[j])]
            dofs = range(int(m.jnt_dofadr[j]), int(m.jnt_dofadr[j]) + {"free": 6, "ball": 3}.get(kind, 1))
            for key, values in (("damping", m.dof_damping), ("frictionloss", m.dof_frictionloss),
                                ("armature", m.dof_armature)):
                if any(float(values[k]) != 0 for k in dofs):
                    notes.append(f"{where}: {key} {float(values[dofs[0]])} dropped (the seed's joints are ideal)")
    for a in range(m.nu):
        notes.append(f"actuator '{m.actuator(a).name or a}': dropped (the seed has no actuators)")
    for t in range(m.ntendon):
        notes.append(f"tendon '{m.tendon(t).name or t}': dropped (the seed has no tendons)")
    for e in range(m.neq):
        notes.append(f"equality '{m.eq(e).name or e}': dropped")
    integrator = mujoco.mjtIntegrator(m.opt.integrator).name.split("_", 1)[1]
    notes.append(f"option: integrator {integrator}, timestep {float(m.opt.timestep)}: the timestep is "
                 "the scene's timeStepSize; the integrator is the method's")
    name = ET.parse(path).getroot().get("model") or path.stem
    return Model(name, path, links, joints, [float(v) for v in m.opt.gravity], float(m.opt.timestep), notes,
                 world_shapes)


# --- the scene ----------------------------------------------------------------------------------

def _merge(model: Model) -> tuple[list[list[Link]], dict[str, int]]:
    """Groups of links joined by fixed joints (union-find), in link order."""
    index = {link.name: i for i, link in enumerate(model.links)}
    parent = list(range(len(model.links)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for joint in model.joints:
        if joint.kind == "fixed" and joint.parent is not None:
            a, b = find(index[joint.parent]), find(index[joint.child])
            parent[max(a, b)] = min(a, b)
    groups: dict[int, list[Link]] = {}
    for i, link in enumerate(model.links):
        groups.setdefault(find(i), []).append(link)
    ordered = list(groups.values())
    group_of = {link.name: g for g, members in enumerate(ordered) for link in members}
    return ordered, group_of


def _primitive_frame(shape: Shape, com: np.ndarray, moments: np.ndarray, axes: np.ndarray,
                     scale: float) -> np.ndarray | None:
    """The body rotation that makes `shape` the seed's primitive about the centre of mass, or
    None: the shape's centre must be the centre of mass and (box, cylinder) its axes principal
    axes; a cylinder's axis becomes the body's y axis (the seed's cylinder axis)."""
    if np.linalg.norm(shape.position - com) > FRAME_TOLERANCE * scale:
        return None
    if shape.kind == "sphere":
        return axes
    rotation = shape.rotation
    if shape.kind == "cylinder":  # shape z → body y: columns (x, y, z) = (shape y, shape z, shape x)
        rotation = np.column_stack([shape.rotation[:, 1], shape.rotation[:, 2], shape.rotation[:, 0]])
    tensor = axes @ np.diag(moments) @ axes.T
    local = rotation.T @ tensor @ rotation
    off_diagonal = local - np.diag(np.diag(local))
    if np.max(np.abs(off_diagonal)) > FRAME_TOLERANCE * max(float(np.max(np.abs(moments))), 1e-300):
        return None
    return rotation


def _tessellate(shape: Shape, notes: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A closed triangle mesh of a shape, in world coordinates (an open mesh: its convex hull,
    noted in `notes`)."""
    import trimesh

    if shape.kind == "mesh":
        assert shape.vertices is not None and shape.faces is not None
        mesh = trimesh.Trimesh(shape.vertices, shape.faces, process=True)
        if not mesh.is_watertight:
            try:
                mesh = mesh.convex_hull
                if notes is not None:
                    notes.append(f"collision mesh '{shape.name}': not closed: its convex hull (approximated)")
            except ValueError as error:  # scipy's QhullError is a ValueError
                raise ImportModelError(f"collision mesh '{shape.name}': not closed, and its convex hull "
                                       f"cannot be built: {error}") from None
    elif shape.kind == "box" or shape.kind == "plane":
        extents = shape.size if shape.kind == "box" else [2 * shape.size[0], 2 * shape.size[1], 0.1]
        mesh = trimesh.creation.box(extents=extents)
        if shape.kind == "plane":
            mesh.apply_translation([0, 0, -0.05])
    elif shape.kind == "sphere":
        mesh = trimesh.creation.icosphere(subdivisions=3, radius=shape.size[0])
    elif shape.kind == "ellipsoid":
        mesh = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
        mesh.vertices = mesh.vertices * np.array(shape.size)
    elif shape.kind == "cylinder":
        mesh = trimesh.creation.cylinder(radius=shape.size[0], height=shape.size[1], sections=32)
    else:
        mesh = trimesh.creation.capsule(height=shape.size[1], radius=shape.size[0], count=[32, 16])
    vertices = np.asarray(mesh.vertices, dtype=float) @ shape.rotation.T + shape.position
    return vertices, np.asarray(mesh.faces, dtype=np.int64)


def _inertia_from_shapes(shapes: list[Shape], mass: float, where: str) -> tuple[np.ndarray, np.ndarray]:
    """The centroid and the inertia tensor about it (world axes) of the shapes' union as a uniform
    solid of `mass`."""
    import trimesh

    parts = [_tessellate(shape) for shape in shapes]
    offsets = np.cumsum([0] + [len(v) for v, _ in parts])
    mesh = trimesh.Trimesh(np.vstack([v for v, _ in parts]),
                           np.vstack([f + offsets[k] for k, (_, f) in enumerate(parts)]), process=False)
    if not mesh.volume > 0:
        raise ImportModelError(f"{where}: no inertia in the file and its collision shapes enclose no volume")
    tensor: np.ndarray = np.asarray(mesh.moment_inertia, dtype=np.float64) * (mass / float(mesh.volume))
    return np.asarray(mesh.center_mass, dtype=np.float64), tensor


def _centroid_at_origin(vertices: np.ndarray, faces: np.ndarray, extent: float) -> bool:
    """Whether the solid a closed mesh encloses has its centroid at the origin (to FRAME_TOLERANCE
    of the model's size), as the scene loader integrates it (additively over the triangles)."""
    import trimesh

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    if not float(mesh.volume) > 0:
        return False
    return bool(np.linalg.norm(np.asarray(mesh.center_mass, dtype=np.float64)) <= FRAME_TOLERANCE * extent)


def _write_obj(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    lines = ["# written by pbdval import (docs/models.md)"]
    lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces.tolist()]
    _write_atomically(path, "\n".join(lines) + "\n")


def _write_atomically(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    with os.fdopen(handle, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(temporary, path)


def _vector(values: np.ndarray) -> list[float]:
    return [float(v) for v in values]


def build_scene(model: Model, scene_path: Path, mesh_folder: Path | None = None,
                collisions: bool = True, collision_links: set[str] | None = None) -> ImportResult:
    """The scene of `model`; mesh collision shapes are written as OBJ files to `mesh_folder`
    (default: SCENE.meshes next to the scene) and referenced relative to the scene's folder."""
    notes = list(model.notes)
    if collision_links is not None:
        unknown = sorted(collision_links - {link.name for link in model.links})
        if unknown:
            raise ImportModelError(f"{model.path}: --collision-links: no link named '{unknown[0]}'")
        for link in model.links:
            if link.shapes and link.name not in collision_links:
                notes.append(f"link '{link.name}': collision shapes left out (not in --collision-links)")
                link.shapes = []
    groups, group_of = _merge(model)
    for joint in model.joints:
        if joint.kind == "fixed" and joint.parent is not None:
            notes.append(f"fixed joint {joint.name}: '{joint.child}' merged into the body of "
                         f"'{joint.parent}' (composite inertia)")
    mesh_folder = mesh_folder or scene_path.parent / f"{scene_path.stem}.meshes"
    bodies: list[Body] = []
    entries: list[dict[str, Any]] = []
    extent = max([1.0] + [float(np.linalg.norm(link.com)) for link in model.links])
    for g, members in enumerate(groups):
        mass, com, inertia = composite(members)
        static = any(link.static for link in members)
        label = " + ".join(f"'{link.name}'" for link in members)
        shapes = [s for link in members for s in link.shapes] if collisions else []
        if not static and not (MIN_MASS <= mass <= MAX_MASS):
            raise ImportModelError(f"{model.path}: link {label}: mass {mass} kg is outside the seed's "
                                   f"[{MIN_MASS:g}, {MAX_MASS:g}] kg for a moving body")
        moments, axes = principal_frame(inertia)
        if not static:
            if not np.all(moments > 0):
                raise ImportModelError(f"{model.path}: link {label}: inertia tensor {inertia.tolist()} has a "
                                       "principal moment ≤ 0; the seed needs a positive-definite inertia")
            a, b, c = sorted(moments)
            if a + b < c * (1 - TRIANGLE_SLACK):
                moment_list = [float(v) for v in moments]
                raise ImportModelError(f"{model.path}: link {label}: principal moments {moment_list} violate "
                                       "the triangle inequality (Ia + Ib ≥ Ic), as no rigid body does")
        rotation = axes
        entry: dict[str, Any] = {"id": g, "isDynamic": not static}
        shape_type = 0
        if len(shapes) == 1 and shapes[0].kind in SEED_SHAPE_TYPES and not static:
            frame = _primitive_frame(shapes[0], com, moments, axes, extent)
            if frame is not None:
                rotation = frame
                shape_type = SEED_SHAPE_TYPES[shapes[0].kind]
                size = shapes[0].size
                entry["collisionObjectScale"] = ([size[0]] * 3 if shape_type == 1 else
                                                 list(size) if shape_type == 2 else [size[0], size[1], size[0]])
        if shapes and shape_type == 0:
            vertices, faces = [], []
            offset = 0
            for shape in shapes:
                v, f = _tessellate(shape, notes)
                vertices.append(v)
                faces.append(f + offset)
                offset += len(v)
                if shape.kind in ("capsule", "ellipsoid", "plane") or (
                        shape.kind in SEED_SHAPE_TYPES and len(shapes) > 1):
                    notes.append(f"collision shape '{shape.name}' ({shape.kind}) of {label}: a mesh with "
                                 "its SDF (approximated)")
                elif shape.kind in SEED_SHAPE_TYPES:
                    notes.append(f"collision shape '{shape.name}' ({shape.kind}) of {label}: off the centre "
                                 "of mass or the principal axes: a mesh with its SDF (approximated)")
            local = (np.vstack(vertices) - com) @ rotation
            mesh_file = mesh_folder / f"body{g}_{members[0].name}.obj"
            _write_obj(mesh_file, local, np.vstack(faces))
            shape_type = 5
            entry["collisionObjectFileName"] = os.path.relpath(mesh_file, scene_path.parent)
            entry["resolutionSDF"] = [SDF_RESOLUTION] * 3
            if static or _centroid_at_origin(local, np.vstack(faces), extent):
                # The loader puts the centre of mass at the mesh's centroid: here it is the body's
                # (or the body is static), so the mesh can be the geometry too: its vertices are
                # tested for contacts, and the engines that build shapes from geometryFile take it.
                entry["geometryFile"] = entry.pop("collisionObjectFileName")
            else:
                notes.append(f"body of {label}: its collision mesh's centroid is not its centre of mass, so "
                             "the mesh is its SDF only (collisionObjectFileName, no geometryFile): its "
                             "vertices are not tested for contacts, and engines that need a geometryFile "
                             "report the body unsupported")
        entry["collisionObjectType"] = shape_type
        entry["translation"] = _vector(com)
        axis, angle = axis_angle(rotation)
        if angle != 0.0:
            entry["rotationAxis"] = _vector(axis)
            entry["rotationAngle"] = angle
        local_moments = np.diag(rotation.T @ inertia @ rotation)
        entry["mass"] = mass if mass > 0 else 1.0
        entry["inertia"] = _vector(local_moments) if not static or np.all(local_moments > 0) else [1.0, 1.0, 1.0]
        entries.append(entry)
        bodies.append(Body(g, [link.name for link in members], mass, com, rotation, local_moments, static,
                           shapes))
    body_of_link = {name: group_of[name] for name in group_of}
    world_id: int | None = next((b.id for b in bodies if b.static), None)
    needs_world = any(j.parent is None and j.kind not in ("free", "fixed") for j in model.joints)
    if needs_world and world_id is None:
        world_id = len(entries)
        entries.append({"id": world_id, "isDynamic": False, "collisionObjectType": 0, "translation": [0, 0, 0],
                        "mass": 1.0, "inertia": [1.0, 1.0, 1.0]})
        notes.append(f"body {world_id}: the world (static, no shape), which joints to the world attach to")
    if collisions:
        for shape in model.world_shapes:
            v, f = _tessellate(shape)
            body_id = len(entries)
            if shape.kind == "plane":
                notes.append(f"world geom '{shape.name}': the plane as a static box {2 * shape.size[0]} x "
                             f"{2 * shape.size[1]} x 0.1 m below it (approximated)")
                entry = {"id": body_id, "isDynamic": False, "collisionObjectType": 2,
                         "collisionObjectScale": [2 * shape.size[0], 2 * shape.size[1], 0.1],
                         "translation": _vector(shape.position - 0.05 * shape.rotation[:, 2])}
                axis, angle = axis_angle(shape.rotation)
            else:
                center = shape.position
                mesh_file = mesh_folder / f"world_{shape.name}.obj"
                _write_obj(mesh_file, v - center, f)
                entry = {"id": body_id, "isDynamic": False, "collisionObjectType": 5,
                         "geometryFile": os.path.relpath(mesh_file, scene_path.parent),
                         "resolutionSDF": [SDF_RESOLUTION] * 3, "translation": _vector(center),
                         "mass": 1.0, "inertia": [1.0, 1.0, 1.0]}
                angle = 0.0
                axis = np.zeros(3)
                if shape.kind in SEED_SHAPE_TYPES:
                    notes.append(f"world geom '{shape.name}' ({shape.kind}): a static mesh with its SDF")
                else:
                    notes.append(f"world geom '{shape.name}' ({shape.kind}): a static mesh with its SDF "
                                 "(approximated)")
            if angle != 0.0:
                entry["rotationAxis"] = _vector(axis)
                entry["rotationAngle"] = angle
            entries.append(entry)
    elif model.world_shapes:
        notes.append("collisions off (--no-collision): no collision shapes written")
    if not collisions and any(link.shapes for link in model.links):
        notes.append("collisions off (--no-collision): the links' collision shapes are not written")

    blocks: dict[str, list[dict[str, Any]]] = {"BallJoints": [], "HingeJoints": [], "UniversalJoints": [],
                                               "SliderJoints": []}
    for joint in model.joints:
        if joint.kind in ("fixed", "free"):
            continue
        parent_id = world_id if joint.parent is None else body_of_link[joint.parent]
        child_id = body_of_link[joint.child]
        assert parent_id is not None
        if parent_id == child_id:
            raise ImportModelError(f"{model.path}: joint '{joint.name}' closes a loop within one rigid body")
        row: dict[str, Any] = {"bodyID1": parent_id, "bodyID2": child_id}
        if joint.kind == "ball":
            row["position"] = _vector(joint.anchor)
            blocks["BallJoints"].append(row)
        elif joint.kind == "hinge":
            row["position"] = _vector(joint.anchor)
            row["axis"] = _vector(joint.axis)
            blocks["HingeJoints"].append(row)
        elif joint.kind == "universal":
            assert joint.axis2 is not None
            row["position"] = _vector(joint.anchor)
            row["axis1"] = _vector(joint.axis)
            row["axis2"] = _vector(joint.axis2)
            blocks["UniversalJoints"].append(row)
        else:
            row["axis"] = _vector(joint.axis)
            blocks["SliderJoints"].append(row)
    scene: dict[str, Any] = {
        "Name": model.name,
        # OBJ coordinates read with every digit: a mesh's centroid is the body's centre of mass.
        "Simulation": {"timeStepSize": model.time_step, "gravitation": model.gravity, "objPrecision": "double"},
        "RigidBodies": entries,
    }
    scene.update({k: v for k, v in blocks.items() if v})
    scene["Validation"] = {
        "schema": 1,
        "description": f"{model.name}, imported from {model.path.name} by pbdval import",
        "notes": notes,
    }
    return ImportResult(scene, notes, bodies, body_of_link)


def import_model(model_path: str | Path, scene_path: str | Path | None = None, *, fixed_base: bool = False,
                 collisions: bool = True, mesh_folder: str | Path | None = None,
                 positions: dict[str, float] | None = None, collision_links: set[str] | None = None,
                 inertia_from_collision: bool = False) -> ImportResult:
    """Read a URDF (.urdf) or MJCF (.xml, .mjcf) model and build its scene; with `scene_path`, write
    it (and its collision meshes) there. Errors name the model's file."""
    path = Path(model_path)
    try:
        return _import(path, scene_path, fixed_base, collisions, mesh_folder, positions or {}, collision_links,
                       inertia_from_collision)
    except ImportModelError as error:
        if str(error).startswith(str(path)):
            raise
        raise ImportModelError(f"{path}: {error}") from None


def _import(path: Path, scene_path: str | Path | None, fixed_base: bool, collisions: bool,
            mesh_folder: str | Path | None, positions: dict[str, float], collision_links: set[str] | None,
            inertia_from_collision: bool) -> ImportResult:
    if not path.is_file():
        raise ImportModelError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".urdf":
        model = read_urdf(path, fixed_base, positions, inertia_from_collision)
    elif suffix in (".xml", ".mjcf"):
        if fixed_base or inertia_from_collision:
            raise ImportModelError(f"{path}: --fixed-base and --inertia-from-collision are for URDF (an MJCF "
                                   "body without a joint is welded; MuJoCo computes inertias from geoms itself)")
        model = read_mjcf(path, positions)
    else:
        raise ImportModelError(f"{path}: expected a URDF (.urdf) or MJCF (.xml) file")
    out = Path(scene_path) if scene_path is not None else path.with_suffix(".json")
    return _build_and_write(model, out, scene_path is not None, collisions, mesh_folder, collision_links)


def _build_and_write(model: Model, out: Path, write: bool, collisions: bool, mesh_folder: str | Path | None,
                     collision_links: set[str] | None) -> ImportResult:
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(mesh_folder) if mesh_folder is not None else (None if write else Path(scratch))
        result = build_scene(model, out, folder, collisions, collision_links)
        if write:
            _write_atomically(out, json.dumps(result.scene, indent=2) + "\n")
    return result


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="pbdval import", description=(
        "A URDF or MJCF robot as a scene in the seed's format (docs/models.md). What the seed "
        "cannot represent is printed and listed in the scene's Validation.notes."))
    parser.add_argument("model", help="MODEL.urdf or MODEL.xml (MJCF)")
    parser.add_argument("--out", help="the scene to write (default: MODEL.json beside the model)")
    parser.add_argument("--mesh-folder", help="where collision meshes go (default: SCENE.meshes/)")
    parser.add_argument("--fixed-base", action="store_true", help="URDF: the root link is static")
    parser.add_argument("--no-collision", action="store_true", help="write no collision shapes")
    parser.add_argument("--inertia-from-collision", action="store_true",
                        help="URDF: links take their collision shapes' centre of mass and inertia (pybullet's "
                             "loadURDF takes their inertia without URDF_USE_INERTIA_FROM_FILE)")
    parser.add_argument("--collision-links", metavar="A,B,...",
                        help="only these links keep their collision shapes (the others are noted)")
    parser.add_argument("--joint", action="append", default=[], metavar="NAME=VALUE",
                        help="start with this hinge (rad) or slider (m) moved from the model's zero "
                             "configuration (MJCF: from qpos0); repeatable")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    args = parser.parse_args(argv)
    positions: dict[str, float] = {}
    for item in args.joint:
        name, _, value = item.partition("=")
        try:
            positions[name] = float(value)
        except ValueError:
            parser.error(f"--joint {item}: expected NAME=VALUE with a number")
        if not name or not math.isfinite(positions[name]):
            parser.error(f"--joint {item}: expected NAME=VALUE with a finite number")
    out = Path(args.out) if args.out else Path(args.model).with_suffix(".json")
    if out.exists() and Path(args.model).exists() and os.path.samefile(out, args.model):
        parser.error(f"--out {out} is the model: it would overwrite its own input")
    try:
        result = import_model(args.model, out, fixed_base=args.fixed_base, collisions=not args.no_collision,
                              mesh_folder=args.mesh_folder, positions=positions,
                              collision_links=set(args.collision_links.split(",")) if args.collision_links else None,
                              inertia_from_collision=args.inertia_from_collision)
    except ImportModelError as error:
        print(f"pbdval import: {error}", file=sys.stderr)
        return 1
    if not args.quiet:
        dynamic = sum(1 for b in result.bodies if not b.static)
        print(f"{out}: {len(result.bodies)} bodies ({dynamic} moving), "
              f"{sum(len(v) for k, v in result.scene.items() if k.endswith('Joints'))} joints")
        for note in result.notes:
            print(f"  note: {note}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
