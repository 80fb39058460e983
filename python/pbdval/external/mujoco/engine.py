"""MuJoCo (the Python package, 4.x) as an external engine (protocol 1,
docs/external-engines.md; parity rules: docs/external-engines.md#mujoco-python).

    .venv/bin/python -m pbdval.external.mujoco --scene RESOLVED.json --out OUTDIR

One model description for both MuJoCo versions: the rigid part (bodies, joints of every kind,
springs, motors, distance joints, loops, contact pairs, solver options) is the MJCF the built-in
`mujoco` engine's writer produces for MuJoCo 2.2.2 (adapters/mujoco/mjcf_writer.cpp, through
pbdval._core._mujoco_mjcf from the run's scene), with the attributes MuJoCo 4 reads differently
rewritten in one place (MJCF_2_2_2_TO_4), read into an mujoco.MjSpec and compiled by MuJoCo 4.
What the C++ engine does after compiling is done here the same way: initial velocities projected
onto the joints in the kinetic-energy norm, motor servos tuned from the joint-space inertia.
tests/python/test_mujoco_model_parity.py compiles the same MJCF in both versions and compares
the models field by field.
Particles of triangle models (cloth) and tet models (solids) are MuJoCo flexes added to the
spec, one body with three slide joints per dynamic particle (flexes.py). Elastic flex forces are
explicit in every integrator but `discrete` (implicit in position): under the others a scene
step is split into internal steps below the stability limit of the stiffest elastic mode
(parameter `substeps`).
Methods: mujoco-python.<integrator>.<solver>, integrator euler, rk4, implicit, implicitfast,
discrete and solver newton, cg, pgs.
"""

from __future__ import annotations

import json
import re
import sys
import warnings
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

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
#: The MJCF keyword of each integrator (option/integrator).
MJCF_INTEGRATORS = {"euler": "Euler", "rk4": "RK4", "implicit": "implicit",
                    "implicitfast": "implicitfast", "discrete": "discrete"}
SOLVERS = {
    "newton": mujoco.mjtSolver.mjSOL_NEWTON,
    "cg": mujoco.mjtSolver.mjSOL_CG,
    "pgs": mujoco.mjtSolver.mjSOL_PGS,
}
#: The MJCF keyword of each solver (option/solver).
MJCF_SOLVERS = {"newton": "Newton", "cg": "CG", "pgs": "PGS"}
CONES = ("elliptic", "pyramidal")
#: Constant impedance of contacts and equality constraints (solimp d0 = d_width), the built-in
#: engine's default solimp.
SOLIMP = [0.99, 0.99, 0.001, 0.5, 2.0]

#: What MuJoCo 4.0.0 reads differently from the MJCF the C++ writer produces for MuJoCo 2.2.2,
#: found by compiling that MJCF with 4.0.0 (the schema rejects the first two). Each entry:
#: (pattern, replacement, why). A pattern that no longer matches the writer's text is an error
#: (mjcf_for_mujoco_4), so a change of the writer cannot slip past this table.
MJCF_2_2_2_TO_4: list[tuple[str, str, str]] = [
    (r' collision="all"', "",
     ("option/collision was removed in MuJoCo 3.0: explicit <pair>s and filtered automatic "
      "contacts are always both generated, which was 2.2.2's `all`")),
    (r' passive="enable"', ' spring="enable" damper="enable"',
     "option/flag/passive was split into `spring` and `damper` in MuJoCo 3.0"),
    (r'<size nconmax="\d+" njmax="\d+"/>\n', "",
     ("size/nconmax and njmax size 2.2.2's fixed contact and constraint buffers (its njmax^2 "
      "matrices, hence the writer's caps); MuJoCo 4 allocates constraint rows from its arena "
      "as they come and would only stop at the caps")),
]


def mjcf_for_mujoco_4(xml: str) -> str:
    """The C++ writer's MJCF with MJCF_2_2_2_TO_4 applied. Raises RuntimeError when a pattern
    of the table does not occur exactly once (the writer changed: the table must follow)."""
    for pattern, replacement, _ in MJCF_2_2_2_TO_4:
        xml, count = re.subn(pattern, replacement, xml)
        if count != 1:
            raise RuntimeError(f"MJCF_2_2_2_TO_4: {pattern!r} occurs {count} times in the C++ "
                               "writer's MJCF (expected once): update the table in "
                               "pbdval/external/mujoco/engine.py")
    return xml


