"""Reduced coordinates in pybullet (methods `pybullet.multibody.*`,
docs/external-engines.md#pybullet-in-reduced-coordinates).

The scene's joints form a graph over its bodies, all static bodies one node (the world). A
spanning forest of that graph (`plan_tree`) becomes pybullet multibodies (btMultiBody, what
loadURDF builds): each tree rooted at a static body is a fixed-base multibody whose base is that
body; a tree of dynamic bodies attached to nothing static has its first body as a free base.
Every tree joint becomes one link joint (revolute, prismatic, spherical) or an exact chain of
them through massless links (`link_chain`); a ball or hinge joint left out of the forest closes
its loop with createConstraint point-to-point rows. Bodies on no tree joint stay maximal-
coordinate btRigidBodies exactly as in the `pybullet.si` family (engine.py), so free flight and
contacts are the same; materials and contact settings are that family's.

What pybullet 3.2.7 does, measured (tests/python/test_pybullet_multibody.py):
- link masses may be 0: a link without mass and collision shape gets inertia 0, and the
  articulated-body algorithm stays regular as long as the bodies beyond it give every joint of
  the chain inertia (true of the chains here, but for a distance joint's rod: ROD_SPIN_INERTIA);
  massless links add no energy and no error;
- `changeDynamics(mass, localInertiaDiagonal)` must be a call of its own: with damping or
  maxJointVelocity in the same call the first step gives NaN;
- every revolute, prismatic and spherical joint gets a velocity motor holding it at rest
  (1-DoF: 'VELOCITY_CONTROL', spherical: a position motor): switched off with force 0;
- btMultiBody damps by default (linear and angular damping 0.04) and clamps joint speeds at
  100 rad/s (`maxJointVelocity`): both switched off;
- getLinkState's first two values are the link's inertial (principal) frame, exact to
  round-off; its link frame (values 5, 6) carries ~1e-7 errors and is not used; with
  computeLinkVelocity and computeForwardKinematics, its velocities are those of the centre of
  mass and the angular velocity, both in world, at the current state;
- a spherical joint's velocity is the child's angular velocity relative to its parent, in the
  child link's inertial frame;
- links are numbered depth first, whatever order createMultiBody got them in;
- a multibody's state crosses the client-server boundary in arrays of 128 position
  coordinates (MAX_COORDINATES), overrun silently beyond; a multibody has at most 127 links.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as pb

from pbdval import protocol as pp
from pbdval.external.pybullet import engine

#: method name → pybullet constraintSolverType. Not CONSTRAINT_SOLVER_LCP_PGS: with a multibody's
#: contacts pybullet 3.2.7's MLCP projected Gauss-Seidel turns the state to NaN (measured:
#: contact_jointed_bodies at 0.065 s, double_pendulum_boxes at 0.01 s).
SOLVERS = {
    "pybullet.multibody.si": pb.CONSTRAINT_SOLVER_LCP_SI,
    "pybullet.multibody.dantzig": pb.CONSTRAINT_SOLVER_LCP_DANTZIG,
}
#: Position coordinates of a multibody that pybullet 3.2.7 transfers (MAX_DEGREE_OF_FREEDOM of
#: its shared-memory state): 7 for the base and 1 per revolute or prismatic, 4 per spherical
#: joint. Beyond it the state it reads and writes overruns into the velocities (measured: 31
#: spherical joints read a base velocity of (0, 0, 1) and step to NaN). A tree that needs more is
#: cut at a ball or hinge joint, which closes the cut as a loop (as adapters/mujoco cuts deep
#: trees).
MAX_COORDINATES = 128
#: btMultiBody clamps joint speeds at 100 rad/s (m/s) by default; the scene's joints have none.
UNLIMITED_JOINT_SPEED = 1e30

HINGES = ("hinge", "target_angle_motor_hinge", "target_velocity_motor_hinge")
SLIDERS = ("slider", "damper", "target_position_motor_slider", "target_velocity_motor_slider")
#: Joint types that only link joints express here (no createConstraint closes their loop).
TREE_ONLY = (*SLIDERS, "universal", "ball_on_line", "distance", "target_angle_motor_hinge",
             "target_velocity_motor_hinge")
#: Joint types that can close a loop (point-to-point rows).
CLOSES_LOOPS = ("ball", "hinge")
#: Force elements, not joints: applied as forces before each step.
FORCES = ("rigid_body_spring",)
#: A distance joint's rod (a massless link between two spherical joints) may spin about its own
#: axis, a motion nothing resists or drives: with no inertia at all it makes the articulated-body
#: solve singular. It gets this fraction of m L^2 (the far body's mass, the rod's length) about
#: its axis and nothing else: no joint transmits a torque about the rod, so its spin stays zero
#: but for round-off (measured: 4e-8 rad/s after 5 s), adding neither energy nor force.
ROD_SPIN_INERTIA = 1e-9
UNSUPPORTED_JOINTS = {
    "rigid_body_particle_ball": "the multibody family has rigid bodies only",
    "stiff_rod": "pybullet has no stiff-rod (Cosserat) joint",
}


def is_multibody_method(name: str) -> bool:
    return name in SOLVERS


@dataclass
class TreePlan:
    """The spanning forest of the scene's joint graph (indices into scene.bodies / joints)."""

    parent: list[int]  # per body: parent body, -1 at a root or off every tree
    parent_joint: list[int]  # per body: the scene joint to its parent, or -1
    reversed: list[bool]  # per body: it is its parent joint's body1 (the joint seen backwards)
    roots: list[int] = field(default_factory=list)  # bodies at the root of a multibody
    order: list[int] = field(default_factory=list)  # bodies of multibodies, parents first
    roles: list[str] = field(default_factory=list)  # per joint: tree, loop, force, static, unsupported
    unsupported: list[str] = field(default_factory=list)

    def children(self, body: int) -> list[int]:
        return [b for b in self.order if self.parent[b] == body]

    def tree_of(self, root: int) -> list[int]:
        """The bodies of the multibody rooted at `root`, depth first (the root first), children
        in `order`: the order in which pybullet numbers the links of a multibody it creates
        (its URDF conversion walks the tree depth first, whatever order the links came in)."""
        members = [root]
        for child in self.children(root):
            members.extend(self.tree_of(child))
        return members


