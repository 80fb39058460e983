"""pybullet as an external engine (protocol 1, docs/external-engines.md; parity rules:
docs/external-engines.md#pybullet).

    .venv/bin/python -m pbdval.external.pybullet --scene RESOLVED.json --out OUTDIR

The scene is built through pybullet's API in DIRECT mode, with the same parity rules as the
built-in `bullet` engine (adapters/bullet/): every body a maximal-coordinate btRigidBody whose
frame is its principal frame (createMultiBody with baseMass, baseInertialFramePosition /
Orientation = the principal frame, then localInertiaDiagonal = the principal inertia: pybullet
never guesses a mass); per-pair friction and restitution (as per-body factors whose products
are the pair values: materials.py); no sleeping; no damping; restitution threshold 0; no
speculative contacts; split impulse for all penetration; one internal step per scene step
(fixedTimeStep = h, numSubSteps 0). Joints through createConstraint: ball = a point-to-point
constraint; hinge = two point-to-point constraints on the axis (hinge_half_length). Everything else is reported
unsupported by name.

The methods pybullet.multibody.* (multibody.py) build the joints' trees as btMultiBodies in
reduced coordinates instead; `run` and `unsupported_features` hand them over.

Scenes with particles (cloth: TriangleModels, solids: TetModels) run in Bullet's deformable world
(resetSimulation(RESET_USE_DEFORMABLE_WORLD)) as soft bodies: deformables.py, and the mapping
table in docs/external-engines.md#pybullet.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as pb

from pbdval import protocol as pp
from pbdval.external.pybullet import deformables, materials

#: method name → pybullet constraintSolverType
SOLVERS = {
    "pybullet.si": pb.CONSTRAINT_SOLVER_LCP_SI,
    "pybullet.pgs": pb.CONSTRAINT_SOLVER_LCP_PGS,
    "pybullet.dantzig": pb.CONSTRAINT_SOLVER_LCP_DANTZIG,
}
DEFAULT_METHOD = "pybullet.si"
#: The reduced-coordinate family (multibody.py): pybullet.multibody.si, .pgs, .dantzig.
MULTIBODY_PREFIX = "pybullet.multibody."
SUPPORTED_JOINTS = ("ball", "hinge")
SUPPORTED_SHAPES = ("none", "sphere", "box", "cylinder", "sdf", "torus")
#: Half the distance between a hinge's two point-to-point constraints when no body of the joint
#: moves, m (hinge_half_length gives it otherwise).
STATIC_HINGE_HALF_LENGTH = 1.0
#: pybullet's constraints default to maxForce 500 N; the scene's joints are ideal (unbounded).
UNLIMITED_FORCE = 1e30
#: Linear slop of resting contacts, m (as the built-in bullet engine: docs/parity-bullet.md).
CONTACT_SLOP = 1e-5
#: Default collision margin of soft bodies, m: a node rests this far from a rigid surface
#: (Bullet's own default, 0.02 m, would hold cloth 2 cm off the surface).
DEFAULT_PARTICLE_MARGIN = 1e-3


def _read_engine_version() -> str:
    # The wheel's version from its dist-info folder beside the module: importlib.metadata would
    # cost 33 ms of imports per run, a fifth of the protocol's start-up (docs/benchmarks.md).
    found = sorted(Path(pb.__file__).parent.glob("pybullet-*.dist-info"))
    version = found[-1].name[len("pybullet-"):-len(".dist-info")] if found else "unknown version"
    return f"pybullet {version} (API {pb.getAPIVersion()})"


#: Read once, when the module is imported: a served run's child has it from the server, instead
#: of listing site-packages twice per run.
_ENGINE_VERSION = _read_engine_version()


def engine_version() -> str:
    return _ENGINE_VERSION


def xyzw(q: Any) -> list[float]:
    return [q[1], q[2], q[3], q[0]]


def wxyz(q: Any) -> tuple[float, float, float, float]:
    return (q[3], q[0], q[1], q[2])


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    if scene.method.name.startswith(MULTIBODY_PREFIX):
        from pbdval.external.pybullet import multibody  # imports this module

        return multibody.unsupported_features(scene)
    missing: list[str] = []
    if scene.method.name not in ("", *SOLVERS):
        missing.append(f"method {scene.method.name}")
    for j in scene.joints:
        if j.type not in SUPPORTED_JOINTS:
            missing.append(f"{j.json_path}: joint {j.type} (pybullet's createConstraint on "
                           "maximal-coordinate bodies has point-to-point, fixed and gear only)")
    for b in scene.bodies:
        if b.shape.type not in SUPPORTED_SHAPES:
            missing.append(f"{b.json_path}: shape {b.shape.type}")
        elif b.shape.inverted:
            missing.append(f"{b.json_path}: inverted shape (invertSDF)")
        elif b.shape.type in ("sdf", "torus") and not b.geometry_file:
            missing.append(f"{b.json_path}: shape {b.shape.type} without a geometry file")
    missing.extend(deformables.unsupported_features(scene))
    if deformables.has_deformables(scene) and scene.method.name not in ("", DEFAULT_METHOD):
        missing.append(f"method {scene.method.name} with cloth or solids: the deformable world "
                       "solves with its own btDeformableMultiBodyConstraintSolver; switching "
                       "constraintSolverType to the MLCP solvers crashes pybullet 3.2.7")
    if material_factors(scene, "friction") is None:
        missing.append("contact friction: the pairs' values are not products of per-body values "
                       "(pybullet multiplies the bodies' lateralFriction)")
    if material_factors(scene, "restitution") is None:
        missing.append("contact restitution: the pairs' values are not products of per-body "
                       "values (pybullet multiplies the bodies' restitution)")
    return missing


def material_factors(scene: pp.ResolvedScene, which: str) -> list[float] | None:
    """Per-body factors whose products are the pairs' values: the rigid bodies' (in scene order)
    then, for friction, the soft bodies' kDF (in particle order): Bullet multiplies a soft body's
    kDF by a rigid body's lateralFriction, and two soft bodies' kDF, where PBD combines the
    model's friction with the other's by the scene's contactCombineRule."""
    index = {b.id: b.index for b in scene.bodies}
    pairs = [(index[p.bodies[0]], index[p.bodies[1]], getattr(p, which))
             for p in scene.contact_pairs]
    count = len(scene.bodies)
    if which == "friction" and deformables.has_deformables(scene):
        soft = [m for _, m in deformables.models(scene)]
        rule = scene.contact_combine_rule
        for i, m in enumerate(soft):
            for b in scene.bodies:
                if b.shape.type != "none":
                    pairs.append((count + i, b.index,
                                  pp.combine_friction(rule, m.friction, b.material.friction)))
            for j in range(i + 1, len(soft)):
                pairs.append((count + i, count + j,
                              pp.combine_friction(rule, m.friction, soft[j].friction)))
        count += len(soft)
    factors = materials.per_body_factors(count, pairs)
    if (factors is not None and which == "friction"
            and any(v > materials.BULLET_MAX_FRICTION for _, _, v in pairs)):
        return None
    return factors