def rigid_model(scene: pp.ResolvedScene, settings: dict[str, Any]) -> dict[str, Any]:
    """The C++ writer's model of the scene's rigid part (pbdval._core._mujoco_mjcf): `xml`,
    `motors`, `body_names`, ..., or only `unsupported` when it cannot be written."""
    try:
        from pbdval import _core  # the C++ extension of the build that runs this engine
    except ImportError as e:
        raise RuntimeError("mujoco-python writes its model with pbdval._core, the C++ part of "
                           "pbdval: build it (cmake --build --preset release --target "
                           "pbdval_python_core) and put <build>/python on PYTHONPATH, as the "
                           f"runner does ({e})") from e
    write = getattr(_core, "_mujoco_mjcf", None)
    if write is None:  # another checkout's build, older than the one description
        raise RuntimeError(f"{_core.__file__} has no _mujoco_mjcf: it is another build's pbdval._core; "
                           "put this build's <build>/python first on PYTHONPATH, as the runner does")
    model: dict[str, Any] = write(json.dumps(scene.document), settings)
    return model


def engine_version() -> str:
    return f"mujoco {mujoco.__version__} (Python)"


def method_parts(name: str) -> tuple[str, str] | None:
    parts = (name or DEFAULT_METHOD).split(".")
    if len(parts) != 3 or parts[0] != ENGINE or parts[1] not in INTEGRATORS or parts[2] not in SOLVERS:
        return None
    return parts[1], parts[2]


def writer_settings(integrator: str, solver: str, parameter: Any, h: float) -> dict[str, Any]:
    """The C++ writer's MujocoSettings (adapters/mujoco/mujoco_settings.h) from this engine's
    method and parameters; time constants are given in steps of h."""
    cone = str(parameter("cone"))
    if cone not in CONES:
        raise ValueError(f"parameter cone: expected one of {', '.join(CONES)}, got {cone!r}")
    steps: dict[str, float] = {}
    for name in ("contactTimeconstSteps", "equalityTimeconstSteps", "servoTimeconstSteps"):
        steps[name] = float(parameter(name))
        if steps[name] < 2:
            raise ValueError(f"parameter {name}: expected >= 2 (MuJoCo raises a shorter time "
                             f"constant to 2h), got {steps[name]}")
    dampratio = float(parameter("equalityDampratio"))
    if dampratio <= 0:
        raise ValueError(f"parameter equalityDampratio: expected > 0, got {dampratio}")
    return {"integrator": MJCF_INTEGRATORS[integrator], "solver": MJCF_SOLVERS[solver],
            "iterations": int(parameter("iterations")), "tolerance": float(parameter("tolerance")),
            "cone": cone, "contact_time_constant": steps["contactTimeconstSteps"] * h,
            "equality_solref": [steps["equalityTimeconstSteps"] * h, dampratio],
            "solimp": list(SOLIMP), "servo_time_constant": steps["servoTimeconstSteps"] * h}


def parameter_reader(scene: pp.ResolvedScene, integrator: str) -> Any:
    """name → the run's value of that parameter, else the catalogue's default (catalogue.py;
    `discrete` has more iterations)."""
    return lambda name: scene.parameter(name, catalogue.default(integrator, name))


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    parts = method_parts(scene.method.name)
    if parts is None:
        return [f"method {scene.method.name}"]
    missing: list[str] = []
    settings = writer_settings(*parts, parameter_reader(scene, parts[0]), scene.time_step_size)
    missing += rigid_model(scene, settings)["unsupported"]
    if scene.particles or scene.triangle_models or scene.tet_models:
        missing += flexes.unsupported(scene)
        if parts[0] in ("implicit", "implicitfast"):
            missing.append(f"method {scene.method.name} with particles: MuJoCo 4 refuses flex "
                           "elasticity under implicit and implicitfast (use discrete, euler or rk4)")
        if parts == ("discrete", "pgs"):
            missing.append(f"method {scene.method.name} with particles: MuJoCo's discrete "
                           "integrator needs the Newton or CG solver for flex elasticity")
    return missing


