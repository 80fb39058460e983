"""Drake's MultibodyPlant as an external engine (protocol 1, docs/external-engines.md;
docs/engine-drake.md).

    .venv/bin/python -m pbdval.external.drake --scene RESOLVED.json --out OUTDIR

The scene's rigid bodies become RigidBodies whose body frame is the principal frame (the centre
of mass on the principal axes), so their spatial inertia is diagonal. The joints become the
edges of a spanning tree grown from the static bodies (welded to the world) and, for what they
do not reach, from a floating root (Drake's quaternion floating joint): hinge → RevoluteJoint,
slider → PrismaticJoint, ball → BallRpyJoint, universal → UniversalJoint, damper →
PrismaticJoint + PrismaticSpring; a rigid-body spring is a LinearSpringDamper force element.
Every joint's two frames coincide at t = 0, so zero joint coordinates are the scene's initial
pose; the scene's velocities are projected onto the tree's generalised velocities. A joint that
would close a loop is refused (a tree cannot hold it).

Contact is Drake's compliant point contact between the shapes (sphere, box, cylinder), with
per-geometry friction chosen so that Drake's combination 2ab/(a+b) is each pair's friction, and
stiffness and dissipation estimated by Drake from a penetration allowance. Bodies joined by a
joint collide, as in the seed (Drake's adjacent-body filter is switched off).

Methods (catalogue.py): drake.sap and drake.tamsi, the discrete plant at the scene's step with
that contact solver; drake.rk3, drake.radau, drake.implicit_euler, the continuous plant under an
error-controlled integrator at a target accuracy (the converged reference at 1e-10).

Only the pydrake modules needed are imported (not pydrake.all, which imports matplotlib).
"""

from __future__ import annotations

import importlib.metadata
import math
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.geometry import AddContactMaterial, Box, Cylinder, ProximityProperties, Shape, Sphere
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.plant import (
    AddMultibodyPlantSceneGraph,
    CoulombFriction,
    DiscreteContactApproximation,
    MultibodyPlant,
)
from pydrake.multibody.tree import (
    BallRpyJoint,
    FixedOffsetFrame,
    Frame,
    JacobianWrtVariable,
    LinearSpringDamper,
    PrismaticJoint,
    PrismaticSpring,
    RevoluteJoint,
    RigidBody,
    RotationalInertia,
    SpatialInertia,
    UniversalJoint,
)
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator
from pydrake.systems.framework import Context, DiagramBuilder

from pbdval import protocol as pp
from pbdval.external.drake import catalogue
from pbdval.external.drake.catalogue import CONTINUOUS, DEFAULT_METHOD, DISCRETE, ENGINE
from pbdval.external.drake.features import FORCE_ELEMENT_JOINTS, JOINTS, SHAPES

#: Two vectors count as perpendicular (a universal joint's axes) below this |cos|: the seed's
#: axes are given perpendicular; this is 1e3 times double rounding of unit vectors.
PERPENDICULAR_TOLERANCE = 1e-12 * 1e3
#: The plant's pose at t = 0 must be the scene's to this many metres (or radians): both are
#: the same numbers composed in another order, a few roundings of double apart.
INITIAL_POSE_TOLERANCE = 1e-9
#: A velocity of the scene that the joints cannot hold is recorded beyond this (relative to
#: 1 + |v| + |w|), the threshold of the MuJoCo engines' projection.
VELOCITY_MISMATCH_TOLERANCE = 1e-9
#: The per-geometry friction solution must reproduce every pair's friction to this relative
#: error (a least-squares solve of a consistent system: rounding only).
FRICTION_TOLERANCE = 1e-9


def engine_version() -> str:
    return f"drake {importlib.metadata.version('drake')} (pydrake, MultibodyPlant)"


