"""DART through dartpy as an external engine (protocol 1, docs/external-engines.md; mapping and
measurements: docs/engine-dart.md).

    .venv/bin/python -m pbdval.external.dart --scene RESOLVED.json --out OUTDIR

The scene's joints become DART skeletons in reduced coordinates (the spanning forest of
pbdval.external.joint_trees): one skeleton per tree, its root a FreeJoint (a tree of dynamic
bodies) or its first joints attached to the world (a tree holding a static body); every static
body a skeleton of its own, immobile. Each BodyNode's frame is the body's principal frame (centre
of mass at its origin, diagonal inertia); each joint's frame sits at the anchor with the world's
axes at t = 0, so every joint coordinate starts at 0. Shapes are ShapeNodes placed at the scene
frame. DART integrates with semi-implicit Euler (velocities, then positions with the new
velocities) and resolves contacts and limits as one boxed LCP per step, by Dantzig's method
(`dart.dantzig`) or projected Gauss-Seidel (`dart.pgs`). Jointed bodies collide, as in the seed
(self-collision and adjacent-body checks on).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import dartpy as dart
import numpy as np

from pbdval import protocol as pp
from pbdval.external import joint_trees
from pbdval.external.dart import catalogue
from pbdval.external.dart.catalogue import DEFAULT_METHOD, ENGINE
from pbdval.external.dart.features import SHAPES, TREE_JOINTS
from pbdval.external.pybullet.materials import per_body_factors


def engine_version() -> str:
    return f"dartpy {dart.__version__}"


def solver_of(method: str) -> str | None:
    """The method's solver suffix (`dantzig`, `pgs`), or None for an unknown method."""
    name = method or DEFAULT_METHOD
    prefix = f"{ENGINE}."
    suffix = name[len(prefix):] if name.startswith(prefix) else ""
    return suffix if suffix in catalogue.SOLVERS else None


def friction_per_body(scene: pp.ResolvedScene) -> list[float] | None:
    """Per-body friction f_i with min(f_i, f_j) = the pair's friction for every pair (DART takes
    the smaller of the two), or None when the pairs are not of that form. f_i is the largest of
    its pairs' values (1 for a body in no pair); that choice works whenever any does."""
    index = {b.id: b.index for b in scene.bodies}
    values = [0.0] * len(scene.bodies)
    seen = [False] * len(scene.bodies)
    for p in scene.contact_pairs:
        for body_id in p.bodies:
            i = index[body_id]
            values[i] = max(values[i], p.friction) if seen[i] else p.friction
            seen[i] = True
    if any(min(values[index[p.bodies[0]]], values[index[p.bodies[1]]]) != p.friction
           for p in scene.contact_pairs):
        return None
    return [v if s else 1.0 for v, s in zip(values, seen)]


def restitution_per_body(scene: pp.ResolvedScene) -> list[float] | None:
    """Per-body restitution whose products are the pairs' (DART multiplies the two)."""
    index = {b.id: b.index for b in scene.bodies}
    factors = per_body_factors(len(scene.bodies), [(index[p.bodies[0]], index[p.bodies[1]], p.restitution)
                                                    for p in scene.contact_pairs])
    if factors is None or any(f > 1 + 1e-9 for f in factors):
        return None  # DART takes restitution coefficients in [0, 1]
    # exp(log) round-off can leave 1 + 2e-16, which DART would not take as a restitution
    return [min(f, 1.0) for f in factors]


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    """What this engine cannot run, each naming its JSON path (the catalogue's table says the same)."""
    missing: list[str] = []
    if solver_of(scene.method.name) is None:
        missing.append(f"method {scene.method.name}")
    for b in scene.bodies:
        if b.shape.type not in SHAPES:
            missing.append(f"{b.json_path}: shape {b.shape.type} (dart maps {', '.join(SHAPES)})")
        elif b.shape.inverted:
            missing.append(f"{b.json_path}: inverted shape (invertSDF)")
    for j in scene.joints:
        if j.type not in TREE_JOINTS:
            missing.append(f"{j.json_path}: joint {j.type} (dart maps {', '.join(sorted(TREE_JOINTS))})")
    forest = joint_trees.plan_forest(scene, TREE_JOINTS)
    missing += joint_trees.loop_messages(scene, forest, "DART")
    if scene.particles or scene.triangle_models or scene.tet_models or scene.line_models or scene.fluid_models:
        missing.append(f"particles ({len(scene.particles)}: cloth, solids, rods or fluids): the dart "
                       "engine maps no particles")
    if friction_per_body(scene) is None:
        missing.append("contact friction: the pairs' values are not the smaller of per-body values "
                       "(DART takes the minimum of the two bodies' friction)")
    if restitution_per_body(scene) is None:
        missing.append("contact restitution: the pairs' values are not products of per-body values "
                       "(DART multiplies the two bodies' restitution, each in [0, 1])")
    return missing