def plan_tree(scene: pp.ResolvedScene) -> TreePlan:
    """Kruskal with a priority, as the built-in MuJoCo adapter (adapters/mujoco/kinematic_tree.cpp):
    joints only link joints express first, then ball and hinge joints in scene order, so a loop
    is closed by a ball or hinge joint whenever one lies on it; all static bodies are one node."""
    n = len(scene.bodies)
    plan = TreePlan(parent=[-1] * n, parent_joint=[-1] * n, reversed=[False] * n,
                    roles=["unsupported"] * len(scene.joints))
    index = {b.id: b.index for b in scene.bodies}
    node = [0] * n
    next_node = 1
    for b in scene.bodies:
        if b.dynamic:
            node[b.index] = next_node
            next_node += 1
    root = list(range(next_node))

    def find(x: int) -> int:
        while root[x] != x:
            root[x] = root[root[x]]
            x = root[x]
        return x

    def both_static(j: pp.Joint) -> bool:
        return not scene.bodies[index[j.body1]].dynamic and not scene.bodies[index[j.body2]].dynamic  # type: ignore[index]

    for k, j in enumerate(scene.joints):
        if j.type in UNSUPPORTED_JOINTS:
            plan.unsupported.append(f"{j.json_path}: joint {j.type}: {UNSUPPORTED_JOINTS[j.type]}")
        elif j.type in FORCES:
            plan.roles[k] = "force"
        elif j.type not in (*TREE_ONLY, *CLOSES_LOOPS):
            plan.unsupported.append(f"{j.json_path}: joint {j.type}")
    for candidates in (TREE_ONLY, CLOSES_LOOPS):
        for k, j in enumerate(scene.joints):
            if j.type not in candidates:
                continue
            if both_static(j):
                plan.roles[k] = "static"
                continue
            node1, node2 = find(node[index[j.body1]]), find(node[index[j.body2]])  # type: ignore[index]
            if node1 != node2:
                root[max(node1, node2)] = min(node1, node2)  # the world (node 0) stays its own root
                plan.roles[k] = "tree"
            elif j.type in CLOSES_LOOPS:
                plan.roles[k] = "loop"
            else:
                plan.unsupported.append(
                    f"{j.json_path}: joint {j.type} closes a kinematic loop, and pybullet's "
                    "createConstraint closes loops here only with point-to-point rows (ball and "
                    "hinge joints)")
    _orient(scene, plan, index)
    return plan


def coordinates(chain: list[LinkJoint]) -> int:
    """The position coordinates of a chain's link joints in pybullet's state."""
    return sum(4 if e.kind == pb.JOINT_SPHERICAL else 1 for e in chain)


def _orient(scene: pp.ResolvedScene, plan: TreePlan, index: dict[int, int]) -> None:
    """Breadth-first from every static body, then from the first body of every remaining group
    of jointed dynamic bodies (a free base)."""
    incident: list[list[int]] = [[] for _ in scene.bodies]
    for k, j in enumerate(scene.joints):
        if plan.roles[k] == "tree":
            incident[index[j.body1]].append(k)  # type: ignore[index]
            incident[index[j.body2]].append(k)  # type: ignore[index]
    placed = [False] * len(scene.bodies)
    cut: list[int] = []  # bodies that start a multibody of their own (MAX_COORDINATES)

    def grow(start: int) -> None:
        queue = [start]
        placed[start] = True
        members = []
        used = 7  # the base's
        while queue:
            body = queue.pop(0)
            members.append(body)
            for k in incident[body]:
                j = scene.joints[k]
                child = index[j.body2] if index[j.body1] == body else index[j.body1]  # type: ignore[index]
                if placed[child]:
                    continue
                size = coordinates(link_chain(scene, j, child, child == index[j.body1]))  # type: ignore[index]
                if used + size > MAX_COORDINATES:
                    if j.type in CLOSES_LOOPS:
                        plan.roles[k] = "loop"
                        cut.append(child)
                    else:
                        plan.unsupported.append(
                            f"{j.json_path}: its multibody would need more than "
                            f"{MAX_COORDINATES} position coordinates (pybullet 3.2.7's state), "
                            "and only a ball or hinge joint can be cut into a loop closure")
                    continue
                used += size
                placed[child] = True
                plan.parent[child] = body
                plan.parent_joint[child] = k
                plan.reversed[child] = child == index[j.body1]  # type: ignore[index]
                queue.append(child)
        if len(members) > 1:
            plan.roots.append(start)
            plan.order.extend(members)

    for b in scene.bodies:
        if not b.dynamic:
            grow(b.index)
    for c in cut:  # (grow may append more cuts)
        if not placed[c]:
            grow(c)
    for b in scene.bodies:
        if not placed[b.index] and incident[b.index]:
            grow(b.index)