def hinge_half_length(bodies: list[pp.Body], anchor: pp.Vec3, axis: pp.Vec3) -> float:
    """Half the distance d between the two point-to-point constraints of a hinge (at anchor ± d
    axis). Any d gives the same kinematics, but not the same solve: for a direction n normal to
    the axis, the rows of the two points along n couple in the inverse-mass metric as
    N - d^2 D, N = sum over the moving bodies of 1/m + (r x n)' I^-1 (r x n) (r: centre of mass
    to anchor), D = sum of e' I^-1 e (e = axis x n). At d^2 = N/D they are orthogonal, and
    Gauss-Seidel solves them independently; a d far from it makes them nearly dependent, and 10
    sweeps leave a double pendulum of 0.5 x 0.05 m links with 1.7 m of joint error at d = 1 m.
    Over the two directions normal to the axis, d^4 = det N / det D (the 2 x 2 matrices on the
    plane: independent of the basis)."""
    a = np.array(axis, dtype=float)
    a /= np.linalg.norm(a)
    n1 = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    n1 /= np.linalg.norm(n1)
    plane = (n1, np.cross(a, n1))
    n_matrix, d_matrix = np.zeros((2, 2)), np.zeros((2, 2))
    for body in bodies:
        if not body.dynamic:
            continue
        rotation = np.array(_rotation_matrix(body.world_principal_rotation))
        inverse_inertia = rotation @ np.diag([1.0 / i for i in body.principal_inertia]) @ rotation.T
        r = np.array(anchor) - np.array(body.position)
        for i, ni in enumerate(plane):
            for j, nj in enumerate(plane):
                n_matrix[i, j] += (float(ni @ nj) / body.mass
                                   + np.cross(r, ni) @ inverse_inertia @ np.cross(r, nj))
                d_matrix[i, j] += np.cross(a, ni) @ inverse_inertia @ np.cross(a, nj)
    if np.linalg.det(d_matrix) <= 0.0:
        return STATIC_HINGE_HALF_LENGTH
    return float((np.linalg.det(n_matrix) / np.linalg.det(d_matrix)) ** 0.25)