def _rotation(q: pp.FloatVector) -> np.ndarray:
    w, x, y, z = (float(v) for v in q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _isometry(rotation: np.ndarray, translation: pp.FloatVector) -> Any:
    t = dart.math.Isometry3()
    t.set_rotation(rotation)
    t.set_translation(np.asarray(translation, dtype=float))
    return t


def _z_to(axis: pp.FloatVector) -> np.ndarray:
    """A rotation taking z to the unit vector `axis` (DART's cylinders lie along z)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    z = np.array([0.0, 0.0, 1.0])
    c = float(z @ a)
    if c < -1 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    v = np.cross(z, a)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rotation: np.ndarray = np.eye(3) + k + k @ k / (1 + c)
    return rotation


def _quaternion(r: np.ndarray) -> pp.Quat:
    """w, x, y, z with w >= 0 of a rotation matrix (Shepperd's method)."""
    trace = float(np.trace(r))
    if trace > 0:
        s = 2 * math.sqrt(1 + trace)
        q = (0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * math.sqrt(max(0.0, 1 + r[i, i] - r[j, j] - r[k, k]))
        v = [0.0, 0.0, 0.0]
        v[i] = 0.25 * s
        v[j] = (r[j, i] + r[i, j]) / s
        v[k] = (r[k, i] + r[i, k]) / s
        q = ((r[k, j] - r[j, k]) / s, v[0], v[1], v[2])
    n = math.sqrt(sum(c * c for c in q))
    sign = -1.0 if q[0] < 0 else 1.0
    return (sign * q[0] / n, sign * q[1] / n, sign * q[2] / n, sign * q[3] / n)


class DartRun:
    def __init__(self, scene: pp.ResolvedScene) -> None:
        self.scene = scene
        solver = solver_of(scene.method.name)
        assert solver is not None

        def parameter(name: str) -> pp.ParameterValue:
            return scene.parameter(name, catalogue.default(solver, name))

        detector = str(parameter("collisionDetector"))
        if detector not in catalogue.DETECTORS:
            raise ValueError(f"parameter collisionDetector: expected one of "
                             f"{', '.join(catalogue.DETECTORS)}, got {detector!r}")
        per_pair = int(parameter("maxContactsPerPair"))
        if per_pair < 1:
            raise ValueError(f"parameter maxContactsPerPair: expected >= 1, got {per_pair}")
        self.settings: dict[str, pp.ParameterValue] = {
            "method": f"{ENGINE}.{solver}", "boxedLcpSolver": catalogue.SOLVERS[solver].split(":")[0],
            "collisionDetector": catalogue.DETECTORS[detector], "maxContactsPerPair": per_pair,
            "integrator": "semi-implicit Euler (DART's World::step)", "timeStep": scene.time_step_size,
            "frictionCombination": "min", "restitutionCombination": "product",
            "jointedBodiesCollide": "yes (self-collision and adjacent-body checks on)",
        }
        self.world = dart.simulation.World()
        self.world.setGravity(np.asarray(scene.gravity, dtype=float))
        self.world.setTimeStep(scene.time_step_size)
        constraint_solver = self.world.getConstraintSolver()
        detectors = {"fcl": dart.collision.FCLCollisionDetector, "bullet": dart.collision.BulletCollisionDetector,
                     "ode": dart.collision.OdeCollisionDetector, "dart": dart.collision.DARTCollisionDetector}
        constraint_solver.setCollisionDetector(detectors[detector]())
        constraint_solver.getCollisionOption().maxNumContactsPerPair = per_pair
        if solver == "pgs":
            # dartpy binds no constructor for the LCP solvers: the world's own PGS (its default
            # fallback) becomes the primary solver, without a fallback.
            pgs = constraint_solver.getSecondaryBoxedLcpSolver()
            option = dart.constraint.PgsBoxedLcpSolverOption()
            option.mMaxIteration = int(parameter("iterations"))
            if option.mMaxIteration < 1:
                raise ValueError(f"parameter iterations: expected >= 1, got {option.mMaxIteration}")
            pgs.setOption(option)
            constraint_solver.setSecondaryBoxedLcpSolver(None)
            constraint_solver.setBoxedLcpSolver(pgs)
            self.settings["iterations"] = option.mMaxIteration
        # dart.dantzig: the world's default, Dantzig with PGS as the fallback when it fails.
        secondary = constraint_solver.getSecondaryBoxedLcpSolver()
        self.settings["boxedLcpSolver"] = constraint_solver.getBoxedLcpSolver().getType()
        self.settings["secondaryBoxedLcpSolver"] = secondary.getType() if secondary is not None else "none"
        friction = friction_per_body(scene)
        restitution = restitution_per_body(scene)
        assert friction is not None and restitution is not None
        self.friction, self.restitution = friction, restitution
        self.forest = joint_trees.plan_forest(scene, TREE_JOINTS)
        self.nodes: dict[int, Any] = {}
        self.skeletons: list[Any] = []
        self._build()
        for skeleton in self.skeletons:
            self.world.addSkeleton(skeleton)
        self._initial_velocities()

    # --- building ---------------------------------------------------------------------------

    def _pose(self, body: pp.Body) -> Any:
        return _isometry(_rotation(body.world_principal_rotation), body.position)

    def _inertia(self, body: pp.Body) -> Any:
        return dart.dynamics.Inertia(body.mass, np.zeros(3), np.diag(np.asarray(body.principal_inertia, dtype=float)))

    def _shape(self, node: Any, body: pp.Body) -> None:
        s = body.shape
        if s.type == "none":
            return
        if s.type == "sphere":
            assert s.radius is not None
            shape: Any = dart.dynamics.SphereShape(s.radius)
            in_scene = np.eye(3)
        elif s.type == "box":
            assert s.half_extents is not None
            shape = dart.dynamics.BoxShape(2 * np.asarray(s.half_extents, dtype=float))
            in_scene = np.eye(3)
        else:  # cylinder
            assert s.radius is not None and s.height is not None and s.axis is not None
            shape = dart.dynamics.CylinderShape(s.radius, s.height)
            in_scene = _z_to(s.axis)
        # scene frame in the principal (BodyNode) frame: R_p^T (x - c)
        principal = _rotation(body.principal_rotation)
        rotation = principal.T @ in_scene
        translation = -principal.T @ np.asarray(body.principal_com, dtype=float)
        shape_node = node.createShapeNode(shape)
        shape_node.setRelativeTransform(_isometry(rotation, translation))
        shape_node.createCollisionAspect()
        dynamics = shape_node.createDynamicsAspect()
        dynamics.setFrictionCoeff(self.friction[body.index])
        dynamics.setRestitutionCoeff(self.restitution[body.index])

    def _build(self) -> None:
        scene = self.scene
        for body in scene.bodies:
            if body.dynamic:
                continue
            skeleton = dart.dynamics.Skeleton(f"static{body.index}")
            joint, node = skeleton.createWeldJointAndBodyNodePair()
            joint.setTransformFromParentBodyNode(self._pose(body))
            node.setInertia(dart.dynamics.Inertia(1.0, np.zeros(3), np.eye(3)))
            self._shape(node, body)
            skeleton.setMobile(False)
            self.nodes[body.index] = node
            self.skeletons.append(skeleton)
        skeleton_of: dict[int, Any] = {}
        for b in self.forest.order:
            body = scene.bodies[b]
            tree_joint = self.forest.parent_joint.get(b)
            if tree_joint is None:  # a free root
                skeleton = dart.dynamics.Skeleton(f"tree{b}")
                skeleton.enableSelfCollisionCheck()
                skeleton.enableAdjacentBodyCheck()
                joint, node = skeleton.createFreeJointAndBodyNodePair()
                joint.setPositions(dart.dynamics.FreeJoint.convertToPositions(self._pose(body)))
                self.skeletons.append(skeleton)
            else:
                parent = tree_joint.parent
                if parent == joint_trees.WORLD:
                    skeleton = dart.dynamics.Skeleton(f"tree{b}")
                    skeleton.enableSelfCollisionCheck()
                    skeleton.enableAdjacentBodyCheck()
                    self.skeletons.append(skeleton)
                    parent_node, parent_pose = None, _isometry(np.eye(3), np.zeros(3))
                else:
                    skeleton = skeleton_of[parent]
                    parent_node, parent_pose = self.nodes[parent], self._pose(scene.bodies[parent])
                joint, node = self._tree_joint(skeleton, parent_node, tree_joint)
                anchor = _isometry(np.eye(3), self._anchor(scene.joints[tree_joint.joint]))
                joint.setTransformFromParentBodyNode(parent_pose.inverse().multiply(anchor))
                joint.setTransformFromChildBodyNode(self._pose(body).inverse().multiply(anchor))
            skeleton_of[b] = skeleton
            node.setName(f"body{b}")
            node.setInertia(self._inertia(body))
            self._shape(node, body)
            self.nodes[b] = node

    @staticmethod
    def _anchor(j: pp.Joint) -> pp.Vec3:
        return j.points["anchor"].world if "anchor" in j.points else j.points["anchor1"].world

    def _tree_joint(self, skeleton: Any, parent: Any, tree_joint: joint_trees.TreeJoint) -> tuple[Any, Any]:
        j = self.scene.joints[tree_joint.joint]
        kind = TREE_JOINTS[j.type]
        if kind == "BallJoint":
            pair: tuple[Any, Any] = skeleton.createBallJointAndBodyNodePair(parent)
            return pair
        if kind == "UniversalJoint":
            joint, node = skeleton.createUniversalJointAndBodyNodePair(parent)
            first, second = ("axis2", "axis1") if tree_joint.flipped else ("axis1", "axis2")
            joint.setAxis1(np.asarray(j.axes[first].world, dtype=float))
            joint.setAxis2(np.asarray(j.axes[second].world, dtype=float))
            return joint, node
        create = (skeleton.createRevoluteJointAndBodyNodePair if kind == "RevoluteJoint"
                  else skeleton.createPrismaticJointAndBodyNodePair)
        joint, node = create(parent)
        joint.setAxis(np.asarray(j.axes["axis"].world, dtype=float))
        if j.type == "damper":
            assert j.stiffness is not None
            joint.setSpringStiffness(0, j.stiffness)
            joint.setRestPosition(0, 0.0)  # the initial offset: the coordinate starts at 0
            self.settings[f"{j.json_path}.spring"] = f"PrismaticJoint spring k={j.stiffness:g} N/m, rest 0"
        return joint, node

    def _initial_velocities(self) -> None:
        """Per skeleton, the joint velocities closest to the scene's body velocities in the
        kinetic-energy norm: M qdot = sum_b J_b^T (I w, m v) (J: DART's world Jacobian at the
        centre of mass, angular rows first). Exact where the velocities agree with the joints
        (every free body); a body they disagree for is recorded."""
        for skeleton in self.skeletons:
            if not skeleton.isMobile() or skeleton.getNumDofs() == 0:
                continue
            momentum = np.zeros(skeleton.getNumDofs())
            bodies = [(self.scene.bodies[b], self.nodes[b]) for b in self.forest.order
                      if self.nodes[b].getSkeleton().getName() == skeleton.getName()]
            for body, node in bodies:
                jacobian = self._jacobian(skeleton, node)
                rotation = _rotation(body.world_principal_rotation)
                inertia = rotation @ np.diag(np.asarray(body.principal_inertia, dtype=float)) @ rotation.T
                wrench = np.concatenate([inertia @ np.asarray(body.angular_velocity, dtype=float),
                                         body.mass * np.asarray(body.velocity, dtype=float)])
                momentum += jacobian.T @ wrench
            skeleton.setVelocities(np.linalg.solve(skeleton.getMassMatrix(), momentum))
            for body, node in bodies:
                v, w = node.getLinearVelocity(), node.getAngularVelocity()
                mismatch = float(np.linalg.norm(v - body.velocity) + np.linalg.norm(w - body.angular_velocity))
                scale = float(np.linalg.norm(body.velocity) + np.linalg.norm(body.angular_velocity))
                if mismatch > 1e-9 * (1 + scale):
                    self.settings[f"{body.json_path}.initialVelocity"] = (
                        f"disagrees with its joints by {mismatch:.6g}; projected onto them (kinetic-energy norm)")

    @staticmethod
    def _jacobian(skeleton: Any, node: Any) -> np.ndarray:
        """The node's 6 x ndofs world Jacobian at its origin, columns for every DoF of the skeleton."""
        local = np.asarray(node.getWorldJacobian(np.zeros(3)))
        full = np.zeros((6, skeleton.getNumDofs()))
        for column in range(node.getNumDependentGenCoords()):
            full[:, node.getDependentGenCoordIndex(column)] = local[:, column]
        return full

    # --- running ----------------------------------------------------------------------------

    def states(self) -> list[pp.BodyState]:
        out = []
        for body in self.scene.bodies:
            node = self.nodes[body.index]
            pose = node.getWorldTransform()
            principal = _quaternion(np.asarray(pose.rotation()))
            q = pp.quat_multiply(principal, pp.quat_conjugate(body.principal_rotation))
            if body.dynamic:
                v, w = node.getLinearVelocity(), node.getAngularVelocity()
            else:
                v, w = np.zeros(3), np.zeros(3)
            out.append(pp.BodyState(body.id, np.asarray(pose.translation()).copy(), q,
                                    [float(x) for x in v], [float(x) for x in w]))
        return out

    def run(self, out_dir: Path) -> pp.Status:
        def check(t: float) -> str | None:
            for skeleton in self.skeletons:
                q, v = skeleton.getPositions(), skeleton.getVelocities()
                if not (np.isfinite(q).all() and np.isfinite(v).all()):
                    return f"non-finite state at t = {t:g} s"
                largest = max(float(np.abs(q).max(initial=0.0)), float(np.abs(v).max(initial=0.0)))
                if largest > pp.DIVERGENCE_LIMIT:
                    return f"a coordinate or speed beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            return None

        status = pp.simulate(self.scene, out_dir, self.world.step, lambda t: self.states(), check=check)
        status.engine_version = engine_version()
        status.effective_settings = self.settings
        status.integrator_steps_per_scene_step = 1
        status.contact_margin = 0.0
        status.initial_velocities_projected = True
        return status


def main(argv: list[str] | None = None) -> int:
    return pp.serve(argv, "DART (dartpy) as a pbdval external engine", unsupported_features,
                    lambda scene, out: DartRun(scene).run(out), engine_version())
