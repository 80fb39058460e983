"""NVIDIA Newton as an external engine (protocol 1, docs/external-engines.md; mapping and
measurements: docs/engine-newton.md).

    .venv/bin/python -m pbdval.external.newton --scene RESOLVED.json --out OUTDIR

Warp runs its kernels on the CPU (no CUDA driver here); they are compiled on the first run into
the source tree's build/cache/warp (KERNEL_CACHE), not $HOME. Every dynamic body is a Newton
body whose frame is its principal frame (centre of mass at the origin, the principal inertia);
static bodies are static shapes (body -1) at their pose. Joints follow the spanning forest of
pbdval.external.joint_trees: a free joint at each tree of dynamic bodies' root, each tree joint
from its parent (or the world) at the anchor (a slider's at its child's centre), its frame
world-aligned at t = 0 (a slider's, and under SolverXPBD a hinge's, turned so that its x is the
joint's axis: Newton's XPBD bounds each coordinate of the axis in that frame) so that every joint coordinate starts
at 0. Contacts: Newton's collision pipeline once per scene step.
Methods: newton.xpbd (SolverXPBD), newton.featherstone, newton.semiImplicit; a run naming
newton.mujoco (SolverMuJoCo) is `unsupported` with features.MUJOCO_WARP_REASON.
State in float32, Warp's precision: positions carry ~6e-8 relative round-off.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from pbdval import protocol as pp
from pbdval.external import joint_trees
from pbdval.external.newton import catalogue, cloth
from pbdval.external.newton.catalogue import DEFAULT_METHOD, ENGINE
from pbdval.external.newton.features import MUJOCO_WARP, MUJOCO_WARP_REASON, SHAPES, TREE_JOINTS

#: Warp's kernel cache: the source tree's build/cache/warp (python/pbdval/external/newton/ → root).
KERNEL_CACHE = Path(__file__).resolve().parents[4] / "build" / "cache" / "warp"
#: The solvers with penalty contacts and explicit particle forces (tets among them).
PENALTY_SOLVERS = ("featherstone", "semiImplicit")
#: Relative agreement demanded of (m_a + m_b) / 2 with a pair's value (float32 state: 1e-6).
AVERAGE_TOLERANCE = 1e-6
#: A particle faster than this fraction of Newton's particle_max_velocity is at its clamp
#: (float32: the clamped speed reads back within 1e-6 of the limit).
PARTICLE_CLAMP_FRACTION = 0.999


def _import_newton() -> tuple[Any, Any]:
    """warp and newton, Warp told to compile into KERNEL_CACHE and to print nothing on stdout
    (the protocol keeps standard output empty)."""
    os.environ.setdefault("WARP_CACHE_PATH", str(KERNEL_CACHE))
    import warp as wp

    wp.config.kernel_cache_dir = str(KERNEL_CACHE)
    wp.config.log_level = wp.LOG_WARNING  # no start-up banner, no per-module load lines
    import newton

    return wp, newton


def solver_of(method: str) -> str | None:
    name = method or DEFAULT_METHOD
    prefix = f"{ENGINE}."
    suffix = name[len(prefix):] if name.startswith(prefix) else ""
    return suffix if suffix in catalogue.SOLVERS else None


def particle_pairs(scene: pp.ResolvedScene) -> list[tuple[int, int, float]]:
    """The particle-shape friction pairs (len(bodies), body index, the scene's value): Newton
    gives every particle one friction, soft_contact_mu, averaged with the shape's like a body's;
    the scene's value is the particle's model combined with the body by contactCombineRule."""
    particles = len(scene.bodies)
    return [(particles, b.index, pp.combine_friction(scene.contact_combine_rule, m.friction, b.material.friction))
            for m in (*scene.triangle_models, *scene.tet_models) for b in scene.bodies if b.shape.type != "none"]


def average_per_body(scene: pp.ResolvedScene, which: str) -> list[float] | None:
    """Per-body values m_i with (m_a + m_b) / 2 = the pair's value for every pair (Newton
    averages the two shapes' friction and restitution), by least squares, or None when the pairs
    are not of that form (or need a negative value). A body in no pair gets 0. For friction in
    a scene with particles, one more value, the particles' (particle_pairs), comes last."""
    index = {b.id: b.index for b in scene.bodies}
    pairs = [(index[p.bodies[0]], index[p.bodies[1]], float(getattr(p, which))) for p in scene.contact_pairs]
    values = [0.0] * len(scene.bodies)
    if which == "friction" and scene.particles:
        pairs += particle_pairs(scene)
        values.append(0.0)
    if not pairs:
        return values
    unknowns = sorted({b for i, j, _ in pairs for b in (i, j)})
    column = {b: k for k, b in enumerate(unknowns)}
    a = np.zeros((len(pairs), len(unknowns)))
    rhs = np.zeros(len(pairs))
    for row, (i, j, v) in enumerate(pairs):
        a[row, column[i]] += 0.5
        a[row, column[j]] += 0.5
        rhs[row] = v
    solution, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    for b, k in column.items():
        values[b] = float(solution[k])
    for i, j, v in pairs:
        if abs(0.5 * (values[i] + values[j]) - v) > AVERAGE_TOLERANCE * max(1.0, abs(v)):
            return None
    if any(v < -AVERAGE_TOLERANCE for v in values):
        return None
    return [max(v, 0.0) for v in values]


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    if scene.method.name == MUJOCO_WARP:
        return [f"method {MUJOCO_WARP}: {MUJOCO_WARP_REASON}"]
    if solver_of(scene.method.name) is None:
        return [f"method {scene.method.name}"]
    missing: list[str] = []
    for b in scene.bodies:
        if b.shape.type not in SHAPES:
            missing.append(f"{b.json_path}: shape {b.shape.type} (newton maps {', '.join(SHAPES)})")
        elif b.shape.inverted:
            missing.append(f"{b.json_path}: inverted shape (invertSDF)")
    for j in scene.joints:
        if j.type not in TREE_JOINTS:
            missing.append(f"{j.json_path}: joint {j.type} (newton maps {', '.join(sorted(TREE_JOINTS))})")
    missing += joint_trees.loop_messages(scene, joint_trees.plan_forest(scene, TREE_JOINTS), "Newton")
    missing += cloth.unsupported(scene, explicit=solver_of(scene.method.name) in PENALTY_SOLVERS)
    for which in ("friction", "restitution"):
        if average_per_body(scene, which) is None:
            missing.append(f"contact {which}: the pairs' values are not averages of per-body values "
                           f"(Newton averages the two shapes' {which})")
    return missing


def _rotation(q: pp.FloatVector) -> np.ndarray:
    w, x, y, z = (float(v) for v in q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _rotation_to(axis: pp.FloatVector, start: int) -> pp.Quat:
    """w, x, y, z of the shortest rotation taking the unit vector along coordinate `start`
    (0 x, 2 z) to `axis`; opposite vectors turn half a turn about x (from z) or z (from x)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    c = float(a[start])
    if c < -1 + 1e-12:
        half_turn = [0.0, 0.0, 0.0]
        half_turn[2 - start] = 1.0  # z → -z about x, x → -x about z
        return (0.0, half_turn[0], half_turn[1], half_turn[2])
    v = np.cross(np.eye(3)[start], a)
    return pp.quat_normalized((1 + c, float(v[0]), float(v[1]), float(v[2])))


def _z_to(axis: pp.FloatVector) -> pp.Quat:
    """The shortest rotation taking z to `axis` (Newton's cylinders lie along z)."""
    return _rotation_to(axis, 2)


def _x_to(axis: pp.FloatVector) -> pp.Quat:
    """The shortest rotation taking x to `axis`: the frame of a hinge or slider joint, whose
    axis Newton is given as the frame's x (see NewtonRun._joint)."""
    return _rotation_to(axis, 0)


class NewtonRun:
    def __init__(self, scene: pp.ResolvedScene) -> None:
        self.wp, self.newton = _import_newton()
        wp, newton = self.wp, self.newton
        self.scene = scene
        solver = solver_of(scene.method.name)
        assert solver is not None
        self.solver_name = solver

        def parameter(name: str) -> float:
            value = scene.parameter(name, catalogue.default(solver, name))
            if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
                raise ValueError(f"parameter {name}: expected a number >= 0, got {value!r}")
            return float(value)

        self.substeps = int(parameter("substeps"))
        if self.substeps < 1:
            raise ValueError(f"parameter substeps: expected >= 1, got {self.substeps}")
        friction = average_per_body(scene, "friction")
        restitution = average_per_body(scene, "restitution")
        assert friction is not None and restitution is not None
        penalty = solver in PENALTY_SOLVERS
        builder = newton.ModelBuilder(gravity=tuple(float(g) for g in scene.gravity))
        self.settings: dict[str, pp.ParameterValue] = {
            "method": f"{ENGINE}.{solver}", "solver": catalogue.SOLVERS[solver][0], "device": "cpu",
            "precision": "float32", "substeps": self.substeps, "kernelCache": str(KERNEL_CACHE),
            "frictionCombination": "average", "restitutionCombination": "average",
            "jointedBodiesCollide": "yes (collision_filter_parent off on every joint)",
        }
        shape_config: dict[str, float] = {"margin": 0.0}
        if penalty:
            shape_config["ke"] = parameter("contactStiffness")
            shape_config["kd"] = parameter("contactDamping")
            self.settings["contactStiffness"] = shape_config["ke"]
            self.settings["contactDamping"] = shape_config["kd"]
        self.forest = joint_trees.plan_forest(scene, TREE_JOINTS)
        self.body_of: dict[int, int] = {}  # scene body index → Newton body
        for b in self.forest.order:
            body = scene.bodies[b]
            self.body_of[b] = builder.add_link(
                xform=self._transform(body.position, body.world_principal_rotation), com=wp.vec3(0.0, 0.0, 0.0),
                inertia=wp.mat33(*np.diag(np.asarray(body.principal_inertia, dtype=float)).flatten()),
                mass=body.mass, lock_inertia=True, label=f"body{b}")
        for body in scene.bodies:
            config = builder.ShapeConfig(mu=friction[body.index], restitution=restitution[body.index],
                                         density=0.0, **shape_config)
            self._shape(builder, body, config)
        joints = []
        for b in self.forest.order:
            tree_joint = self.forest.parent_joint.get(b)
            if tree_joint is None:
                joints.append(builder.add_joint_free(self.body_of[b], collision_filter_parent=False))
            else:
                joints.append(self._joint(builder, tree_joint))
        if joints:
            builder.add_articulation(joints)
        if scene.particles:
            self.particles = cloth.add_particles(
                builder, wp.vec3, scene, cloth.EXPLICIT_BENDING if penalty else cloth.XPBD_BENDING,
                parameter("clothBendingCurvature"), self.settings)
        self.model = builder.finalize(device="cpu")
        self.state, self.next_state = self.model.state(), self.model.state()
        self.control = self.model.control()
        if scene.particles:
            # One friction for every particle (Newton averages it with the shape's, as a body's).
            self.model.soft_contact_mu = friction[len(scene.bodies)]
            self.settings["particleFriction"] = self.model.soft_contact_mu
            self.settings["particleContactGap"] = scene.contact_tolerance
            self.settings["particleRestitution"] = "0: Newton's soft contacts here are inelastic (approximated)"
            if penalty:  # the particle's half of the averaged penalty equal to the shapes'
                self.model.soft_contact_ke = shape_config["ke"]
                self.model.soft_contact_kd = shape_config["kd"]
            self.pipeline = newton.CollisionPipeline(self.model, soft_contact_gap=scene.contact_tolerance)
        else:
            self.pipeline = newton.CollisionPipeline(self.model)
        self.contacts = self.pipeline.contacts() if hasattr(self.pipeline, "contacts") else self.model.contacts()
        damping = parameter("angularDamping")
        self.settings["angularDamping"] = damping
        if solver == "xpbd":
            iterations = int(parameter("iterations"))
            if iterations < 1:
                raise ValueError(f"parameter iterations: expected >= 1, got {iterations}")
            linear, angular = parameter("jointLinearRelaxation"), parameter("jointAngularRelaxation")
            self.solver = newton.solvers.SolverXPBD(self.model, iterations=iterations, angular_damping=damping,
                                                    joint_linear_relaxation=linear,
                                                    joint_angular_relaxation=angular,
                                                    enable_restitution=any(r > 0 for r in restitution))
            self.settings["iterations"] = iterations
            self.settings["jointLinearRelaxation"] = linear
            self.settings["jointAngularRelaxation"] = angular
            self.settings["enableRestitution"] = any(r > 0 for r in restitution)
        elif solver == "featherstone":
            self.solver = newton.solvers.SolverFeatherstone(self.model, angular_damping=damping)
        else:
            ke, kd = parameter("jointStiffness"), parameter("jointDamping")
            self.solver = newton.solvers.SolverSemiImplicit(self.model, angular_damping=damping,
                                                            joint_attach_ke=ke, joint_attach_kd=kd)
            self.settings["jointStiffness"], self.settings["jointDamping"] = ke, kd
        self._initial_state()

    # --- building ---------------------------------------------------------------------------

    def _transform(self, position: pp.FloatVector, rotation: pp.FloatVector) -> Any:
        w, x, y, z = (float(v) for v in rotation)
        return self.wp.transform(self.wp.vec3(*(float(p) for p in position)), self.wp.quat(x, y, z, w))

    def _shape(self, builder: Any, body: pp.Body, config: Any) -> None:
        s = body.shape
        if s.type == "none":
            return
        # the scene frame in the principal frame (dynamic bodies) or in world (static ones)
        principal = _rotation(body.principal_rotation)
        in_body = pp.quat_conjugate(body.principal_rotation)
        offset = -principal.T @ np.asarray(body.principal_com, dtype=float)
        if body.dynamic:
            owner = self.body_of[body.index]
        else:
            owner = -1
            offset = np.asarray(body.scene_origin, dtype=float)
            in_body = body.rotation
        if s.type == "cylinder":
            assert s.axis is not None
            in_body = pp.quat_multiply(in_body, _z_to(s.axis))
        xform = self._transform(offset, in_body)
        if s.type == "sphere":
            builder.add_shape_sphere(owner, xform=xform, radius=s.radius, cfg=config)
        elif s.type == "box":
            assert s.half_extents is not None
            hx, hy, hz = s.half_extents
            builder.add_shape_box(owner, xform=xform, hx=hx, hy=hy, hz=hz, cfg=config)
        else:
            assert s.height is not None
            builder.add_shape_cylinder(owner, xform=xform, radius=s.radius, half_height=0.5 * s.height, cfg=config)

    def _joint(self, builder: Any, tree_joint: joint_trees.TreeJoint) -> int:
        newton, wp = self.newton, self.wp
        j = self.scene.joints[tree_joint.joint]
        anchor = j.points["anchor"].world if "anchor" in j.points else j.points["anchor1"].world
        identity = (1.0, 0.0, 0.0, 0.0)
        child_body = self.scene.bodies[tree_joint.child]
        child = self.body_of[tree_joint.child]
        if j.type == "slider":
            # A slider locks the relative rotation, so every point of the child moves on a line
            # parallel to the axis: the line through the child's centre is the same joint. With
            # the scene's anchor (joint_slider's is the origin, 1.7 m from the box) SolverXPBD's
            # position row acts through that lever arm on the rotation its angular row holds,
            # and two iterations leave the box 7 cm off the line in 1 s; at the centre the row
            # moves the box alone.
            anchor = child_body.position

        # The joint frame: at the anchor; for a slider, and a hinge under SolverXPBD, its x
        # along the joint's axis, else the world's axes. SolverXPBD bounds each joint
        # coordinate by the box [min(a·lower, a·upper), max(a·lower, a·upper)] per component of
        # the axis a in this frame (solve_body_joints): an axis off the frame's x, y or z, e.g.
        # joint_slider's (1, -1, 0)/√2, unlimited, frees both components it has — the slider
        # then fell 3.2 m off its line in 1 s — and an axis along x frees x alone.
        # SolverSemiImplicit's revolute joint diverged within three steps in a turned frame on
        # double_pendulum (world-aligned: ok; its penalty form has no box), so its hinges keep
        # the world's axes.
        turned = j.type == "slider" or (j.type == "hinge" and self.solver_name == "xpbd")
        frame = _x_to(j.axes["axis"].world) if turned else identity

        def local(body: pp.Body) -> Any:  # the joint frame in the body's frame
            rotation = _rotation(body.world_principal_rotation)
            point = rotation.T @ (np.asarray(anchor, dtype=float) - np.asarray(body.position, dtype=float))
            return self._transform(point, pp.quat_multiply(pp.quat_conjugate(body.world_principal_rotation), frame))

        if tree_joint.parent == joint_trees.WORLD:
            parent, parent_xform = -1, self._transform(anchor, frame)
        else:
            parent, parent_xform = self.body_of[tree_joint.parent], local(self.scene.bodies[tree_joint.parent])
        common = {"parent_xform": parent_xform, "child_xform": local(child_body), "collision_filter_parent": False}
        if j.type in ("hinge", "slider"):
            add = builder.add_joint_revolute if j.type == "hinge" else builder.add_joint_prismatic
            axis = wp.vec3(1.0, 0.0, 0.0) if turned else wp.vec3(*(float(a) for a in j.axes["axis"].world))
            return int(add(parent, child, axis=axis, **common))
        if j.type == "ball":
            return int(builder.add_joint_ball(parent, child, **common))
        first, second = ("axis2", "axis1") if tree_joint.flipped else ("axis1", "axis2")
        dof = newton.ModelBuilder.JointDofConfig
        axes = [dof(axis=wp.vec3(*(float(a) for a in j.axes[k].world))) for k in (first, second)]
        return int(builder.add_joint_d6(parent, child, angular_axes=axes, **common))

    def _initial_state(self) -> None:
        """body_q, body_qd from the scene; the joint coordinates from them (eval_ik), and for
        Featherstone (reduced coordinates) the bodies again from the joints (eval_fk)."""
        newton = self.newton
        if not self.body_of:  # particles only: Newton has no body arrays
            return
        q = self.state.body_q.numpy()
        qd = self.state.body_qd.numpy()
        for b, n in self.body_of.items():
            body = self.scene.bodies[b]
            w, x, y, z = body.world_principal_rotation
            q[n] = [*body.position, x, y, z, w]
            qd[n] = [*body.velocity, *body.angular_velocity]
        self.state.body_q.assign(q)
        self.state.body_qd.assign(qd)
        if self.model.joint_count:
            newton.eval_ik(self.model, self.state, self.state.joint_q, self.state.joint_qd)
            if self.solver_name == "featherstone":
                newton.eval_fk(self.model, self.state.joint_q, self.state.joint_qd, self.state)

    # --- running ----------------------------------------------------------------------------

    def step(self) -> None:
        h = self.scene.time_step_size / self.substeps
        self.pipeline.collide(self.state, self.contacts)
        for _ in range(self.substeps):
            self.state.clear_forces()
            self.solver.step(self.state, self.next_state, self.control, self.contacts, h)
            self.state, self.next_state = self.next_state, self.state

    def initial_states(self) -> list[pp.BodyState]:
        return [pp.BodyState(b.id, np.asarray(b.position, dtype=float), b.rotation, list(b.velocity),
                             list(b.angular_velocity)) for b in self.scene.bodies]

    def states(self) -> list[pp.BodyState]:
        if not self.body_of:  # no dynamic body (a cloth alone, or on static shapes): no body_q
            return self.initial_states()
        q = self.state.body_q.numpy().astype(float)
        qd = self.state.body_qd.numpy().astype(float)
        out = []
        for body in self.scene.bodies:
            n = self.body_of.get(body.index)
            if n is None:
                out.append(pp.BodyState(body.id, np.asarray(body.position, dtype=float), body.rotation,
                                        [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]))
                continue
            x, y, z, w = q[n, 3:7]
            principal = pp.quat_normalized((w, x, y, z))
            rotation = pp.quat_normalized(pp.quat_multiply(principal, pp.quat_conjugate(body.principal_rotation)))
            out.append(pp.BodyState(body.id, q[n, 0:3].copy(), rotation,
                                    [float(v) for v in qd[n, 0:3]], [float(v) for v in qd[n, 3:6]]))
        return out

    def particle_states(self) -> np.ndarray:
        """(P, 6): every particle's position and velocity in scene order (Newton's order)."""
        out = np.empty((len(self.scene.particles), 6))
        out[:, :3] = self.state.particle_q.numpy()
        out[:, 3:] = self.state.particle_qd.numpy()
        return out

    def initial_particle_states(self) -> np.ndarray:
        """The scene's particles as given (static ones at rest)."""
        return np.array([[*p.position, *((0.0, 0.0, 0.0) if p.mass <= 0 else p.velocity)]
                         for p in self.scene.particles], dtype=float).reshape(-1, 6)

    def run(self, out_dir: Path) -> pp.Status:
        def check(t: float) -> str | None:
            if self.scene.particles:
                # Newton clamps every particle's speed to particle_max_velocity (1e5 m/s), below
                # the runner's divergence limit: a particle at the clamp has diverged.
                limit = float(self.model.particle_max_velocity)
                speed = float(np.linalg.norm(self.state.particle_qd.numpy(), axis=1).max())
                if not speed < PARTICLE_CLAMP_FRACTION * limit:
                    return (f"a particle at Newton's speed clamp ({speed:g} m/s, particle_max_velocity "
                            f"{limit:g}) at t = {t:g} s")
            if not self.body_of:
                return None
            q, qd = self.state.body_q.numpy(), self.state.body_qd.numpy()
            if not (np.isfinite(q).all() and np.isfinite(qd).all()):
                return f"non-finite state at t = {t:g} s"
            if max(float(np.abs(q[:, 0:3]).max()), float(np.abs(qd).max())) > pp.DIVERGENCE_LIMIT:
                return f"a position or speed beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            return None

        def states(t: float) -> list[pp.BodyState]:
            # t = 0: the scene's state as given; Newton holds it rounded to float32 (up to 6e-8
            # relative), which the runner's check of the first sample would read as another state.
            return self.initial_states() if t == 0 else self.states()

        def particles(t: float) -> np.ndarray:  # t = 0: as given, like the bodies
            return self.initial_particle_states() if t == 0 else self.particle_states()

        status = pp.simulate(self.scene, out_dir, self.step, states, check=check,
                             particles=particles if self.scene.particles else None)
        status.engine_version = engine_version()
        status.effective_settings = self.settings
        status.integrator_steps_per_scene_step = self.substeps
        status.contact_margin = 0.0
        status.initial_velocities_projected = self.solver_name == "featherstone"
        return status


def engine_version() -> str:
    return f"newton {catalogue.NEWTON_VERSION}, warp-lang {catalogue.WARP_VERSION} (CPU)"



def main(argv: list[str] | None = None) -> int:
    return pp.serve(argv, "NVIDIA Newton as a pbdval external engine", unsupported_features,
                    lambda scene, out: NewtonRun(scene).run(out), engine_version())