@dataclass(frozen=True)
class LinkJoint:
    """One link of a scene joint's chain: its joint and its frame's origin (world, t = 0)."""

    kind: int  # pb.JOINT_REVOLUTE, JOINT_PRISMATIC, JOINT_SPHERICAL
    axis: tuple[float, float, float]  # world, t = 0 (unused for spherical joints)
    origin: tuple[float, float, float]  # the joint's point: the link frame's origin
    name: str
    rod: tuple[float, float, float] | None = None  # a distance joint's rod (world, t = 0)


def link_chain(scene: pp.ResolvedScene, j: pp.Joint, child: int,
               reversed_: bool) -> list[LinkJoint]:
    """The link joints that express scene joint `j` with body `child` (index) on the far side;
    all but the last link are massless. Joint coordinates keep the scene's sign (body 2
    relative to body 1): seen from body 2 (reversed) axes are negated."""
    sign = -1.0 if reversed_ else 1.0
    zero = (0.0, 0.0, 0.0)
    if j.type in SLIDERS:
        axis = tuple(sign * a for a in j.axes["axis"].world)
        # Any origin gives the same translation; the child's centre of mass is the joint's point
        # (docs/metrics.md: slider-type joints anchor at body 2's initial centre of mass).
        return [LinkJoint(pb.JOINT_PRISMATIC, axis, scene.bodies[child].position, "prismatic")]  # type: ignore[arg-type]
    if j.type == "distance":
        # A massless rod from the parent's point to the child's, spherical at both ends: the
        # two points keep their distance, everything else is free (5 degrees of freedom).
        near, far = ("anchor2", "anchor1") if reversed_ else ("anchor1", "anchor2")
        start, end = j.points[near].world, j.points[far].world
        rod = (end[0] - start[0], end[1] - start[1], end[2] - start[2])
        return [LinkJoint(pb.JOINT_SPHERICAL, zero, start, "spherical", rod=rod),
                LinkJoint(pb.JOINT_SPHERICAL, zero, end, "spherical")]
    anchor = j.points["anchor"].world
    if j.type == "ball":
        return [LinkJoint(pb.JOINT_SPHERICAL, zero, anchor, "spherical")]
    if j.type in HINGES:
        axis = tuple(sign * a for a in j.axes["axis"].world)
        return [LinkJoint(pb.JOINT_REVOLUTE, axis, anchor, "revolute")]  # type: ignore[arg-type]
    if j.type == "universal":
        # axis1 is fixed in body 1, axis2 in body 2: the parent's axis turns the massless link.
        first, second = ("axis2", "axis1") if reversed_ else ("axis1", "axis2")
        return [LinkJoint(pb.JOINT_REVOLUTE, j.axes[first].world, anchor, f"revolute ({first})"),
                LinkJoint(pb.JOINT_REVOLUTE, j.axes[second].world, anchor, f"revolute ({second})")]
    if j.type == "ball_on_line":
        # The line is fixed in body 1: as the parent, the massless link slides along it and the
        # child turns about the link's origin; as the child, the link turns about the parent's
        # point and the child slides along its own line through that point.
        axis = j.axes["axis"].world
        ball = LinkJoint(pb.JOINT_SPHERICAL, zero, anchor, "spherical")
        slide = LinkJoint(pb.JOINT_PRISMATIC, axis, anchor, "prismatic")
        return [ball, slide] if reversed_ else [slide, ball]
    raise ValueError(f"{j.json_path}: joint {j.type} is no tree joint")