def _rotation_matrix(q: pp.Quat) -> list[list[float]]:
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def collision_shape(client: int, body: pp.Body,
                    frame_position: Sequence[float] = (0.0, 0.0, 0.0)) -> tuple[int, str]:
    """The pybullet shape in the body's scene frame, and a note when it approximates.
    `frame_position`: the scene frame's origin in the frame the shape is attached to, when that
    is not the scene frame but one turned as it (a multibody's link frame: multibody.py)."""
    s = body.shape
    offset = list(frame_position)
    if s.type == "none":
        return -1, ""
    if s.type == "sphere":
        return pb.createCollisionShape(pb.GEOM_SPHERE, radius=s.radius,
                                       collisionFramePosition=offset, physicsClientId=client), ""
    if s.type == "box":
        assert s.half_extents is not None  # every box has them (protocol.read_resolved_scene)
        return pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(s.half_extents),
                                       collisionFramePosition=offset,
                                       physicsClientId=client), ""
    if s.type == "cylinder":
        # pybullet's cylinder runs along z, the scene's along y: rotate −90° about x.
        half = math.sqrt(0.5)
        return pb.createCollisionShape(pb.GEOM_CYLINDER, radius=s.radius, height=s.height,
                                       collisionFrameOrientation=[-half, 0, 0, half],
                                       collisionFramePosition=offset,
                                       physicsClientId=client), ""
    # sdf and torus: the body's mesh, as the built-in bullet engine does.
    flags = 0 if body.dynamic else pb.GEOM_FORCE_CONCAVE_TRIMESH
    shape = pb.createCollisionShape(pb.GEOM_MESH, fileName=body.geometry_file,
                                    meshScale=list(body.geometry_scale or (1, 1, 1)), flags=flags,
                                    collisionFramePosition=offset, physicsClientId=client)
    note = "convex hull of the mesh" if body.dynamic else "triangle mesh"
    return shape, f"{body.json_path}: {s.type} as {note}"



def point_in_principal_frames(scene: pp.ResolvedScene, joint: pp.Joint,
                              offset: tuple[float, float, float]
                              ) -> tuple[pp.Body, pp.Body, list[float], list[float]]:
    """The joint's two bodies and the point anchor + offset (world, t = 0) in each body's
    principal (centre-of-mass) frame, q_wp⁻¹ (x − c): how pybullet's point-to-point constraints
    take their pivots."""
    b1 = scene.body_by_id(joint.body1)  # type: ignore[arg-type]
    b2 = scene.body_by_id(joint.body2)  # type: ignore[arg-type]
    world = [a + o for a, o in zip(joint.points["anchor"].world, offset, strict=True)]

    def local(body: pp.Body) -> list[float]:
        d = [x - c for x, c in zip(world, body.position, strict=True)]
        return list(pp.quat_rotate(pp.quat_conjugate(body.world_principal_rotation), d))

    return b1, b2, local(b1), local(b2)