def _matrix(q: pp.Quat) -> np.ndarray:
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _fatal_warnings() -> dict[int, str]:
    """MuJoCo's warnings after which a run cannot go on (as in the built-in engine): it resets
    the state after a bad number, and drops contacts or constraints when memory runs out."""
    w = mujoco.mjtWarning
    return {int(w.mjWARN_BADQPOS): "bad qpos: MuJoCo reset the state",
            int(w.mjWARN_BADQVEL): "bad qvel: MuJoCo reset the state",
            int(w.mjWARN_BADQACC): "bad qacc (unstable): MuJoCo reset the state",
            int(w.mjWARN_BADCTRL): "bad ctrl: MuJoCo reset the state",
            int(w.mjWARN_CONTACTFULL): "contact memory full: contacts were dropped",
            int(w.mjWARN_CNSTRFULL): "constraint memory full: constraints were dropped"}


class MujocoRun:
    def __init__(self, scene: pp.ResolvedScene) -> None:
        self.scene = scene
        parts = method_parts(scene.method.name)
        assert parts is not None
        integrator, solver = parts
        h = scene.time_step_size
        parameter = parameter_reader(scene, integrator)
        writer = writer_settings(integrator, solver, parameter, h)
        self.tau = float(writer["contact_time_constant"])
        self.servo_tau = float(writer["servo_time_constant"])
        requested_substeps = int(parameter("substeps"))
        if requested_substeps < 0:
            raise ValueError(f"parameter substeps: expected >= 0 (0: automatic), got {requested_substeps}")
        self.settings: dict[str, pp.ParameterValue] = {
            "method": f"{ENGINE}.{integrator}.{solver}", "integrator": integrator, "solver": solver,
            "iterations": writer["iterations"], "tolerance": writer["tolerance"],
            "cone": writer["cone"], "contactTimeconst": self.tau,
            "solimp": " ".join(str(v) for v in SOLIMP), "margin": 0.0, "gap": 0.0, "damping": 0.0,
            "equality.solref": " ".join(str(v) for v in writer["equality_solref"]),
            "servo.timeconst": self.servo_tau,
            "model": "the built-in engine's MJCF (adapters/mujoco/mjcf_writer.cpp) with "
                     f"{len(MJCF_2_2_2_TO_4)} MuJoCo 4 rewrites (MJCF_2_2_2_TO_4)",
        }
        self.mjcf = rigid_model(scene, writer)
        if self.mjcf["unsupported"]:
            raise ValueError("MuJoCo cannot represent " + "; ".join(self.mjcf["unsupported"]))
        spec = mujoco.MjSpec.from_string(mjcf_for_mujoco_4(self.mjcf["xml"]))
        if scene.particles:  # rigid pairs stay explicit <pair>s; particles collide by affinity
            for geom in spec.geoms:
                geom.conaffinity = flexes.FLEX_CONTACT_BIT
        self.settings["contact.pairs"] = int(self.mjcf["contact_pairs"])
        self.settings["equality.constraints"] = int(self.mjcf["equality_constraints"])
        for pair, law in dict(self.mjcf["pair_settings"]).items():
            self.settings[f"contact.{pair}"] = str(law)
        for i, note in enumerate(self.mjcf["approximations"]):
            self.settings[f"approximation.{i}"] = str(note)
        self.settings["jointedBodiesCollide"] = (
            f"yes (as in the seed): {self.mjcf['jointed_contact_pairs']} of the pairs join bodies "
            "connected by a joint; explicit <pair>s, which MuJoCo never filters, and filterparent "
            "disabled")
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
        self.body_ids = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, n)
                         for n in self.mjcf["body_names"]]
        # What states() reads into and with, allocated once.
        self._body_index = np.array(self.body_ids, dtype=np.intp)
        self._principal_factors = pp.principal_to_scene_factors(scene)
        self._velocity = np.zeros((len(self.body_ids), 6))
        self._velocity_rows = [(body_id, self._velocity[i]) for i, body_id in enumerate(self.body_ids)]
        self._state = np.empty((len(self.body_ids), pp.STATE_COLUMNS))
        mujoco.mj_forward(self.model, self.data)
        self._project_initial_velocities()
        self.layout.resolve(self.model)
        for i, d in zip(self.layout.dynamic, self.layout.dofs):
            self.data.qvel[d] = scene.particles[i].velocity
        mujoco.mj_forward(self.model, self.data)
        mismatch = flexes.state_matches(self.data, self.layout)
        if mismatch != 0.0:
            raise RuntimeError("flex vertices are not the scene's particles at t = 0 "
                               f"(off by {mismatch:g} m)")
        self.servos = self._tune_servos()
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

    def _project_initial_velocities(self) -> None:
        """The built-in engine's projection (mujoco_engine.cpp projectInitialVelocities): the
        scene gives every body's velocity, MuJoCo's state is the joint velocities; the qvel
        closest to the scene's in the kinetic-energy norm solves M qvel = sum_b J_b^T (m v, I w)
        (the generalised momentum of the scene's velocities). It reproduces them exactly when
        they agree with the joints; a body they disagree for is recorded."""
        m, d = self.model, self.data
        if m.nv == 0:
            return
        jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        momentum = np.zeros(m.nv)
        inertias: list[np.ndarray] = []
        for b, body_id in zip(self.scene.bodies, self.body_ids):
            rotation = _matrix(b.world_principal_rotation)
            inertias.append(rotation @ np.diag(b.principal_inertia) @ rotation.T)
            if not b.dynamic:
                continue
            mujoco.mj_jacBodyCom(m, d, jacp, jacr, body_id)
            momentum += jacp.T @ (b.mass * np.array(b.velocity)) + jacr.T @ (inertias[-1] @ b.angular_velocity)
        qvel = np.zeros((1, m.nv))
        mujoco.mj_solveM(m, d, qvel, momentum.reshape(1, -1))
        d.qvel[:] = qvel[0]
        for b, body_id in zip(self.scene.bodies, self.body_ids):
            if not b.dynamic:
                continue
            mujoco.mj_jacBodyCom(m, d, jacp, jacr, body_id)
            v, w = jacp @ d.qvel, jacr @ d.qvel
            mismatch = float(np.linalg.norm(v - b.velocity) + np.linalg.norm(w - b.angular_velocity))
            scale = float(np.linalg.norm(b.velocity) + np.linalg.norm(b.angular_velocity))
            if mismatch > 1e-9 * (1 + scale):  # the C++ engine's threshold
                self.settings[f"{b.json_path}.initialVelocity"] = (
                    f"disagrees with its joints by {mismatch:.6g}; projected onto them "
                    "(kinetic-energy norm): v = " + " ".join(f"{x:.6g}" for x in v)
                    + ", w = " + " ".join(f"{x:.6g}" for x in w))

    def _tune_servos(self) -> list[tuple[int, pp.MotorTarget]]:
        """The built-in engine's servos (mujoco_engine.cpp tuneServos): critically damped on the
        driven joint, m = 1/(M^-1)_ii at t = 0, tau = servoTimeconst; a position servo applies
        kp (q* - q) - kv qdot with kp = m/tau^2, kv = 2m/tau, a velocity servo kv (qdot* - qdot)
        with kv = m/tau. Returns (actuator, set point) per motor."""
        m, d = self.model, self.data
        servos: list[tuple[int, pp.MotorTarget]] = []
        for motor in self.mjcf["motors"]:
            actuator = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, motor["actuator"])
            joint = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, motor["joint_name"])
            dof = int(m.jnt_dofadr[joint])
            unit, column = np.zeros((1, m.nv)), np.zeros((1, m.nv))
            unit[0, dof] = 1.0
            mujoco.mj_solveM(m, d, column, unit)
            inertia = 1.0 / column[0, dof]
            tau = self.servo_tau
            velocity = bool(motor["velocity_servo"])
            kv = inertia / tau if velocity else 2 * inertia / tau
            kp = 0.0 if velocity else inertia / (tau * tau)
            m.actuator_gainprm[actuator, 0] = kv if velocity else kp
            m.actuator_biasprm[actuator, 0:3] = [0.0, -kp, -kv]
            joint_desc = self.scene.joints[int(motor["joint"])]
            assert joint_desc.target is not None
            d.ctrl[actuator] = joint_desc.target.value_at(d.time)
            servos.append((actuator, joint_desc.target))
            self.settings[f"servo.{joint_desc.json_path}"] = (
                f"{'velocity' if velocity else 'position (PD)'} kp={kp:.6g} kv={kv:.6g} "
                f"joint inertia={inertia:.6g}")
        return servos

    def states(self) -> np.ndarray:
        """Every body's state (pp.state_array_rows' columns) but the rotation, which is the
        principal frame's (finish_states turns a whole trajectory's into the scene frame's),
        read with array operations: the positions and orientations of all bodies at once, one
        mj_objectVelocity per body (MuJoCo has no batched form) into a row of one preallocated
        array."""
        m, d = self.model, self.data
        velocity = self._velocity
        body_frame, object_velocity = mujoco.mjtObj.mjOBJ_XBODY, mujoco.mj_objectVelocity
        for body_id, row in self._velocity_rows:
            # [w; v] at the body frame's origin (the centre of mass), world axes.
            object_velocity(m, d, body_frame, body_id, row, 0)
        state = self._state
        state[:, 0:3] = d.xpos[self._body_index]
        state[:, 3:7] = d.xquat[self._body_index]
        state[:, 7:10] = velocity[:, 3:]
        state[:, 10:13] = velocity[:, :3]
        return state

    def finish_states(self, read: np.ndarray) -> np.ndarray:
        """The scene frames' state arrays from `states`' (a whole trajectory's at once,
        pp.simulate's `finish_states`): the principal frame's rotation → the scene frame's."""
        out = read.copy()
        out[..., 3:7] = pp.quat_multiply_rows(read[..., 3:7], self._principal_factors)
        return out

    def run(self, out_dir: Path) -> pp.Status:
        fatal = _fatal_warnings()
        fatal_index = np.array(list(fatal), dtype=np.intp)
        # Views of the run's MjData arrays, taken once: every step looks at them (MjData's
        # buffers stay where they are for the whole run), and a view made per step costs more
        # than MuJoCo's step of a small scene.
        warning_counts = self.data.warning.number
        qpos, qvel = self.data.qpos, self.data.qvel
        count_nonzero, dot = np.count_nonzero, np.vdot  # C functions, without Python wrappers
        squared_limit = pp.DIVERGENCE_LIMIT**2

        def failure(t: float) -> str | None:
            # One look at every warning counter (no warning at all: the common case), then at
            # the fatal ones.
            if not count_nonzero(warning_counts) or not count_nonzero(warning_counts[fatal_index]):
                return None
            for warning, text in fatal.items():
                if self.data.warning[warning].number > 0:
                    return f"MuJoCo at t = {t:g} s: {text}"
            return None

        def check(t: float) -> str | None:
            # Between samples: the runner's limits on the generalised state, vectorised (a free
            # body's qpos holds its position, its qvel its linear and angular velocity).
            # One cheap look first, sufficient but not necessary: the sum of the squares within
            # the limit's square, so every value within the limit (NaN and infinity fail the
            # comparison, so does a sum that overflows); only a state that fails it is looked at
            # closer, by the exact test below, which decides.
            if dot(qpos, qpos) + dot(qvel, qvel) <= squared_limit:
                return None
            if not (np.isfinite(qpos).all() and np.isfinite(qvel).all()):
                return f"non-finite state at t = {t:g} s"
            if qpos.size and np.abs(qpos).max() > pp.DIVERGENCE_LIMIT:
                return f"a coordinate beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            if qvel.size and np.abs(qvel).max() > pp.DIVERGENCE_LIMIT:
                return f"a speed beyond {pp.DIVERGENCE_LIMIT:g} at t = {t:g} s"
            return None

        def states(t: float) -> np.ndarray:
            # mj_step leaves xpos, xquat and cvel at the start of the step (they are computed
            # before the integration); recompute them for the new state. What states() reads
            # (xpos, xquat; cvel and subtree_com for mj_objectVelocity) is made by the first
            # stages of mj_forward alone, the same functions on the same qpos and qvel: the
            # same numbers, without the collision and constraint solve of a whole mj_forward
            # (most of a sample's cost). They change no state and no warm start, so sampling
            # does not change the trajectory. Scenes with particles keep the whole mj_forward.
            if t > 0:
                if self.scene.particles:
                    mujoco.mj_forward(self.model, self.data)
                else:
                    mujoco.mj_kinematics(self.model, self.data)
                    mujoco.mj_comPos(self.model, self.data)
                    mujoco.mj_comVel(self.model, self.data)
            return self.states()

        model, data = self.model, self.data
        mj_step = mujoco.mj_step

        def step() -> None:
            for _ in range(self.substeps):
                # Set points for the end of the step being taken, as the PBD motors use them.
                end = data.time + model.opt.timestep
                for actuator, target in self.servos:
                    data.ctrl[actuator] = target.value_at(end)
                mj_step(model, data)

        def step_once() -> None:  # step() of one substep without servos
            mj_step(model, data)

        particles = (lambda t: self.layout.state(self.data)) if self.scene.particles else None
        status = pp.simulate(self.scene, out_dir,
                             step_once if self.substeps == 1 and not self.servos else step,
                             states, failure, check, particles=particles,
                             finish_states=self.finish_states)
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