def rod_rotation(rod: Sequence[float], frame: pp.Quat) -> pp.Quat:
    """The rotation (w, x, y, z) of a link frame turned as `frame` onto a frame whose x axis
    runs along `rod` (world): the rod link's inertial frame, in which its one inertia is Ixx."""
    direction = _matrix(frame).T @ np.array(rod)
    direction /= np.linalg.norm(direction)
    half = np.array([1.0, 0.0, 0.0]) + direction  # the half-way vector: q = (1 + x.d, x cross d)
    if np.linalg.norm(half) < 1e-12:  # the rod runs along -x: half a turn about z
        return (0.0, 0.0, 0.0, 1.0)
    w = 1.0 + float(direction[0])
    axis = np.cross([1.0, 0.0, 0.0], direction)
    return pp.quat_normalized((w, float(axis[0]), float(axis[1]), float(axis[2])))


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    missing: list[str] = []
    if scene.method.name not in SOLVERS:
        missing.append(f"method {scene.method.name}")
    for b in scene.bodies:
        if b.shape.type not in engine.SUPPORTED_SHAPES:
            missing.append(f"{b.json_path}: shape {b.shape.type}")
        elif b.shape.inverted:
            missing.append(f"{b.json_path}: inverted shape (invertSDF)")
        elif b.shape.type in ("sdf", "torus") and not b.geometry_file:
            missing.append(f"{b.json_path}: shape {b.shape.type} without a geometry file")
    for kind, models in (("TriangleModels", scene.triangle_models), ("TetModels", scene.tet_models)):
        missing.extend(f"{m.json_path}: the multibody family has rigid bodies only (cloth and "
                       "solids run in pybullet.si)" for m in models)
    if scene.line_models or scene.fluid_models:
        missing.append("rods and fluids: not mapped to pybullet")
    missing.extend(plan_tree(scene).unsupported)
    for which in ("friction", "restitution"):
        if engine.material_factors(scene, which) is None:
            missing.append(f"contact {which}: the pairs' values are not products of per-body "
                           f"values (pybullet multiplies the bodies' {which} coefficients)")
    return missing


def _matrix(q: Sequence[float]) -> np.ndarray:
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@dataclass
class _Link:
    """Where a scene body lives in pybullet: a body id and a link index (-1: base or maximal)."""

    body: int
    link: int