def method_name(scene: pp.ResolvedScene) -> str | None:
    """The method's last name part (sap, tamsi, rk3, radau, implicit_euler), or None."""
    name = scene.method.name or DEFAULT_METHOD
    prefix = f"{ENGINE}."
    if not name.startswith(prefix) or name[len(prefix):] not in (*DISCRETE, *CONTINUOUS):
        return None
    return name[len(prefix):]


# ---------------------------------------------------------------------------------------------
# What the engine can build: the tree and the friction values


@dataclass(frozen=True)
class TreeEdge:
    joint: int  # index into scene.joints
    parent: int | None  # scene body id; None: the world (a static body)
    child: int  # scene body id


@dataclass(frozen=True)
class Tree:
    edges: tuple[TreeEdge, ...]
    floating_roots: tuple[int, ...]  # scene body ids, in scene order
    closing: tuple[int, ...]  # joints (indices) that would close a loop


def spanning_tree(scene: pp.ResolvedScene) -> Tree:
    """The tree the plant is built as: breadth first from the static bodies (the world), then
    from the first unreached dynamic body (a floating root), joints in scene order. A tree
    joint between two bodies reached already closes a loop."""
    static = {b.id for b in scene.bodies if not b.dynamic}
    tree_joints = [i for i, j in enumerate(scene.joints)
                   if j.type in JOINTS and j.type not in FORCE_ELEMENT_JOINTS
                   and j.body1 is not None and j.body2 is not None]
    reached: set[int] = set(static)
    used: set[int] = set()
    edges: list[TreeEdge] = []
    roots: list[int] = []

    def grow(start: list[int]) -> None:
        queue = deque(start)
        while queue:
            body = queue.popleft()
            for i in tree_joints:
                j = scene.joints[i]
                if i in used or body not in (j.body1, j.body2):
                    continue
                other = j.body2 if j.body1 == body else j.body1
                assert other is not None
                if other in reached:
                    continue
                used.add(i)
                reached.add(other)
                edges.append(TreeEdge(i, None if body in static else body, other))
                queue.append(other)

    grow([b.id for b in scene.bodies if not b.dynamic])
    for b in scene.bodies:
        if b.id not in reached:
            roots.append(b.id)
            reached.add(b.id)
            grow([b.id])
    closing = tuple(i for i in tree_joints if i not in used)
    return Tree(tuple(edges), tuple(roots), closing)