class PybulletRun:
    def __init__(self, scene: pp.ResolvedScene, folder: str | None = None) -> None:
        """`folder`: a scratch folder for the soft bodies' mesh files (scenes with particles)."""
        self.scene = scene
        self.client = pb.connect(pb.DIRECT)
        self.ids: list[int] = []
        self.principal_factors = pp.principal_to_scene_factors(scene)
        self.notes: list[str] = []
        self.soft: deformables.SoftBodies | None = None
        self.substeps = 1
        method = scene.method.name or DEFAULT_METHOD
        self.solver = self._solver(method)
        self.iterations = int(scene.parameter("solverIterations", 10))
        self.erp = float(scene.parameter("erp", 0.2))
        self.contact_erp = float(scene.parameter("contactErp", 0.2))
        self.settings: dict[str, pp.ParameterValue] = {
            "method": method, "solverIterations": self.iterations, "erp": self.erp,
            "contactErp": self.contact_erp, "fixedTimeStep": scene.time_step_size,
            "numSubSteps": 0, "restitutionVelocityThreshold": 0.0, "contactSlop": CONTACT_SLOP,
            "useSplitImpulse": True, "splitImpulsePenetrationThreshold": 0.0,
            "linearDamping": 0.0, "angularDamping": 0.0, "sleeping": False,
            "contactProcessingThreshold": 0.0, "bodies": "maximal coordinates (btRigidBody)",
            "materials": "per-body factors whose products are the pair values",
        }
        if deformables.has_deformables(scene):
            # Bullet's deformable world (btDeformableMultiBodyDynamicsWorld) replaces the
            # discrete dynamics world; it must come before anything is added.
            pb.resetSimulation(pb.RESET_USE_DEFORMABLE_WORLD, physicsClientId=self.client)
        self._world()
        self._bodies()
        self._joints()
        if deformables.has_deformables(scene):
            if folder is None:
                raise ValueError("a scene with particles needs a scratch folder for its meshes")
            self._soft_bodies(folder)
        if self.notes:
            self.settings["approximations"] = "; ".join(self.notes)
        self._prepare_state_reads()

    def _prepare_state_reads(self) -> None:
        """What `states` needs at every sample, made once the world is built: its array, a row
        per body in scene order."""
        self._read = np.empty((len(self.scene.bodies), pp.STATE_COLUMNS))

    def _solver(self, method: str) -> int:
        return int(SOLVERS[method])

    def _soft_bodies(self, folder: str) -> None:
        scene = self.scene
        requested = int(scene.parameter("deformableSubsteps", 0))
        margin = float(scene.parameter("particleCollisionMargin", DEFAULT_PARTICLE_MARGIN))
        bending = float(scene.parameter("bendingSpringStiffness", 0.0))
        friction = material_factors(scene, "friction")
        assert friction is not None  # checked by unsupported_features
        self.soft = deformables.SoftBodies(self.client, scene, folder, margin, bending,
                                           friction[len(scene.bodies):])
        self.notes.extend(self.soft.notes)
        h = scene.time_step_size
        automatic = deformables.substep_count(h, self.soft.omega)
        self.substeps = requested if requested > 0 else automatic
        pb.setPhysicsEngineParameter(fixedTimeStep=h / self.substeps, physicsClientId=self.client)
        self.settings.update({
            "world": "deformable (btDeformableMultiBodyDynamicsWorld)",
            "fixedTimeStep": h / self.substeps, "deformableSubsteps": self.substeps,
            "deformableSubstepsAutomatic": automatic,
            "omegaMaxBound": self.soft.omega,
            "particleCollisionMargin": margin, "bendingSpringStiffness": bending,
            "sparseSdfVoxelSize": deformables.SPARSE_SDF_VOXEL,
            "springDampingStiffness": 0.0, "NeoHookeanDamping": 0.0,
            "elasticForces": "explicit (Bullet's deformable world, m_implicit = false)",
            "particleVelocities": "(x_n - x_(n-1)) / h_s over the last internal step",
            "particleFriction": "soft body kDF x rigid lateralFriction (kDF x kDF between soft "
                                "bodies), factors whose products are the contactCombineRule values",
        })
        for m in self.soft.models:
            self.settings[f"{m.json_path}.nodeMass"] = m.node_mass
            self.settings[f"{m.json_path}.frictionCoeff"] = m.friction
        for kind, m in deformables.models(scene):
            if kind == "solid":
                young = float(m.material["stiffness"])
                poisson = float(m.material.get("poissonRatio", 0.3))
                mu_b, lambda_b = deformables.stable_neo_hookean(young, poisson)
                self.settings[f"{m.json_path}.NeoHookeanMu"] = mu_b
                self.settings[f"{m.json_path}.NeoHookeanLambda"] = lambda_b
            else:
                stiffness = float(m.material["stiffness"])
                self.settings[f"{m.json_path}.springElasticStiffness"] = stiffness

    def _world(self) -> None:
        c = self.client
        pb.setGravity(*self.scene.gravity, physicsClientId=c)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=self.scene.time_step_size, numSubSteps=0,
            numSolverIterations=self.iterations, constraintSolverType=self.solver,
            erp=self.erp, contactERP=self.contact_erp, frictionERP=self.erp,
            restitutionVelocityThreshold=0.0, useSplitImpulse=1,
            splitImpulsePenetrationThreshold=0.0, contactSlop=CONTACT_SLOP,
            enableConeFriction=0, deterministicOverlappingPairs=1, solverResidualThreshold=0.0,
            globalCFM=0.0, physicsClientId=c)

    def _bodies(self) -> None:
        c = self.client
        friction = material_factors(self.scene, "friction")
        restitution = material_factors(self.scene, "restitution")
        assert friction is not None and restitution is not None  # checked by unsupported_features
        for b in self.scene.bodies:
            shape, note = collision_shape(c, b)
            if note:
                self.notes.append(note)
            body = pb.createMultiBody(
                baseMass=b.mass if b.dynamic else 0.0, baseCollisionShapeIndex=shape,
                basePosition=list(b.scene_origin), baseOrientation=xyzw(b.rotation),
                baseInertialFramePosition=list(b.principal_com),
                baseInertialFrameOrientation=xyzw(b.principal_rotation),
                useMaximalCoordinates=True, physicsClientId=c)
            dynamics: dict[str, Any] = {
                "lateralFriction": friction[b.index], "restitution": restitution[b.index],
                "rollingFriction": 0.0, "spinningFriction": 0.0, "linearDamping": 0.0,
                "angularDamping": 0.0, "contactProcessingThreshold": 0.0,
                "activationState": pb.ACTIVATION_STATE_DISABLE_SLEEPING}
            if b.dynamic:
                # With `mass` given too: localInertiaDiagonal alone sets the mass of a
                # maximal-coordinate body to -1 (pybullet 3.2.7), and the first step gives NaN.
                dynamics["mass"] = b.mass
                dynamics["localInertiaDiagonal"] = list(b.principal_inertia)
            pb.changeDynamics(body, -1, physicsClientId=c, **dynamics)
            # Re-set the pose so that Bullet recomputes the world inertia from the new one
            # (setMassProps changes only the local inertia); pybullet reads and writes the base
            # pose as the principal frame of a maximal-coordinate body.
            position, orientation = pb.getBasePositionAndOrientation(body, physicsClientId=c)
            pb.resetBasePositionAndOrientation(body, position, orientation, physicsClientId=c)
            if shape < 0:  # no collision at all, as in the seed
                pb.setCollisionFilterGroupMask(body, -1, 0, 0, physicsClientId=c)
            if b.dynamic:
                pb.resetBaseVelocity(body, list(b.velocity), list(b.angular_velocity),
                                     physicsClientId=c)
            self.ids.append(body)

    def _point_to_point(self, joint: pp.Joint, offset: tuple[float, float, float]) -> None:
        """A point-to-point constraint at the anchor + offset (world, t = 0)."""
        b1, b2, local1, local2 = point_in_principal_frames(self.scene, joint, offset)
        cid = pb.createConstraint(self.ids[b1.index], -1, self.ids[b2.index], -1,
                                  pb.JOINT_POINT2POINT, [0, 0, 0], local1, local2,
                                  physicsClientId=self.client)
        pb.changeConstraint(cid, maxForce=UNLIMITED_FORCE, physicsClientId=self.client)

    def _joints(self) -> None:
        for j in self.scene.joints:
            if j.type == "ball":
                self._point_to_point(j, (0.0, 0.0, 0.0))
            elif j.type == "hinge":
                a = j.axes["axis"].world
                bodies = [self.scene.body_by_id(j.body1), self.scene.body_by_id(j.body2)]  # type: ignore[arg-type]
                half = hinge_half_length(bodies, j.points["anchor"].world, a)
                self.settings[f"{j.json_path}.pointSeparation"] = 2 * half
                for sign in (-1.0, 1.0):
                    self._point_to_point(j, tuple(sign * half * x for x in a))  # type: ignore[arg-type]
        self._jointed_bodies_collide()

    def _jointed_bodies_collide(self) -> None:
        """Jointed bodies collide with each other, as in the seed. createConstraint keeps their
        collisions already (Bullet's addConstraint without disableCollisionsBetweenLinkedBodies);
        the pair filter states it, independently of that default."""
        pairs = {p.bodies for p in self.scene.contact_pairs if self.scene.jointed(*p.bodies)}
        for id_a, id_b in sorted(pairs):
            a, b = self.scene.body_by_id(id_a), self.scene.body_by_id(id_b)
            pb.setCollisionFilterPair(self.ids[a.index], self.ids[b.index], -1, -1,
                                      enableCollision=1, physicsClientId=self.client)
        self.settings["jointedBodiesCollide"] = (
            f"yes (as in the seed): {len(pairs)} pairs of bodies connected by a joint "
            "(setCollisionFilterPair enableCollision=1)")

    def states(self, time: float) -> np.ndarray:
        """Every body's state as pybullet reports it: the inertial (principal) frame, x y z,
        qx qy qz qw, v, w; finish_states turns the whole trajectory's into the scene frame's
        state arrays (pp.state_array_rows' columns) when the run ends. pybullet reads a
        maximal-coordinate body's state in two calls and has no batched form: each body's four
        tuples, joined, fill its row of one array made when the run starts and filled again at
        every sample (simulate copies it before the next call)."""
        read = self._read
        c = self.client
        get_pose = pb.getBasePositionAndOrientation
        get_velocity = pb.getBaseVelocity
        for row, body in enumerate(self.ids):
            position, orientation = get_pose(body, c)
            velocity, angular = get_velocity(body, c)
            read[row] = position + orientation + velocity + angular
        return read

    def finish_states(self, read: np.ndarray) -> np.ndarray:
        """The scene frames' state arrays from `states`' (a whole trajectory's at once, pp.simulate's
        `finish_states`): the rotation of the principal frame times the conjugate of the
        principal rotation, position and velocities as they are."""
        return pp.principal_to_scene_states(read, self.principal_factors)

    def run(self, out_dir: Path) -> pp.Status:
        if self.soft is None:
            # The step is pybullet's function itself, its client bound: no Python frame per step.
            status = pp.simulate(self.scene, out_dir, functools.partial(pb.stepSimulation, self.client),
                                 self.states, finish_states=self.finish_states)
        else:
            status = self._run_with_particles(out_dir)
        status.engine_version = engine_version()
        status.effective_settings = self.settings
        status.integrator_steps_per_scene_step = self.substeps
        return status

    def _run_with_particles(self, out_dir: Path) -> pp.Status:
        """The protocol's loop with `substeps` internal steps per scene step; at a sample the
        positions before the last internal step give the velocities (pybullet 3.2.7 reads
        no node velocities): v_n = (x_n − x_(n−1)) / h_s."""
        soft = self.soft
        assert soft is not None
        sampled = set(self.scene.sample_steps())
        h_s = self.scene.time_step_size / self.substeps
        counter = [0]
        before: list[np.ndarray] = []
        initial = np.array([p.velocity for p in self.scene.particles], dtype=np.float64)

        def step() -> None:
            counter[0] += 1
            for _ in range(self.substeps - 1):
                pb.stepSimulation(physicsClientId=self.client)
            before.clear()
            if counter[0] in sampled:
                before.append(soft.positions())
            pb.stepSimulation(physicsClientId=self.client)

        def particles(time: float) -> np.ndarray:
            x = soft.positions()
            if counter[0] == 0:
                v = initial
            elif before:
                v = (x - before[0]) / h_s
            else:  # not a sample step: the velocity was not prepared
                v = np.full_like(x, np.nan)
            return np.hstack([x, v])

        return pp.simulate(self.scene, out_dir, step, self.states, particles=particles,
                           finish_states=self.finish_states)


def main(argv: list[str] | None = None) -> int:
    return pp.serve(argv, "pybullet as a pbdval external engine", unsupported_features,
                    run, engine_version())


def run(scene: pp.ResolvedScene, out: Path) -> pp.Status:
    if scene.method.name.startswith(MULTIBODY_PREFIX):
        from pbdval.external.pybullet import multibody  # imports this module

        return multibody.run(scene, out)
    if not deformables.has_deformables(scene):
        return PybulletRun(scene).run(out)
    # The soft bodies' meshes go to a scratch folder of our own, never into OUTDIR (tempfile
    # imported here: the runs without particles, and the server's start, do without it).
    import tempfile

    with tempfile.TemporaryDirectory(prefix="pbdval-pybullet-") as folder:
        return PybulletRun(scene, folder).run(out)