class MultibodyRun(engine.PybulletRun):
    """A scene in reduced coordinates: the `pybullet.si` world, bodies and contacts, with the
    joints' trees as multibodies (module docstring)."""

    def __init__(self, scene: pp.ResolvedScene) -> None:
        self.plan = plan_tree(scene)
        self.handles: list[_Link] = []
        self.motors: list[tuple[pp.Joint, _Link]] = []
        self.dampers: list[tuple[pp.Joint, _Link]] = []
        self.springs: list[pp.Joint] = []
        self.step_count = 0
        super().__init__(scene)
        self.settings["bodies"] = (
            "reduced coordinates: each tree of joints a btMultiBody (createMultiBody), other "
            "bodies maximal-coordinate btRigidBodies")

    def _solver(self, method: str) -> int:
        return int(SOLVERS[method])

    # --- bodies ---------------------------------------------------------------------------

    def _bodies(self) -> None:
        scene = self.scene
        friction = engine.material_factors(scene, "friction")
        restitution = engine.material_factors(scene, "restitution")
        assert friction is not None and restitution is not None  # checked by unsupported_features
        self.handles = [_Link(-1, -1) for _ in scene.bodies]
        in_tree = set(self.plan.order)
        for b in scene.bodies:
            if b.index not in in_tree:
                self.handles[b.index] = _Link(self._maximal_body(b), -1)
        for r in self.plan.roots:
            self._multibody(r)
        for b in scene.bodies:
            h = self.handles[b.index]
            self._dynamics(b, h, friction[b.index], restitution[b.index])
        # Bodies in trees: pose and velocities set once every multibody exists.
        for r in self.plan.roots:
            self._initial_velocities(r)

    def _maximal_body(self, b: pp.Body) -> int:
        shape, note = engine.collision_shape(self.client, b)
        if note:
            self.notes.append(note)
        return int(pb.createMultiBody(
            baseMass=b.mass if b.dynamic else 0.0, baseCollisionShapeIndex=shape,
            basePosition=list(b.scene_origin), baseOrientation=engine.xyzw(b.rotation),
            baseInertialFramePosition=list(b.principal_com),
            baseInertialFrameOrientation=engine.xyzw(b.principal_rotation),
            useMaximalCoordinates=True, physicsClientId=self.client))

    def _multibody(self, root: int) -> None:
        scene, c = self.scene, self.client
        base = scene.bodies[root]
        shape, note = engine.collision_shape(c, base)
        if note:
            self.notes.append(note)
        # A link frame per body: at its joint's point, turned as the body's scene frame; the
        # base frame is the scene frame. (origin, rotation w x y z) in world at t = 0.
        frames: dict[int, tuple[np.ndarray, pp.Quat]] = {
            root: (np.array(base.scene_origin), base.rotation)}
        link_of: dict[int, int] = {root: -1}  # body → its (last) link index
        links: dict[str, list[Any]] = {k: [] for k in (
            "linkMasses", "linkCollisionShapeIndices", "linkVisualShapeIndices", "linkPositions",
            "linkOrientations", "linkInertialFramePositions", "linkInertialFrameOrientations",
            "linkParentIndices", "linkJointTypes", "linkJointAxis")}
        chains: list[tuple[int, pp.Joint, list[LinkJoint], int]] = []  # body, joint, chain, first link
        rods: list[tuple[int, float]] = []  # rod link, its inertia about its axis
        for b_index in self.plan.tree_of(root)[1:]:
            body = scene.bodies[b_index]
            joint = scene.joints[self.plan.parent_joint[b_index]]
            chain = link_chain(scene, joint, b_index, self.plan.reversed[b_index])
            parent = self.plan.parent[b_index]
            parent_origin, parent_rotation = frames[parent]
            parent_link = link_of[parent]
            rotation = body.rotation
            to_local = _matrix(rotation).T
            chains.append((b_index, joint, chain, len(links["linkMasses"])))
            for k, element in enumerate(chain):
                last = k == len(chain) - 1
                origin = np.array(element.origin)
                links["linkPositions"].append(
                    list(_matrix(parent_rotation).T @ (origin - parent_origin)))
                links["linkOrientations"].append(
                    engine.xyzw(pp.quat_multiply(pp.quat_conjugate(parent_rotation), rotation)))
                links["linkParentIndices"].append(parent_link + 1)  # 0: the base
                links["linkJointTypes"].append(element.kind)
                links["linkJointAxis"].append(list(to_local @ np.array(element.axis)))
                links["linkVisualShapeIndices"].append(-1)
                if last:
                    shape_b, note_b = engine.collision_shape(
                        c, body, frame_position=to_local @ (np.array(body.scene_origin) - origin))
                    if note_b:
                        self.notes.append(note_b)
                    links["linkMasses"].append(body.mass)
                    links["linkCollisionShapeIndices"].append(shape_b)
                    links["linkInertialFramePositions"].append(
                        list(to_local @ (np.array(body.position) - origin)))
                    links["linkInertialFrameOrientations"].append(engine.xyzw(body.principal_rotation))
                else:
                    links["linkMasses"].append(0.0)
                    links["linkCollisionShapeIndices"].append(-1)
                    links["linkInertialFramePositions"].append([0.0, 0.0, 0.0])
                    links["linkInertialFrameOrientations"].append(
                        engine.xyzw(rod_rotation(element.rod, rotation)) if element.rod
                        else [0.0, 0.0, 0.0, 1.0])
                    if element.rod:
                        length_squared = float(np.dot(element.rod, element.rod))
                        spin_inertia = ROD_SPIN_INERTIA * body.mass * length_squared
                        rods.append((len(links["linkMasses"]) - 1, spin_inertia))
                        self.settings[f"{joint.json_path}.rodSpinInertia"] = spin_inertia
                parent_link = len(links["linkMasses"]) - 1
                parent_origin, parent_rotation = origin, rotation
            frames[b_index] = (parent_origin, rotation)
            link_of[b_index] = parent_link
        flags = pb.URDF_USE_SELF_COLLISION | pb.URDF_USE_SELF_COLLISION_INCLUDE_PARENT
        mb = int(pb.createMultiBody(
            baseMass=base.mass if base.dynamic else 0.0, baseCollisionShapeIndex=shape,
            basePosition=list(base.scene_origin), baseOrientation=engine.xyzw(base.rotation),
            baseInertialFramePosition=list(base.principal_com),
            baseInertialFrameOrientation=engine.xyzw(base.principal_rotation),
            flags=flags, physicsClientId=c, **links))
        count = len(links["linkMasses"])
        if pb.getNumJoints(mb, physicsClientId=c) != count:
            raise RuntimeError(f"{base.json_path}: pybullet built "
                               f"{pb.getNumJoints(mb, physicsClientId=c)} of {count} links")
        # pybullet names the k-th link it was given "link{k+1}" and numbers links depth first:
        # the links were given depth first, and the names check that the numbers are theirs.
        for index in range(count):
            name = pb.getJointInfo(mb, index, physicsClientId=c)[12].decode()
            if name != f"link{index + 1}":
                raise RuntimeError(f"{base.json_path}: pybullet numbered link {name} {index}")
        for b_index, link in link_of.items():
            self.handles[b_index] = _Link(mb, link)
        for link in range(count):
            # Massless links keep mass 0 and inertia 0 (pybullet's for a link without shape).
            pb.changeDynamics(mb, link, linearDamping=0.0, angularDamping=0.0, jointDamping=0.0,
                              maxJointVelocity=UNLIMITED_JOINT_SPEED, physicsClientId=c)
            if links["linkJointTypes"][link] == pb.JOINT_SPHERICAL:
                pb.setJointMotorControlMultiDof(
                    mb, link, pb.POSITION_CONTROL, targetPosition=[0, 0, 0, 1],
                    targetVelocity=[0, 0, 0], positionGain=0, velocityGain=0, force=[0, 0, 0],
                    physicsClientId=c)
            else:
                pb.setJointMotorControl2(mb, link, pb.VELOCITY_CONTROL, force=0,
                                         physicsClientId=c)
        pb.changeDynamics(mb, -1, linearDamping=0.0, angularDamping=0.0, physicsClientId=c)
        for link, spin_inertia in rods:
            pb.changeDynamics(mb, link, mass=0.0, localInertiaDiagonal=[spin_inertia, 0.0, 0.0],
                              physicsClientId=c)
        for b_index, joint, chain, first in chains:
            handle = _Link(mb, first + len(chain) - 1)
            if joint.type.startswith("target_"):
                self.motors.append((joint, handle))
            elif joint.type == "damper":
                self.dampers.append((joint, handle))
            self.settings[f"{joint.json_path}.links"] = " + ".join(
                e.name + ("" if i == len(chain) - 1 else " (massless link)")
                for i, e in enumerate(chain))
        self.settings[f"{base.json_path}.multibody"] = (
            f"{'fixed' if not base.dynamic else 'free'} base, {count} links")

    def _dynamics(self, b: pp.Body, h: _Link, friction: float, restitution: float) -> None:
        c = self.client
        if b.dynamic:
            # Mass and inertia in a call of their own: together with damping or
            # maxJointVelocity, pybullet 3.2.7 gives NaN at the first step.
            pb.changeDynamics(h.body, h.link, mass=b.mass,
                              localInertiaDiagonal=list(b.principal_inertia), physicsClientId=c)
        pb.changeDynamics(
            h.body, h.link, lateralFriction=friction, restitution=restitution,
            rollingFriction=0.0, spinningFriction=0.0, contactProcessingThreshold=0.0,
            activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING, physicsClientId=c)
        if b.index not in self.plan.order:  # a maximal-coordinate body
            pb.changeDynamics(h.body, -1, linearDamping=0.0, angularDamping=0.0,
                              physicsClientId=c)
            # As engine.PybulletRun: the world inertia of a maximal body follows the new one.
            position, orientation = pb.getBasePositionAndOrientation(h.body, physicsClientId=c)
            pb.resetBasePositionAndOrientation(h.body, position, orientation, physicsClientId=c)
            if b.dynamic:
                pb.resetBaseVelocity(h.body, list(b.velocity), list(b.angular_velocity),
                                     physicsClientId=c)
        if b.shape.type == "none":
            pb.setCollisionFilterGroupMask(h.body, h.link, 0, 0, physicsClientId=c)

    def _initial_velocities(self, root: int) -> None:
        """The scene's velocities projected onto the multibody's joints in the kinetic-energy
        norm: the joint velocities u minimising sum over bodies of m |v - J_v u|^2 +
        (w - J_w u)' I (w - J_w u), i.e. (J' M J) u = J' M V, which keeps the generalised
        momenta (about a pivot: its angular momentum) and gives velocities the joints allow
        unchanged (as the MuJoCo adapters do, docs/parity-mujoco.md)."""
        scene, c = self.scene, self.client
        members = self.plan.tree_of(root)
        slot = {b: i for i, b in enumerate(members)}
        centre = {b: np.array(scene.bodies[b].position) for b in members}
        columns: list[np.ndarray] = []
        # (link index or -1 for the base, element kind, the world basis of its velocity)
        owners: list[tuple[int, int, np.ndarray]] = []

        def add(bodies: list[int], angular: np.ndarray | None, point: np.ndarray | None,
                linear: np.ndarray | None) -> None:
            column = np.zeros(6 * len(members))
            for b in bodies:
                i = slot[b]
                if angular is not None:
                    column[6 * i + 3:6 * i + 6] += angular
                    assert point is not None
                    column[6 * i:6 * i + 3] += np.cross(angular, centre[b] - point)
                if linear is not None:
                    column[6 * i:6 * i + 3] += linear
            columns.append(column)

        base = scene.bodies[root]
        if base.dynamic:
            for e in np.eye(3):
                add(members, None, None, e)
            for e in np.eye(3):
                add(members, e, centre[root], None)
        link = 0
        for b_index in members[1:]:
            body = scene.bodies[b_index]
            subtree = self.plan.tree_of(b_index)
            joint = scene.joints[self.plan.parent_joint[b_index]]
            chain = link_chain(scene, joint, b_index, self.plan.reversed[b_index])
            for element in chain:
                x, axis = np.array(element.origin), np.array(element.axis)
                if element.kind == pb.JOINT_REVOLUTE:
                    add(subtree, axis, x, None)
                    owners.append((link, element.kind, axis[:, None]))
                elif element.kind == pb.JOINT_PRISMATIC:
                    add(subtree, None, None, axis)
                    owners.append((link, element.kind, axis[:, None]))
                else:
                    # btMultiBody's spherical joint velocity is the angular velocity relative to
                    # the parent link in the child link's inertial frame: the body's principal
                    # frame for its own link, turned as its scene frame for a massless one.
                    inertial = (body.world_principal_rotation if element is chain[-1]
                                else pp.quat_multiply(body.rotation,
                                                      rod_rotation(element.rod, body.rotation))
                                if element.rod
                                else body.rotation)
                    frame = _matrix(inertial)
                    for e in frame.T:
                        add(subtree, e, x, None)
                    owners.append((link, element.kind, frame))
                link += 1
        jacobian = np.array(columns).T
        weights = np.zeros((6 * len(members), 6 * len(members)))
        velocities = np.zeros(6 * len(members))
        for b in members:
            body, i = scene.bodies[b], slot[b]
            if not body.dynamic:
                continue
            rotation = _matrix(body.world_principal_rotation)
            weights[6 * i:6 * i + 3, 6 * i:6 * i + 3] = body.mass * np.eye(3)
            weights[6 * i + 3:6 * i + 6, 6 * i + 3:6 * i + 6] = (
                rotation @ np.diag(body.principal_inertia) @ rotation.T)
            velocities[6 * i:6 * i + 3] = body.velocity
            velocities[6 * i + 3:6 * i + 6] = body.angular_velocity
        u = np.linalg.solve(jacobian.T @ weights @ jacobian, jacobian.T @ weights @ velocities)
        mb = self.handles[root].body
        offset = 0
        if base.dynamic:
            pb.resetBaseVelocity(mb, list(u[0:3]), list(u[3:6]), physicsClientId=c)
            offset = 6
        for link, kind, basis in owners:
            count = basis.shape[1]
            rates = u[offset:offset + count]
            offset += count
            if kind == pb.JOINT_SPHERICAL:
                pb.resetJointStateMultiDof(mb, link, [0, 0, 0, 1], list(rates), physicsClientId=c)
            else:
                pb.resetJointState(mb, link, 0.0, float(rates[0]), physicsClientId=c)
        fitted = jacobian @ u
        moved = max(float(np.max(np.abs(fitted - velocities))), 0.0)
        self.settings[f"{base.json_path}.initialVelocities"] = (
            "projected onto the joints (kinetic-energy norm); largest change of a body's "
            f"velocity component {moved:.3g}")

    # --- joints ---------------------------------------------------------------------------

    def _joints(self) -> None:
        scene = self.scene
        for k, j in enumerate(scene.joints):
            role = self.plan.roles[k]
            if role == "loop":
                if j.type == "ball":
                    self._point_to_point(j, (0.0, 0.0, 0.0))
                else:
                    a = j.axes["axis"].world
                    bodies = [scene.body_by_id(j.body1), scene.body_by_id(j.body2)]  # type: ignore[arg-type]
                    half = engine.hinge_half_length(bodies, j.points["anchor"].world, a)
                    self.settings[f"{j.json_path}.pointSeparation"] = 2 * half
                    for sign in (-1.0, 1.0):
                        self._point_to_point(j, tuple(sign * half * x for x in a))  # type: ignore[arg-type]
                self.settings[f"{j.json_path}.links"] = "loop closure (createConstraint point-to-point)"
            elif role == "force":
                self.springs.append(j)
                self.settings[f"{j.json_path}.force"] = (
                    "explicit: -k (l - l0) along the connectors' line, applyExternalForce at both "
                    "connectors before each step (as the built-in bullet engine)")
        self._jointed_bodies_collide()

    def _point_to_point(self, joint: pp.Joint, offset: tuple[float, float, float]) -> None:
        b1, b2, local1, local2 = engine.point_in_principal_frames(self.scene, joint, offset)
        h1, h2 = self.handles[b1.index], self.handles[b2.index]
        cid = pb.createConstraint(h1.body, h1.link, h2.body, h2.link, pb.JOINT_POINT2POINT,
                                  [0, 0, 0], local1, local2, physicsClientId=self.client)
        pb.changeConstraint(cid, maxForce=engine.UNLIMITED_FORCE, physicsClientId=self.client)

    def _jointed_bodies_collide(self) -> None:
        """Jointed bodies collide, as in the seed: links of one multibody through its
        self-collision flags (parents included), others as any two bodies."""
        pairs = {p.bodies for p in self.scene.contact_pairs if self.scene.jointed(*p.bodies)}
        for id_a, id_b in sorted(pairs):
            a = self.handles[self.scene.body_by_id(id_a).index]
            b = self.handles[self.scene.body_by_id(id_b).index]
            if a.body != b.body:
                pb.setCollisionFilterPair(a.body, b.body, a.link, b.link, enableCollision=1,
                                          physicsClientId=self.client)
        self.settings["jointedBodiesCollide"] = (
            f"yes (as in the seed): {len(pairs)} pairs of bodies connected by a joint "
            "(links: URDF_USE_SELF_COLLISION | URDF_USE_SELF_COLLISION_INCLUDE_PARENT)")

    # --- stepping -------------------------------------------------------------------------

    def _before_step(self) -> None:
        """Motor set points, damper springs and spring forces for the coming step."""
        c = self.client
        h = self.scene.time_step_size
        t_next = (self.step_count + 1) * h
        for joint, link in self.motors:
            assert joint.target is not None
            target = joint.target.value_at(t_next)
            if joint.type == "target_angle_motor_hinge":
                angle = pb.getJointState(link.body, link.link, physicsClientId=c)[0]
                error = math.remainder(target - angle, 2 * math.pi)  # the shortest way round
                velocity = error / h
            elif joint.type == "target_position_motor_slider":
                velocity = (target - pb.getJointState(link.body, link.link, physicsClientId=c)[0]) / h
            else:
                velocity = target
            pb.setJointMotorControl2(link.body, link.link, pb.VELOCITY_CONTROL,
                                     targetVelocity=velocity, velocityGain=1.0,
                                     force=engine.UNLIMITED_FORCE, physicsClientId=c)
        for joint, link in self.dampers:
            extension = pb.getJointState(link.body, link.link, physicsClientId=c)[0]
            pb.setJointMotorControl2(link.body, link.link, pb.TORQUE_CONTROL,
                                     force=-float(joint.stiffness or 0.0) * extension,
                                     physicsClientId=c)
        for joint in self.springs:
            self._spring_force(joint)

    def _pose(self, b: pp.Body) -> tuple[np.ndarray, np.ndarray]:
        """Centre of mass and principal rotation matrix of body b now."""
        h = self.handles[b.index]
        if h.link < 0:
            x, q = pb.getBasePositionAndOrientation(h.body, physicsClientId=self.client)
        else:
            s = pb.getLinkState(h.body, h.link, computeForwardKinematics=1,
                                physicsClientId=self.client)
            x, q = s[0], s[1]
        return np.array(x), _matrix(engine.wxyz(q))

    def _spring_force(self, j: pp.Joint) -> None:
        connectors = []
        for key, body_id in (("anchor1", j.body1), ("anchor2", j.body2)):
            b = self.scene.body_by_id(body_id)  # type: ignore[arg-type]
            coordinates = j.points[key].body1 if key == "anchor1" else j.points[key].body2
            assert coordinates is not None
            x, rotation = self._pose(b)
            connectors.append((b, x + rotation @ np.array(coordinates.principal)))
        (b1, p1), (b2, p2) = connectors
        d = p2 - p1
        length = float(np.linalg.norm(d))
        rest = float(j.rest_length or 0.0)
        force = -float(j.stiffness or 0.0) * (length - rest) * d / length if length > 0 else np.zeros(3)
        for b, p, f in ((b2, p2, force), (b1, p1, -force)):
            if b.dynamic:
                h = self.handles[b.index]
                pb.applyExternalForce(h.body, h.link, list(f), list(p), pb.WORLD_FRAME,
                                      physicsClientId=self.client)

    def _step(self) -> None:
        self._before_step()
        pb.stepSimulation(physicsClientId=self.client)
        self.step_count += 1

    def _prepare_state_reads(self) -> None:
        """`states`' array and its reads, once the multibodies are built: the links of each
        multibody read in one getLinkStates call (in scene order), and for each body (row) the
        index of its link's state among those calls' results, or -1 for a base or a
        maximal-coordinate body (read by getBasePositionAndOrientation and getBaseVelocity)."""
        super()._prepare_state_reads()
        links: dict[int, list[int]] = {}
        for h in self.handles:
            if h.link >= 0:
                links.setdefault(h.body, []).append(h.link)
        self._link_reads: list[tuple[int, list[int]]] = list(links.items())
        slot: dict[tuple[int, int], int] = {}
        for body, indices in self._link_reads:
            for link in indices:
                slot[(body, link)] = len(slot)
        self._body_reads: list[tuple[int, int]] = []
        for b in self.scene.bodies:
            h = self.handles[b.index]
            self._body_reads.append((h.body, slot[(h.body, h.link)] if h.link >= 0 else -1))

    def states(self, time: float) -> np.ndarray:
        """Every body's state as pybullet reports it (the principal frame, pybullet's
        quaternion order: engine.PybulletRun.states), a row per body of one array filled again
        at every sample (simulate copies it before the next call)."""
        c = self.client
        # Every multibody's links in one call (getLinkStates): the inertial (principal) frame
        # and its velocities, world (module docstring).
        link_states: list[Any] = []
        for body, indices in self._link_reads:
            link_states += pb.getLinkStates(body, indices, computeLinkVelocity=1,
                                            computeForwardKinematics=1, physicsClientId=c)
        read = self._read
        get_pose = pb.getBasePositionAndOrientation
        get_velocity = pb.getBaseVelocity
        for row, (body, slot) in enumerate(self._body_reads):
            if slot < 0:
                position, orientation = get_pose(body, c)
                velocity, angular = get_velocity(body, c)
                read[row] = position + orientation + velocity + angular
            else:
                s = link_states[slot]
                read[row] = s[0] + s[1] + s[6] + s[7]
        return read

    def run(self, out_dir: Path) -> pp.Status:
        # Without motors, dampers or springs nothing happens before a step: the step is
        # pybullet's function itself, its client bound (no Python frame per step).
        driven = self.motors or self.dampers or self.springs
        step = self._step if driven else functools.partial(pb.stepSimulation, self.client)
        status = pp.simulate(self.scene, out_dir, step, self.states,
                             finish_states=self.finish_states)
        status.engine_version = engine.engine_version()
        status.effective_settings = self.settings
        status.initial_velocities_projected = bool(self.plan.roots)
        return status


def run(scene: pp.ResolvedScene, out: Path) -> pp.Status:
    return MultibodyRun(scene).run(out)