def geometry_friction(scene: pp.ResolvedScene) -> dict[int, float] | None:
    """Per-body friction values whose combination by Drake, 2ab/(a+b), is every contact pair's
    friction, or None when there are none. 1/a + 1/b = 2/mu is linear in the reciprocals,
    solved by least squares (the minimum-norm solution: equal values for a lone pair); bodies
    whose pairs all have no friction get 0. Bodies in no pair get 1 (never used)."""
    friction: dict[int, float] = {b.id: 1.0 for b in scene.bodies}
    zero = {b.id for b in scene.bodies
            if any(b.id in p.bodies for p in scene.contact_pairs)
            and all(p.friction == 0 for p in scene.contact_pairs if b.id in p.bodies)}
    positive = [p for p in scene.contact_pairs if p.friction != 0]
    if any(p.friction == 0 and not (set(p.bodies) & zero) for p in scene.contact_pairs):
        return None
    if any(set(p.bodies) & zero or p.friction < 0 for p in positive):
        return None
    for body_id in zero:
        friction[body_id] = 0.0
    if positive:
        ids = sorted({i for p in positive for i in p.bodies})
        column = {body_id: k for k, body_id in enumerate(ids)}
        a = np.zeros((len(positive), len(ids)))
        rhs = np.array([2.0 / p.friction for p in positive])
        for row, p in enumerate(positive):
            a[row, column[p.bodies[0]]] += 1.0
            a[row, column[p.bodies[1]]] += 1.0
        reciprocal = np.linalg.lstsq(a, rhs, rcond=None)[0]
        if (reciprocal <= 0).any() or np.abs(a @ reciprocal - rhs).max() > FRICTION_TOLERANCE * rhs.max():
            return None
        for body_id, k in column.items():
            friction[body_id] = float(1.0 / reciprocal[k])
    return friction


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    """What this engine cannot run in the scene, each naming its JSON path; [] when it runs.
    The same verdict as the catalogue's feature table (features.py), plus what only the
    engine sees: loop closures and pair friction no per-geometry values combine to."""
    if method_name(scene) is None:
        return [f"method {scene.method.name}"]
    missing: list[str] = []
    for b in scene.bodies:
        if b.shape.type not in SHAPES:
            missing.append(f"{b.json_path}: shape {b.shape.type} (Drake's shapes here: "
                           f"{', '.join(SHAPES)})")
        elif b.shape.inverted:
            missing.append(f"{b.json_path}: inverted shape (invertSDF)")
    for j in scene.joints:
        if j.type not in JOINTS:
            missing.append(f"{j.json_path}: joint {j.type} (mapped: {', '.join(JOINTS)})")
    for i in spanning_tree(scene).closing:
        j = scene.joints[i]
        missing.append(f"{j.json_path}: the {j.type} joint closes a kinematic loop "
                       "(MultibodyPlant is a tree)")
    if scene.particles or scene.triangle_models or scene.tet_models:
        missing.append("particles (TriangleModels, TetModels): no particles in this engine")
    if scene.line_models:
        missing.append("LineModels: no rods in this engine")
    if scene.fluid_models:
        missing.append("FluidModels: no fluids in this engine")
    if geometry_friction(scene) is None:
        missing.append("contact friction: the pairs' values are not the combination 2ab/(a+b) of "
                       "per-geometry values (Drake combines the geometries' friction so)")
    return missing


# ---------------------------------------------------------------------------------------------
# Building the plant


def _rotation(q: pp.FloatVector) -> RotationMatrix:
    w, x, y, z = pp.quat_normalized(q)
    return RotationMatrix(Quaternion(w, x, y, z))


def _frame_with_axes(x_axis: np.ndarray, y_axis: np.ndarray | None = None) -> RotationMatrix:
    """A rotation whose x axis is `x_axis` (and y axis `y_axis` when given, perpendicular)."""
    x = x_axis / np.linalg.norm(x_axis)
    if y_axis is None:
        return RotationMatrix.MakeFromOneVector(x, 0)
    y = y_axis / np.linalg.norm(y_axis)
    return RotationMatrix(np.column_stack([x, y, np.cross(x, y)]))


def _ball_frame(up: np.ndarray, arm: np.ndarray) -> RotationMatrix:
    """The frame of a ball joint (BallRpyJoint, R = Rz(yaw) Ry(pitch) Rx(roll)): its
    coordinates are singular where the child's x axis meets the parent's ±z (pitch ±π/2). With
    z up and x horizontal across the arm (anchor → the child's centre of mass), the swing in
    the vertical plane of the arm is a roll about x, which never nears that: a chain or pendulum
    released in its plane stays regular at any angle; a swing out of the plane by π/2 does not."""
    across = np.cross(up, arm)
    if np.linalg.norm(across) < 1e-9 * max(1.0, float(np.linalg.norm(arm))):  # arm vertical: any
        return RotationMatrix.MakeFromOneVector(up, 2)
    x = across / np.linalg.norm(across)
    return RotationMatrix(np.column_stack([x, np.cross(up, x), up]))


def _shape(shape: pp.Shape) -> tuple[Shape, RigidTransform] | None:
    """The Drake shape of a scene shape and its pose in the scene frame (None: no geometry)."""
    if shape.type == "sphere":
        assert shape.radius is not None
        return Sphere(shape.radius), RigidTransform()
    if shape.type == "box":
        assert shape.half_extents is not None
        return Box(*(2.0 * e for e in shape.half_extents)), RigidTransform()
    if shape.type == "cylinder":
        assert shape.radius is not None and shape.height is not None and shape.axis is not None
        turn = RotationMatrix.MakeFromOneVector(np.array(shape.axis, dtype=float), 2)
        return Cylinder(shape.radius, shape.height), RigidTransform(turn, np.zeros(3))
    return None


