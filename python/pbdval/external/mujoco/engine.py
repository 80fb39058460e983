"""MuJoCo (the Python package, 4.x) as an external engine (protocol 1,
docs/external-engines.md; parity rules: docs/external-engines.md#mujoco-python).

    .venv/bin/python -m pbdval.external.mujoco --scene RESOLVED.json --out OUTDIR

The model is built with mujoco.MjSpec (no MJCF text), with the parity rules of the built-in
`mujoco` engine (adapters/mujoco/, MuJoCo 2.2.2): every body's frame is its principal frame at
t = 0 with the scene's mass and principal inertia given explicitly; free bodies get a free
joint; ball and hinge joints form the kinematic tree (a joint whose child already has a parent
would close a loop: unsupported here); every contact pair of the scene is an explicit <pair>
(contype = conaffinity = 0) with the pair's friction and a direct solref whose Kelvin-Voigt
rebound is the pair's restitution (contact_law.py); margin and gap 0; no damping.
Particles of triangle models (cloth) and tet models (solids) are MuJoCo flexes, one body with
three slide joints per dynamic particle (flexes.py). Elastic flex forces are explicit in every
integrator but `discrete` (implicit in position): under the others a scene step is split into
internal steps below the stability limit of the stiffest elastic mode (parameter `substeps`).
Methods: mujoco-python.<integrator>.<solver>, integrator euler, rk4, implicit, implicitfast,
discrete and solver newton, cg, pgs.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np

import mujoco

from pbdval import protocol as pp
from pbdval.external.mujoco import catalogue, contact_law, flexes
from pbdval.external.mujoco.catalogue import DEFAULT_METHOD, ENGINE

INTEGRATORS = {
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "rk4": mujoco.mjtIntegrator.mjINT_RK4,
    "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
    "discrete": mujoco.mjtIntegrator.mjINT_DISCRETE,
}
SOLVERS = {
    "newton": mujoco.mjtSolver.mjSOL_NEWTON,
    "cg": mujoco.mjtSolver.mjSOL_CG,
    "pgs": mujoco.mjtSolver.mjSOL_PGS,
}
CONES = {"elliptic": mujoco.mjtCone.mjCONE_ELLIPTIC, "pyramidal": mujoco.mjtCone.mjCONE_PYRAMIDAL}
SUPPORTED_JOINTS = ("ball", "hinge")
SUPPORTED_SHAPES = ("none", "sphere", "box", "cylinder", "sdf")
#: Constant impedance of contacts (solimp d0 = d_width), as the built-in engine.
SOLIMP = [0.99, 0.99, 0.001, 0.5, 2.0]


def engine_version() -> str:
    return f"mujoco {mujoco.__version__} (Python)"


def method_parts(name: str) -> tuple[str, str] | None:
    parts = (name or DEFAULT_METHOD).split(".")
    if len(parts) != 3 or parts[0] != ENGINE or parts[1] not in INTEGRATORS or parts[2] not in SOLVERS:
        return None
    return parts[1], parts[2]


def tree(scene: pp.ResolvedScene) -> tuple[dict[int, tuple[int | None, pp.Joint | None]], list[str]]:
    """Parent of every dynamic body (body index → (parent index or None for the world, the joint
    to it or None for a free joint)), and the joints that do not fit a tree."""
    parent: dict[int, tuple[int | None, pp.Joint | None]] = {}
    problems: list[str] = []

    def ancestors(i: int | None) -> set[int]:
        seen: set[int] = set()
        while i is not None and i in parent:
            seen.add(i)
            i = parent[i][0]
        return seen

    for j in scene.joints:
        if j.type not in SUPPORTED_JOINTS or j.body1 is None or j.body2 is None:
            continue
        a, b = scene.body_by_id(j.body1), scene.body_by_id(j.body2)
        if not a.dynamic and not b.dynamic:
            continue
        candidates = [(b, a), (a, b)] if b.dynamic else [(a, b)]
        if not a.dynamic:
            candidates = [(b, a)]
        placed = False
        for child, par in candidates:
            par_index = par.index if par.dynamic else None
            if child.index in parent or (par_index is not None and child.index in ancestors(par_index)):
                continue
            parent[child.index] = (par_index, j)
            placed = True
            break
        if not placed:
            problems.append(f"{j.json_path}: closes a kinematic loop (equality constraints are not "
                            "implemented in this engine)")
    for b in scene.bodies:
        if b.dynamic and b.index not in parent:
            parent[b.index] = (None, None)
    return parent, problems


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    missing: list[str] = []
    if method_parts(scene.method.name) is None:
        missing.append(f"method {scene.method.name}")
    for j in scene.joints:
        if j.type not in SUPPORTED_JOINTS:
            missing.append(f"{j.json_path}: joint {j.type}")
    missing += tree(scene)[1]
    parents = tree(scene)[0]
    for b in scene.bodies:
        if b.shape.type not in SUPPORTED_SHAPES:
            missing.append(f"{b.json_path}: shape {b.shape.type}")
        elif b.shape.inverted:
            missing.append(f"{b.json_path}: inverted shape (invertSDF)")
        elif b.shape.type == "sdf" and not b.geometry_file:
            missing.append(f"{b.json_path}: sdf without a geometry file")
        parent, joint = parents.get(b.index, (None, None))
        if b.dynamic and joint is not None and parent is not None and (
                any(b.velocity) or any(b.angular_velocity)):
            missing.append(f"{b.json_path}: initial velocity of a body jointed to a moving body")
    if scene.particles or scene.triangle_models or scene.tet_models:
        missing += flexes.unsupported(scene)
        parts = method_parts(scene.method.name)
        if parts is not None and parts[0] in ("implicit", "implicitfast"):
            missing.append(f"method {scene.method.name} with particles: MuJoCo 4 refuses flex "
                           "elasticity under implicit and implicitfast (use discrete, euler or rk4)")
        if parts == ("discrete", "pgs"):
            missing.append(f"method {scene.method.name} with particles: MuJoCo's discrete "
                           "integrator needs the Newton or CG solver for flex elasticity")
    return missing


def _matrix(q: "pp.Quat") -> list[list[float]]:
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def relative_pose(parent: pp.Body | None, child: pp.Body) -> tuple[list[float], list[float]]:
    """The child's principal frame in its parent's principal frame (world when None)."""
    if parent is None:
        return list(child.position), list(child.world_principal_rotation)
    inv = pp.quat_conjugate(parent.world_principal_rotation)
    d = [c - p for c, p in zip(child.position, parent.position)]
    return list(pp.quat_rotate(inv, d)), list(pp.quat_multiply(inv, child.world_principal_rotation))


class MujocoRun:
    def __init__(self, scene: pp.ResolvedScene) -> None:
        self.scene = scene
        parts = method_parts(scene.method.name)
        assert parts is not None
        integrator, solver = parts
        h = scene.time_step_size
        # The catalogue's defaults (catalogue.py; `discrete` has more iterations).
        def parameter(name: str) -> pp.ParameterValue:
            return scene.parameter(name, catalogue.default(integrator, name))

        self.iterations = int(parameter("iterations"))
        self.tolerance = float(parameter("tolerance"))
        cone = str(parameter("cone"))
        if cone not in CONES:
            raise ValueError(f"parameter cone: expected one of {', '.join(CONES)}, got {cone!r}")
        tau_steps = float(parameter("contactTimeconstSteps"))
        if tau_steps < 2:
            raise ValueError(f"parameter contactTimeconstSteps: expected >= 2 (MuJoCo raises a "
                             f"shorter time constant to 2h), got {tau_steps}")
        self.tau = tau_steps * h
        requested_substeps = int(parameter("substeps"))
        if requested_substeps < 0:
            raise ValueError(f"parameter substeps: expected >= 0 (0: automatic), got {requested_substeps}")
        self.settings: dict[str, pp.ParameterValue] = {
            "method": f"{ENGINE}.{integrator}.{solver}", "integrator": integrator, "solver": solver,
            "iterations": self.iterations, "tolerance": self.tolerance, "cone": cone,
            "contactTimeconst": self.tau, "solimp": " ".join(str(v) for v in SOLIMP),
            "margin": 0.0, "gap": 0.0, "damping": 0.0,
        }
        spec = mujoco.MjSpec()
        spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
        spec.compiler.boundmass = 0.0
        spec.compiler.boundinertia = 0.0
        spec.compiler.balanceinertia = False
        spec.option.timestep = h
        spec.option.gravity = list(scene.gravity)
        spec.option.integrator = INTEGRATORS[integrator]
        spec.option.solver = SOLVERS[solver]
        spec.option.iterations = self.iterations
        spec.option.tolerance = self.tolerance
        spec.option.cone = CONES[cone]
        # Jointed bodies collide (the seed's rule): the rigid pairs are explicit <pair>s, which
        # MuJoCo never filters; filterparent is disabled as well, as in the built-in adapter.
        spec.option.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_FILTERPARENT)
        self.body_names: list[str] = [f"body{b.index}" for b in scene.bodies]
        self.geom_names: dict[int, str] = {}
        self.parents, _ = tree(scene)
        self._add_bodies(spec)
        self._add_pairs(spec)
        bending_curvature = float(parameter("clothBendingCurvature"))
        if bending_curvature < 0:
            raise ValueError("parameter clothBendingCurvature: expected >= 0 (0: no bending), "
                             f"got {bending_curvature}")
        self.layout = flexes.add_flexes(spec, scene, self._flex_contact, self.settings, bending_curvature)
        with warnings.catch_warnings():
            # MuJoCo 4.0.0 warns that a flex with elasticity but no edge equality "has no
            # equality constraints or passive forces"; its elasticity is there (tested).
            warnings.filterwarnings("ignore", message=".*has no equality constraints or passive forces")
            self.model = spec.compile()
        self.data = mujoco.MjData(self.model)
        self._initial_velocities()
        self.layout.resolve(self.model)
        for i, d in zip(self.layout.dynamic, self.layout.dofs):
            self.data.qvel[d] = scene.particles[i].velocity
        mujoco.mj_forward(self.model, self.data)
        mismatch = flexes.state_matches(self.data, self.layout)
        if mismatch != 0.0:
            raise RuntimeError("flex vertices are not the scene's particles at t = 0 "
                               f"(off by {mismatch:g} m)")
        self.body_ids = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, n)
                         for n in self.body_names]
        self.substeps = self._substeps(integrator, requested_substeps)
        self.model.opt.timestep = h / self.substeps
        self.settings["substeps"] = self.substeps
        self.settings["timestep"] = h / self.substeps

    def _substeps(self, integrator: str, requested: int) -> int:
        """Internal steps per scene step: as requested, else 1 without particles or under
        `discrete` (elasticity implicit in position), else from the stiffest elastic mode."""
        if not len(self.layout.dynamic) or integrator == "discrete":
            return requested or 1
        omega = flexes.highest_frequency(self.model, self.data, self.layout)
        self.settings["elasticOmegaMax"] = omega
        return requested or flexes.explicit_substeps(omega, self.scene.time_step_size)

    def _flex_contact(self, model: pp.TriangleModel | pp.TetModel) -> tuple[list[float], list[float]]:
        """solref, solimp of a particle model's contacts: the rigid pairs' law with its restitution."""
        law = contact_law.contact_solref(self.tau, self.scene.time_step_size, model.restitution)
        return [-law.stiffness, -law.damping], list(SOLIMP)

    def _add_geom(self, mj_body: "mujoco.MjsBody", b: pp.Body, spec: "mujoco.MjSpec") -> None:
        s = b.shape
        if s.type == "none":
            return
        # The shape is given in the scene frame; the body frame is the principal frame.
        to_principal = pp.quat_conjugate(b.principal_rotation)
        pos = pp.quat_rotate(to_principal, [-c for c in b.principal_com])
        quat = to_principal
        name = f"geom{b.index}"
        # Rigid pairs are explicit <pair>s; particles (flexes) collide through the affinity bit.
        affinity = flexes.FLEX_CONTACT_BIT if self.scene.particles else 0
        geom = mj_body.add_geom(name=name, contype=0, conaffinity=affinity, margin=0.0, gap=0.0)
        if s.type == "sphere":
            geom.type = mujoco.mjtGeom.mjGEOM_SPHERE
            geom.size = [s.radius, 0, 0]
        elif s.type == "box":
            geom.type = mujoco.mjtGeom.mjGEOM_BOX
            geom.size = list(s.half_extents)
        elif s.type == "cylinder":
            geom.type = mujoco.mjtGeom.mjGEOM_CYLINDER
            geom.size = [s.radius, s.height / 2, 0]
            half = math.sqrt(0.5)  # MuJoCo's cylinder runs along z, the scene's along y
            quat = pp.quat_multiply(quat, (half, -half, 0.0, 0.0))
        else:  # sdf: the body's mesh, which MuJoCo collides as its convex hull
            mesh = spec.add_mesh(name=f"mesh{b.index}", file=b.geometry_file,
                                 scale=list(b.geometry_scale or (1, 1, 1)))
            geom.type = mujoco.mjtGeom.mjGEOM_MESH
            geom.meshname = mesh.name
            self.settings[f"{b.json_path}.shape"] = "convex hull of the mesh"
        geom.pos = list(pos)
        geom.quat = list(quat)
        self.geom_names[b.index] = name

    def _add_bodies(self, spec: "mujoco.MjSpec") -> None:
        scene = self.scene
        children: dict[int | None, list[int]] = {}
        for index, (par, _) in self.parents.items():
            children.setdefault(par, []).append(index)
        for b in scene.bodies:  # static bodies: welded to the world
            if not b.dynamic:
                body = spec.worldbody.add_body(name=self.body_names[b.index], pos=list(b.position),
                                               quat=list(b.world_principal_rotation))
                self._add_geom(body, b, spec)

        def add(mj_parent: "mujoco.MjsBody", parent: pp.Body | None, index: int) -> None:
            b = scene.bodies[index]
            pos, quat = relative_pose(parent, b)
            body = mj_parent.add_body(name=self.body_names[index], pos=pos, quat=quat,
                                      mass=b.mass, inertia=list(b.principal_inertia),
                                      ipos=[0, 0, 0], iquat=[1, 0, 0, 0], explicitinertial=True)
            joint = self.parents[index][1]
            if joint is None:
                body.add_freejoint()
            else:
                side = "body1" if joint.body1 == b.id else "body2"
                anchor = getattr(joint.points["anchor"], side).principal
                if joint.type == "ball":
                    body.add_joint(type=mujoco.mjtJoint.mjJNT_BALL, pos=list(anchor), damping=0.0)
                else:
                    axis = getattr(joint.axes["axis"], side).principal
                    # Seen from its first body, the joint turns the other way round.
                    sign = -1.0 if side == "body1" else 1.0
                    body.add_joint(type=mujoco.mjtJoint.mjJNT_HINGE, pos=list(anchor),
                                   axis=[sign * a for a in axis], damping=0.0)
            self._add_geom(body, b, spec)
            for c in children.get(index, []):
                add(body, b, c)

        for index in children.get(None, []):
            add(spec.worldbody, None, index)

    def _add_pairs(self, spec: "mujoco.MjSpec") -> None:
        h = self.scene.time_step_size
        jointed = 0
        for p in self.scene.contact_pairs:
            a, b = self.scene.body_by_id(p.bodies[0]), self.scene.body_by_id(p.bodies[1])
            if a.index not in self.geom_names or b.index not in self.geom_names:
                continue
            jointed += self.scene.jointed(a.id, b.id)
            law = contact_law.contact_solref(self.tau, h, p.restitution)
            spec.add_pair(geomname1=self.geom_names[a.index], geomname2=self.geom_names[b.index],
                          condim=3, friction=[p.friction, p.friction, 0.0, 0.0, 0.0],
                          solref=[-law.stiffness, -law.damping], solimp=SOLIMP, margin=0.0, gap=0.0)
        self.settings["jointedBodiesCollide"] = (
            f"yes (as in the seed): {jointed} of the pairs join bodies connected by a joint; "
            "explicit <pair>s, which MuJoCo never filters, and filterparent disabled")

    def _initial_velocities(self) -> None:
        for b in self.scene.bodies:
            if not b.dynamic:
                continue
            body_id = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, self.body_names[b.index])
            dof = self.model.jnt_dofadr[self.model.body_jntadr[body_id]]
            joint = self.parents[b.index][1]
            if joint is not None:
                if any(b.velocity) or any(b.angular_velocity):
                    self._jointed_initial_velocity(b, joint, dof)
                continue
            # A free joint's qvel: linear velocity in world, angular velocity in body axes.
            local_w = pp.quat_rotate(pp.quat_conjugate(b.world_principal_rotation), b.angular_velocity)
            self.data.qvel[dof:dof + 3] = b.velocity
            self.data.qvel[dof + 3:dof + 6] = local_w

    def _jointed_initial_velocity(self, b: pp.Body, joint: pp.Joint, dof: int) -> None:
        """A body jointed to the world whose scene velocity (v, w) need not fit the joint: the
        nearest joint motion in the kinetic-energy norm, minimising m|v - W x r|^2 +
        (w - W)^T I (w - W) over the joint's angular velocities W (r from the pivot to the centre
        of mass), which gives I_p W = L_p: the angular momentum about the pivot is kept (the
        built-in engine's projection, docs/parity-mujoco.md). Ball: W free; hinge: W = s a."""
        rotation = np.array(_matrix(b.world_principal_rotation))
        inertia = rotation @ np.diag(b.principal_inertia) @ rotation.T
        r = np.array(b.position) - np.array(joint.points["anchor"].world)
        inertia_pivot = inertia + b.mass * (float(r @ r) * np.eye(3) - np.outer(r, r))
        momentum = inertia @ np.array(b.angular_velocity) + b.mass * np.cross(r, np.array(b.velocity))
        if joint.type == "ball":
            w = np.linalg.solve(inertia_pivot, momentum)
            self.data.qvel[dof:dof + 3] = rotation.T @ w  # MuJoCo's ball qvel is in body axes
        else:
            side = "body1" if joint.body1 == b.id else "body2"
            axis = np.array(joint.axes["axis"].world) * (-1.0 if side == "body1" else 1.0)
            w = axis * float(axis @ momentum) / float(axis @ inertia_pivot @ axis)
            self.data.qvel[dof] = float(axis @ w)
        fitted = (np.cross(w, r), w)
        self.settings[f"{b.json_path}.initialVelocity"] = (
            "projected onto the joint (kinetic-energy norm): v = " + " ".join(f"{x:.6g}" for x in fitted[0])
            + ", w = " + " ".join(f"{x:.6g}" for x in fitted[1]))

    def states(self) -> list[pp.BodyState]:
        out = []
        velocity = np.zeros(6)
        for b, body_id in zip(self.scene.bodies, self.body_ids):
            mujoco.mj_objectVelocity(self.model, self.data, mujoco.mjtObj.mjOBJ_BODY, body_id,
                                     velocity, 0)
            q = pp.quat_multiply(self.data.xquat[body_id], pp.quat_conjugate(b.principal_rotation))
            out.append(pp.BodyState(b.id, self.data.xpos[body_id].copy(), q,
                                    velocity[3:].copy(), velocity[:3].copy()))
        return out

    def run(self, out_dir: Path) -> pp.Status:
        bad_qacc = int(mujoco.mjtWarning.mjWARN_BADQACC)

        def failure(t: float) -> str | None:
            if self.data.warning[bad_qacc].number > 0:
                return f"MuJoCo reset the state after a bad acceleration at t = {t:g} s"
            return None

        def check(t: float) -> str | None:
            # Between samples: the runner's limits on the generalised state, vectorised (a free
            # body's qpos holds its position, its qvel its linear and angular velocity).
            qpos, qvel = self.data.qpos, self.data.qvel
            if not (np.isfinite(qpos).all() and np.isfinite(qvel).all()):
                return f"non-finite state at t = {t:g} s"
            if qpos.size and np.abs(qpos).max() > pp.DIVERGENCE_LIMIT:
                return f"a coordinate beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            if qvel.size and np.abs(qvel).max() > pp.DIVERGENCE_LIMIT:
                return f"a speed beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            return None

        def states(t: float) -> list[pp.BodyState]:
            # mj_step leaves xpos, xquat and cvel at the start of the step (they are computed
            # before the integration); recompute them for the new state. mj_forward changes no
            # state and no warm start, so sampling does not change the trajectory.
            if t > 0:
                mujoco.mj_forward(self.model, self.data)
            return self.states()

        def step() -> None:
            for _ in range(self.substeps):
                mujoco.mj_step(self.model, self.data)

        particles = (lambda t: self.layout.state(self.data)) if self.scene.particles else None
        status = pp.simulate(self.scene, out_dir, step, states, failure, check, particles=particles)
        status.engine_version = engine_version()
        status.effective_settings = self.settings
        inertia_warnings = self.data.warning[int(mujoco.mjtWarning.mjWARN_INERTIA)].number
        if inertia_warnings:
            # Under `discrete`: the iterative solve of M + h^2 K stopped at `iterations` above
            # `tolerance` (MuJoCo's message); recorded, not a failure.
            self.settings["inertiaWarnings"] = int(inertia_warnings)
        status.integrator_steps_per_scene_step = self.substeps
        status.contact_margin = 0.0
        status.initial_velocities_projected = True  # generalised coordinates (as MuJoCo 2.2.2)
        return status


def _warn_on_stderr(message: str) -> None:
    """MuJoCo's warnings go to standard error (the runner keeps its tail), not to a
    MUJOCO_LOG.TXT in the working folder, which is the repository (data.warning still counts
    them: the instability is reported as a divergence)."""
    print(f"MuJoCo warning: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    mujoco.set_mju_user_warning(_warn_on_stderr)
    return pp.serve(argv, "MuJoCo (Python) as a pbdval external engine", unsupported_features,
                    lambda scene, out: MujocoRun(scene).run(out), engine_version())