class DrakeRun:
    """One run: the plant built from the resolved scene, stepped and sampled by pp.simulate."""

    def __init__(self, scene: pp.ResolvedScene) -> None:
        method = method_name(scene)
        if method is None:
            raise ValueError(f"method {scene.method.name!r}: not a method of {ENGINE}")
        self.scene = scene
        self.method = method
        h = scene.time_step_size
        self.settings: dict[str, pp.ParameterValue] = {"method": f"{ENGINE}.{method}"}

        def parameter(name: str) -> float:
            value = float(scene.parameter(name, catalogue.default(method, name)))
            if not value > 0:
                raise ValueError(f"parameter {name}: expected > 0, got {value}")
            self.settings[name] = value
            return value

        builder = DiagramBuilder()
        discrete = method in DISCRETE
        plant: MultibodyPlant
        plant, _ = AddMultibodyPlantSceneGraph(builder, h if discrete else 0.0)
        self.plant = plant
        if discrete:
            approximation = DISCRETE[method][0]
            plant.set_discrete_contact_approximation(getattr(DiscreteContactApproximation, approximation))
            self.settings["plant"] = (f"discrete, time step {pp.format_number(h)} s, "
                                      f"contact approximation {approximation}")
        else:
            self.settings["plant"] = "continuous"
        plant.set_penetration_allowance(parameter("penetrationAllowance"))
        if method in CONTINUOUS or method == "tamsi":
            plant.set_stiction_tolerance(parameter("stictionTolerance"))
        plant.set_adjacent_bodies_collision_filters(False)
        plant.mutable_gravity_field().set_gravity_vector(np.array(scene.gravity))
        self.settings["contact.model"] = ("point contact, stiffness and dissipation estimated by Drake "
                                          "from penetrationAllowance; restitution not used")
        self.bodies: dict[int, RigidBody] = {}
        self.tree = spanning_tree(scene)
        if self.tree.closing:
            raise ValueError(f"{scene.joints[self.tree.closing[0]].json_path}: closes a kinematic loop")
        self._add_bodies()
        self._add_geometry()
        self._add_joints()
        self._add_force_elements()
        plant.Finalize()
        self.diagram = builder.Build()
        self.simulator = Simulator(self.diagram)
        self.root_context = self.simulator.get_mutable_context()
        self.context: Context = plant.GetMyMutableContextFromRoot(self.root_context)
        self._set_initial_state()
        if not discrete:
            integrator = ResetIntegratorFromFlags(self.simulator, CONTINUOUS[method][0], h)
            integrator.set_target_accuracy(parameter("targetAccuracy"))
            control = scene.parameter("stepControl", catalogue.default(method, "stepControl"))
            if control not in ("error", "fixed"):
                raise ValueError(f"parameter stepControl: expected error or fixed, got {control!r}")
            self.settings["stepControl"] = str(control)
            if control == "fixed":
                integrator.set_fixed_step_mode(True)
                self.settings["integrator"] = f"{CONTINUOUS[method][0]}, fixed step {pp.format_number(h)} s"
            else:
                self.settings["integrator"] = f"{CONTINUOUS[method][0]}, maximum step {pp.format_number(h)} s"
        self.simulator.Initialize()
        self.settings["tree"] = (f"{len(self.tree.edges)} joints, {len(self.tree.floating_roots)} floating "
                                 f"roots, {plant.num_positions()} positions, {plant.num_velocities()} velocities")
        self.steps = 0

    def _name(self, body_id: int) -> str:
        return f"body{self.scene.body_by_id(body_id).index}"

    def _add_bodies(self) -> None:
        for b in self.scene.bodies:
            if not b.dynamic:
                continue
            if not b.mass > 0:
                raise ValueError(f"{b.json_path}: a dynamic body needs a positive mass, got {b.mass}")
            inertia = SpatialInertia.MakeFromCentralInertia(
                b.mass, np.zeros(3), RotationalInertia(*b.principal_inertia))
            self.bodies[b.id] = self.plant.AddRigidBody(self._name(b.id), inertia)

    def _pose_of_body(self, body_id: int | None) -> RigidTransform:
        """X_WB at t = 0 of a dynamic body's principal frame; the identity for the world."""
        if body_id is None:
            return RigidTransform()
        b = self.scene.body_by_id(body_id)
        return RigidTransform(_rotation(b.world_principal_rotation), np.array(b.position))

    def _body(self, body_id: int | None) -> RigidBody:
        if body_id is None or not self.scene.body_by_id(body_id).dynamic:
            return self.plant.world_body()
        return self.bodies[body_id]

    def _add_geometry(self) -> None:
        friction = geometry_friction(self.scene)
        if friction is None:
            raise ValueError("contact friction: the pairs' values are not a harmonic combination of "
                             "per-geometry values")
        for b in self.scene.bodies:
            made = _shape(b.shape)
            if made is None:
                continue
            shape, x_sg = made
            properties = ProximityProperties()
            mu = friction[b.id]
            AddContactMaterial(None, None, CoulombFriction(mu, mu), properties)
            x_ws = RigidTransform(_rotation(b.rotation), np.array(b.scene_origin))
            if b.dynamic:
                x_wb = self._pose_of_body(b.id)
                pose = x_wb.inverse() @ x_ws @ x_sg
            else:
                pose = x_ws @ x_sg
            self.plant.RegisterCollisionGeometry(self._body(b.id if b.dynamic else None), pose,
                                                 shape, f"{self._name(b.id)}.collision", properties)
            if any(b.id in p.bodies for p in self.scene.contact_pairs):
                self.settings[f"{b.json_path}.friction"] = mu

    def _joint_frames(self, edge: TreeEdge, rotation: RotationMatrix, anchor: np.ndarray) -> tuple[Frame, Frame]:
        """The joint's frames on parent and child: both at `anchor` with `rotation` in world at
        t = 0, so the joint's coordinates are zero there."""
        x_wj = RigidTransform(rotation, anchor)
        frames = []
        for role, body_id in (("parent", edge.parent), ("child", edge.child)):
            x_bj = self._pose_of_body(body_id).inverse() @ x_wj
            frame = FixedOffsetFrame(f"joint{edge.joint}.{role}", self._body(body_id).body_frame(), x_bj)
            frames.append(self.plant.AddFrame(frame))
        return frames[0], frames[1]

    def _add_joints(self) -> None:
        gravity = np.array(self.scene.gravity, dtype=float)
        up = -gravity / np.linalg.norm(gravity) if np.linalg.norm(gravity) > 0 else np.array([0.0, 0.0, 1.0])
        for edge in self.tree.edges:
            j = self.scene.joints[edge.joint]
            child = self.scene.body_by_id(edge.child)
            anchor = np.array(j.points["anchor"].world if "anchor" in j.points else child.position, dtype=float)
            name = f"joint{edge.joint}"
            if j.type in ("hinge", "slider", "damper"):
                axis = np.array(j.axes["axis"].world, dtype=float)
                parent_frame, child_frame = self._joint_frames(edge, RotationMatrix(), anchor)
                if j.type == "hinge":
                    self.plant.AddJoint(RevoluteJoint(name, parent_frame, child_frame, axis))
                else:
                    prismatic = self.plant.AddJoint(PrismaticJoint(name, parent_frame, child_frame, axis))
                    if j.type == "damper":
                        assert j.stiffness is not None
                        self.plant.AddForceElement(PrismaticSpring(prismatic, 0.0, j.stiffness))
            elif j.type == "ball":
                parent_frame, child_frame = self._joint_frames(edge, _ball_frame(up, np.array(child.position) - anchor),
                                                               anchor)
                self.plant.AddJoint(BallRpyJoint(name, parent_frame, child_frame))
            elif j.type == "universal":
                first = np.array(j.axes["axis1"].world, dtype=float)  # fixed in body1
                second = np.array(j.axes["axis2"].world, dtype=float)  # fixed in body2
                if edge.child == j.body1:
                    first, second = second, first
                cosine = abs(float(first @ second)) / float(np.linalg.norm(first) * np.linalg.norm(second))
                if cosine > PERPENDICULAR_TOLERANCE:
                    raise ValueError(f"{j.json_path}: the universal joint's axes are not perpendicular "
                                     f"at t = 0 (|cos| = {cosine:.3g}); Drake's UniversalJoint needs them so")
                parent_frame, child_frame = self._joint_frames(edge, _frame_with_axes(first, second), anchor)
                self.plant.AddJoint(UniversalJoint(name, parent_frame, child_frame))
            else:  # unsupported_features refused it before
                raise ValueError(f"{j.json_path}: joint {j.type} is not mapped")
            self.settings[f"{j.json_path}"] = (f"{JOINTS[j.type]}, parent "
                                               f"{'world' if edge.parent is None else self._name(edge.parent)}, "
                                               f"child {self._name(edge.child)}")

    def _add_force_elements(self) -> None:
        for j in self.scene.joints:
            if j.type != "rigid_body_spring":
                continue
            assert j.stiffness is not None and j.rest_length is not None and j.body1 is not None
            assert j.body2 is not None
            if j.stiffness == 0:  # the seed skips it
                self.settings[j.json_path] = "stiffness 0: skipped, as in the seed"
                continue
            if not j.rest_length > 0:
                raise ValueError(f"{j.json_path}: Drake's LinearSpringDamper needs a positive free length; "
                                 f"the anchors start {j.rest_length} m apart")
            ends = []
            for body_id, key, side in ((j.body1, "anchor1", "body1"), (j.body2, "anchor2", "body2")):
                b = self.scene.body_by_id(body_id)
                point = j.points[key]
                coordinates = getattr(point, side)
                local = coordinates.principal if b.dynamic and coordinates is not None else point.world
                ends.append((self._body(body_id if b.dynamic else None), np.array(local, dtype=float)))
            self.plant.AddForceElement(LinearSpringDamper(ends[0][0], ends[0][1], ends[1][0], ends[1][1],
                                                          j.rest_length, j.stiffness, 0.0))
            self.settings[j.json_path] = f"LinearSpringDamper k={j.stiffness:g} N/m, L={j.rest_length:.9g} m"

    def _set_initial_state(self) -> None:
        plant, context = self.plant, self.context
        for root in self.tree.floating_roots:
            plant.SetFreeBodyPose(context, self.bodies[root], self._pose_of_body(root))
        for b in self.scene.bodies:
            if not b.dynamic:
                continue
            pose = plant.EvalBodyPoseInWorld(context, self.bodies[b.id])
            expected = self._pose_of_body(b.id)
            offset = float(np.linalg.norm(pose.translation() - expected.translation()))
            turn = float(np.abs(pose.rotation().matrix() - expected.rotation().matrix()).max())
            if max(offset, turn) > INITIAL_POSE_TOLERANCE:
                raise RuntimeError(f"{b.json_path}: the plant's pose at t = 0 is not the scene's "
                                   f"(off by {offset:.3g} m, {turn:.3g} in its rotation matrix)")
        nv = plant.num_velocities()
        if nv == 0:
            return
        mass_matrix = plant.CalcMassMatrix(context)
        momentum = np.zeros(nv)
        jacobians: dict[int, np.ndarray] = {}
        for b in self.scene.bodies:
            if not b.dynamic:
                continue
            jacobian = plant.CalcJacobianSpatialVelocity(
                context, JacobianWrtVariable.kV, self.bodies[b.id].body_frame(), np.zeros(3),
                plant.world_frame(), plant.world_frame())
            jacobians[b.id] = jacobian
            rotation = _rotation(b.world_principal_rotation).matrix()
            inertia = rotation @ np.diag(b.principal_inertia) @ rotation.T
            spatial_momentum = np.concatenate([inertia @ np.array(b.angular_velocity),
                                               b.mass * np.array(b.velocity)])
            momentum += jacobian.T @ spatial_momentum
        velocities = np.linalg.solve(mass_matrix, momentum)
        plant.SetVelocities(context, velocities)
        for b in self.scene.bodies:
            if not b.dynamic:
                continue
            spatial = jacobians[b.id] @ velocities
            w, v = spatial[:3], spatial[3:]
            mismatch = float(np.linalg.norm(v - b.velocity) + np.linalg.norm(w - b.angular_velocity))
            scale = float(np.linalg.norm(b.velocity) + np.linalg.norm(b.angular_velocity))
            if mismatch > VELOCITY_MISMATCH_TOLERANCE * (1 + scale):
                self.settings[f"{b.json_path}.initialVelocity"] = (
                    f"disagrees with its joints by {mismatch:.6g}; projected onto them "
                    "(kinetic-energy norm): v = " + " ".join(f"{x:.6g}" for x in v)
                    + ", w = " + " ".join(f"{x:.6g}" for x in w))

    def states(self) -> list[pp.BodyState]:
        out = []
        for b in self.scene.bodies:
            if not b.dynamic:
                out.append(pp.BodyState(b.id, b.position, b.rotation, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
                continue
            body = self.bodies[b.id]
            pose = self.plant.EvalBodyPoseInWorld(self.context, body)
            velocity = self.plant.EvalBodySpatialVelocityInWorld(self.context, body)
            q = pose.rotation().ToQuaternion()
            rotation = pp.quat_multiply((q.w(), q.x(), q.y(), q.z()), pp.quat_conjugate(b.principal_rotation))
            out.append(pp.BodyState(b.id, pose.translation().copy(), rotation,
                                    velocity.translational().copy(), velocity.rotational().copy()))
        return out

    def run(self, out_dir: Path) -> pp.Status:
        h = self.scene.time_step_size

        def step() -> None:
            self.steps += 1
            self.simulator.AdvanceTo(self.steps * h)

        def check(t: float) -> str | None:
            state = self.plant.GetPositionsAndVelocities(self.context)
            if not np.isfinite(state).all():
                return f"non-finite state at t = {t:g} s"
            if state.size and np.abs(state).max() > pp.DIVERGENCE_LIMIT:
                return f"a coordinate or speed beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            return None

        status = pp.simulate(self.scene, out_dir, step, lambda t: self.states(), check=check)
        status.engine_version = engine_version()
        if self.method in CONTINUOUS:
            integrator = self.simulator.get_integrator()
            self.settings["integrator.stepsTaken"] = int(integrator.get_num_steps_taken())
            self.settings["integrator.stepSizeShrinksForError"] = int(
                integrator.get_num_step_shrinkages_from_error_control())
            smallest = float(integrator.get_smallest_adapted_step_size_taken())
            if math.isfinite(smallest):  # NaN in fixed-step mode: no step was adapted
                self.settings["integrator.smallestStep"] = smallest
        status.effective_settings = self.settings
        status.integrator_steps_per_scene_step = 1
        status.contact_margin = 0.0
        status.initial_velocities_projected = True  # generalised coordinates
        return status


def run_scene(scene: pp.ResolvedScene, out_dir: Path) -> pp.Status:
    return DrakeRun(scene).run(out_dir)


def main(argv: list[str] | None = None) -> int:
    return pp.serve(argv, "Drake (MultibodyPlant) as a pbdval external engine", unsupported_features,
                    run_scene, engine_version())


