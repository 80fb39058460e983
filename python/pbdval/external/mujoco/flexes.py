"""The scene's particles as MuJoCo flexes (MuJoCo 4.0.0, docs/external-engines.md#mujoco-python).

Every particle is one flex vertex with exactly its scene mass: a dynamic particle is a body of
that mass under the world with three slide joints along the world axes (MuJoCo's fastest flex
attachment: its stiffness is assembled in 3x3 vertex blocks), its vertex at the body's origin; a
static particle (mass 0) is a vertex of the world body at its position. One flex per model, the
models' particles in scene order, so flex vertex i is scene particle i (checked at t = 0), and the
elements are the model's triangles (dim 2) or tets (dim 3) in the scene's vertex numbering.

Materials:
- tets, method 3 (FEM-XPBD, E and nu): flex elasticity young = E, poisson = nu. MuJoCo's 3D
  model is St. Venant-Kirchhoff on linear tets (energy density mu tr(eps^2) + lambda/2 tr(eps)^2,
  Green strain eps), the energy of the scene's method: native.
- cloth, method 4 (XPBD distance, k N/m on every edge): MuJoCo 4 has edge stiffness for 1D flexes
  only, so the cloth is a St. Venant-Kirchhoff membrane (elastic2d "stretch"; "both" with the
  bending below) whose small-strain stiffness is that of the spring network, averaged over
  directions. A network of springs k_e along edges of length l_e and direction n_e stores, per
  unit area A under a homogeneous strain, the stiffness tensor
  C = (1/A) sum_e w_e k_e l_e^2 n_e n_e n_e n_e (w_e: the edge's share of the bulk, half per
  adjacent triangle). Its isotropic part is c (dd + dd + dd) with
  c = sum_e w_e k_e l_e^2 / (8 A) (the trace C_iijj = 8 c), i.e. Lame parameters lambda* = mu = c:
  a plane-stress membrane of Poisson ratio 1/3 (spring networks obey the Cauchy relation) and
  E t = (8/3) c = sum_e w_e k_e l_e^2 / (3 A). On a square grid with one diagonal per cell that is
  4k/3, which reproduces the network's C_1111 = 3k/2 and C_1122 = C_1212 = k/2 along the grid
  axes exactly; the network's anisotropy (stiffer along the diagonals it has) is not
  representable: approximated.
- cloth, method 2 (the seed's FEM triangles, Bender et al. 2014: an orthotropic St. Venant-
  Kirchhoff membrane, energy A psi per triangle with psi = 1/2 c_xx E_xx^2 + c_xy E_xx E_yy +
  1/2 c_yy E_yy^2 + G E_xy^2 on the Green strain E, c_xx = E_x/(1 - nu_xy nu_yx), c_yy likewise,
  c_xy = (E_x nu_yx + E_y nu_xy)/(2 (1 - nu_xy nu_yx)); the moduli are per unit area, N/m):
  MuJoCo's membrane is isotropic St. Venant-Kirchhoff under plane stress, psi = mu tr(E^2) +
  lambda*/2 (tr E)^2 with mu = E t/(2 (1 + nu)), lambda* = E t nu/(1 - nu^2). With E_x = E_y = E_s
  and nu_xy = nu_yx = nu the two agree term by term for E t = E_s, poisson = nu
  (c_xx = lambda* + 2 mu, c_xy = lambda*) and shear G = 2 mu = E_s/(1 + nu); another G is
  approximated by MuJoCo's (ratio E_s/(G (1 + nu)) recorded; the seed's defaults E = G = 1,
  nu = 0.3 give 1/1.3). Orthotropic moduli are unsupported. The thickness is 2 r (membrane only)
  or, with bending method 3, from the matched rigidity below with this E t and nu. The seed's
  PBD projection has no stiffness factor (its stiffness comes from its iterations and substeps,
  only the moduli's ratios matter to it), MuJoCo's is the moduli's: the same scene is as stiff
  as its moduli in MuJoCo, as stiff as its solver makes it in pbd.
- bending, method 3 (XPBD isometric, Bergou et al. 2006): its potential (1/2) k C^2, with
  C = (3/(A0 + A1)) |sum K_i x_i|^2 / 2 itself quadratic in the positions, is quartic in the fold,
  with no stiffness at the flat state; MuJoCo's shell bending is quadratic (Kirchhoff,
  D kappa^2 / 2 per area, discrete hinges; elastic2d "both"). No modulus matches at every fold,
  so D is matched at one curvature kappa* (parameter clothBendingCurvature): the sheet bent into
  a cylinder of curvature kappa* (an isometry of the plane) stores the seed's energy, summed over
  its interior-edge stencils, in both models; MuJoCo's energy of that cylinder at D = 1 is
  measured as the work of its bending forces along the bend (no assumption on its discrete
  normalisation). Softer than the seed's for larger folds, stiffer for smaller: approximated.
  The shell thickness then follows from D = E t^3 / (12 (1 - nu^2)) with E t fixed by the
  membrane. kappa* = 0: no bending. Method 0: none, native. Methods 1 and 2 (PBD fractions per
  iteration) are unsupported; so are cloth methods 1 and 3.
- method 0 (no constraints) of either: a flex without elasticity, native.
- damping 0 everywhere.

Contacts: flexes collide with rigid geoms and with each other through contype/conaffinity bit 2
(the rigid pairs stay explicit <pair>s, geom contype 0), condim 3 with the model's friction and
the Kelvin-Voigt law of its restitution (contact_law.py); flex priority 1, so a flex-geom contact
takes the flex's parameters. No self-collision.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from pbdval import protocol as pp
from pbdval.external.cloth_bending import bending_stencils, cylinder, isometric_xpbd_energy

#: contype/conaffinity bit of every flex and of the rigid geoms that particles touch.
FLEX_CONTACT_BIT = 2
#: Radius of a cloth's triangles (MuJoCo needs a positive one in 2D): a thin sheet. Its
#: thickness for the membrane's stiffness is 2 r, as MuJoCo's documentation suggests.
CLOTH_RADIUS = 0.001
#: Poisson ratio of the membrane that matches a spring network (Cauchy relation, see above).
NETWORK_POISSON = 1.0 / 3.0
CLOTH_METHODS = {0: "none", 2: "fem (isotropic moduli)", 4: "xpbd_distance"}
#: Relative difference below which two of the FEM cloth's moduli (or Poisson ratios) count as
#: equal: the loader's values are doubles, so equal inputs are equal to the last bit; 1e-12
#: leaves room for moduli derived by arithmetic in a scene generator.
ISOTROPY_TOLERANCE = 1e-12
BENDING_METHODS = {0: "none", 3: "isometric_xpbd (matched at one curvature)"}
SOLID_METHODS = {0: "none", 3: "fem_xpbd"}


def _differ(a: float, b: float) -> bool:
    return abs(a - b) > ISOTROPY_TOLERANCE * max(abs(a), abs(b))


@dataclass(frozen=True)
class FemMembrane:
    """MuJoCo's isotropic membrane for the seed's FEM cloth (method 2, module comment)."""

    stretch: float  # E t (N/m): MuJoCo's young times thickness
    poisson: float  # nu
    shear_ratio: float  # MuJoCo's shear stiffness over the seed's: E_s / (G (1 + nu))


def fem_membrane(material: dict[str, Any]) -> FemMembrane:
    """The membrane of the seed's FEM triangle with E_x = E_y = E_s, nu_xy = nu_yx = nu and
    shear modulus G (the seed's energy has G E_xy^2; isotropy means G = E_s/(1 + nu))."""
    youngs, poisson = float(material["xxStiffness"]), float(material["xyPoissonRatio"])
    shear = float(material["xyStiffness"])
    return FemMembrane(stretch=youngs, poisson=poisson, shear_ratio=youngs / (shear * (1 + poisson)))


def unsupported(scene: Any) -> list[str]:
    """The particle features this engine cannot represent, each naming its JSON path."""
    missing = pp.unsupported_particle_models(scene, "MuJoCo's flexes", CLOTH_METHODS,
                                             BENDING_METHODS, SOLID_METHODS)
    for tm in scene.triangle_models:
        if tm.simulation_method != 2:
            continue
        m = tm.material
        if _differ(float(m["xxStiffness"]), float(m["yyStiffness"])) or _differ(
                float(m["xyPoissonRatio"]), float(m["yxPoissonRatio"])):
            missing.append(
                f"{tm.json_path}: cloth method 2 (fem) with orthotropic moduli (cloth_xxStiffness "
                f"{m['xxStiffness']:g}, cloth_yyStiffness {m['yyStiffness']:g}, cloth_xyPoissonRatio "
                f"{m['xyPoissonRatio']:g}, cloth_yxPoissonRatio {m['yxPoissonRatio']:g}): MuJoCo's "
                "flex elasticity is isotropic")
        elif float(m["xyStiffness"]) <= 0 or not 0 <= float(m["xyPoissonRatio"]) < 0.5:
            missing.append(
                f"{tm.json_path}: cloth method 2 (fem) with cloth_xyStiffness {m['xyStiffness']:g} "
                f"and Poisson ratio {m['xyPoissonRatio']:g}: MuJoCo needs a positive shear modulus "
                "and 0 <= nu < 0.5")
    missing += pp.particles_outside_models(scene)
    return missing


def membrane_stiffness(positions: np.ndarray, triangles: np.ndarray, edge_stiffness: float) -> float:
    """E t (N/m) of the isotropic membrane with the small-strain stiffness of springs
    `edge_stiffness` on every edge of `triangles`, averaged over directions:
    sum_e w_e k l_e^2 / (3 A), w_e = (triangles at e) / 2, A the total area (module comment)."""
    tri = np.asarray(triangles, dtype=np.int64)
    x = np.asarray(positions, dtype=np.float64)
    area = 0.5 * np.linalg.norm(np.cross(x[tri[:, 1]] - x[tri[:, 0]], x[tri[:, 2]] - x[tri[:, 0]]),
                                axis=1).sum()
    shares: dict[tuple[int, int], int] = {}
    for a, b, c in tri:
        for i, j in ((a, b), (b, c), (c, a)):
            key = (min(int(i), int(j)), max(int(i), int(j)))
            shares[key] = shares.get(key, 0) + 1
    total = sum(0.5 * n * float(np.sum((x[i] - x[j]) ** 2)) for (i, j), n in sorted(shares.items()))
    return float(edge_stiffness * total / (3.0 * area))


def kirchhoff_energy_per_rigidity(positions: np.ndarray, triangles: np.ndarray, target: np.ndarray,
                                  poisson: float, steps: int = 64) -> float:
    """MuJoCo's bending energy of `target` at D = 1 N m: the work of its bending forces (a
    bending-only flex of the same mesh) along the straight path from the rest state, by the
    trapezoidal rule (exact for its forces' linear part)."""
    x = np.asarray(positions, dtype=np.float64)
    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, 0.0]
    names = []
    for i, p in enumerate(x):
        body = spec.worldbody.add_body(name=f"v{i}", pos=list(p), mass=1.0, inertia=[1.0] * 3,
                                       explicitinertial=True)
        for axis in np.eye(3):
            body.add_joint(type=mujoco.mjtJoint.mjJNT_SLIDE, axis=list(axis))
        names.append(f"v{i}")
    sheet = spec.add_flex(name="sheet", dim=2, vertbody=names, vert=[0.0] * x.size,
                          elem=[int(v) for v in np.asarray(triangles).ravel()])
    thickness = 1e-3
    sheet.thickness, sheet.poisson, sheet.radius, sheet.elastic2d = thickness, poisson, 1e-3, 1
    sheet.young = 12 * (1 - poisson**2) / thickness**3  # D = E t^3 / (12 (1 - nu^2)) = 1
    sheet.contype = sheet.conaffinity = 0
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=".*has no equality constraints or passive forces")
        model = spec.compile()
    data = mujoco.MjData(model)
    work, previous = 0.0, np.zeros(x.size)
    displacement = (np.asarray(target) - x).ravel()
    for step in range(1, steps + 1):
        data.qpos[:] = displacement * step / steps
        mujoco.mj_forward(model, data)
        force = data.qfrc_passive.copy()
        work -= 0.5 * float((force + previous) @ displacement) / steps
        previous = force
    return work


def matched_rigidity(positions: np.ndarray, triangles: np.ndarray, stiffness: float,
                     curvature: float, poisson: float) -> float:
    """D (N m) at which MuJoCo's bending of the sheet into a cylinder of `curvature` stores the
    seed's isometric XPBD energy of the same cylinder (module comment)."""
    bent = cylinder(positions, triangles, curvature)
    seed = isometric_xpbd_energy(bending_stencils(positions, triangles), bent, stiffness)
    return seed / kirchhoff_energy_per_rigidity(positions, triangles, bent, poisson)


@dataclass
class FlexLayout:
    """Where each scene particle lives in the compiled model."""

    positions0: np.ndarray  # (P, 3), the scene's initial positions
    dynamic: np.ndarray  # (D,) indices of the dynamic particles
    body_names: list[str]  # per particle: its body ("world" when static)
    qpos: np.ndarray = None  # type: ignore[assignment]  # (D, 3) qpos addresses of the slides
    dofs: np.ndarray = None  # type: ignore[assignment]  # (D, 3) dof addresses
    masses: np.ndarray = None  # type: ignore[assignment]  # (D,)

    def resolve(self, model: mujoco.MjModel) -> None:
        qpos, dofs = [], []
        for i in self.dynamic:
            body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, self.body_names[i])
            joint = model.body_jntadr[body]
            qpos.append([model.jnt_qposadr[joint + k] for k in range(3)])
            dofs.append([model.jnt_dofadr[joint + k] for k in range(3)])
        self.qpos = np.array(qpos, dtype=np.int64).reshape(-1, 3)
        self.dofs = np.array(dofs, dtype=np.int64).reshape(-1, 3)

    def state(self, data: mujoco.MjData) -> np.ndarray:
        """(P, 6): positions and velocities of every particle in scene order."""
        out = np.zeros((len(self.positions0), 6))
        out[:, :3] = self.positions0
        if len(self.dynamic):
            out[self.dynamic, :3] += data.qpos[self.qpos]
            out[self.dynamic, 3:] = data.qvel[self.dofs]
        return out


def add_flexes(spec: mujoco.MjSpec, scene: Any, contact: Any, settings: dict[str, Any],
               bending_curvature: float = 2.0) -> FlexLayout:
    """Adds a body per dynamic particle and one flex per triangle or tet model; `contact(model)`
    gives (solref, solimp) of a model's contacts; XPBD isometric bending is matched at
    `bending_curvature` (1/m, 0: none). Records every mapping in `settings`."""
    positions = np.array([p.position for p in scene.particles], dtype=np.float64).reshape(-1, 3)
    masses = np.array([p.mass for p in scene.particles], dtype=np.float64)
    names: list[str] = []
    for i, p in enumerate(scene.particles):
        if p.mass <= 0:
            names.append("world")
            continue
        name = f"particle{i}"
        # Rotational inertia is never used (slide joints only) but must be positive.
        body = spec.worldbody.add_body(name=name, pos=list(p.position), mass=p.mass,
                                       inertia=[1e-12] * 3, ipos=[0, 0, 0], iquat=[1, 0, 0, 0],
                                       explicitinertial=True)
        for axis in np.eye(3):
            body.add_joint(type=mujoco.mjtJoint.mjJNT_SLIDE, axis=list(axis), damping=0.0,
                           stiffness=0.0, armature=0.0)
        names.append(name)
    for tm in (*scene.triangle_models, *scene.tet_models):
        first, count = tm.first_particle, tm.particle_count
        cloth = hasattr(tm, "triangles")
        elements = np.asarray(tm.triangles if cloth else tm.tets, dtype=np.int64)
        vertices = []
        for i in range(first, first + count):
            vertices += list(positions[i]) if names[i] == "world" else [0.0, 0.0, 0.0]
        flex = spec.add_flex(name=f"flex{tm.id}_{'cloth' if cloth else 'solid'}",
                             dim=2 if cloth else 3, vertbody=names[first:first + count],
                             vert=vertices, elem=[int(v) for v in elements.ravel()])
        solref, solimp = contact(tm)
        flex.contype = FLEX_CONTACT_BIT
        flex.conaffinity = FLEX_CONTACT_BIT
        flex.condim = 3
        flex.priority = 1
        flex.friction = [tm.friction, 0.0, 0.0]
        flex.solref = solref
        flex.solimp = solimp
        flex.margin = 0.0
        flex.gap = 0.0
        flex.selfcollide = mujoco.mjtFlexSelf.mjFLEXSELF_NONE
        flex.damping = 0.0
        flex.edgestiffness = 0.0
        flex.edgedamping = 0.0
        path = tm.json_path
        if tm.simulation_method == 0:
            flex.radius = CLOTH_RADIUS if cloth else 0.0
            flex.young = 0.0
            settings[f"{path}.elasticity"] = "none (method 0, native)"
        elif cloth:
            if tm.simulation_method == 2:
                fem = fem_membrane(tm.material)
                stiffness, poisson = fem.stretch, fem.poisson
                membrane = (
                    f"St. Venant-Kirchhoff membrane of the FEM triangles' moduli: E t = "
                    f"cloth_xxStiffness = {stiffness:.6g} N/m, nu = {poisson:g}; shear stiffness "
                    f"{fem.shear_ratio:.6g} x the seed's (cloth_xyStiffness "
                    f"{float(tm.material['xyStiffness']):g}; equal when it is E_s/(1 + nu)): "
                    + ("native" if abs(fem.shear_ratio - 1) <= ISOTROPY_TOLERANCE else "approximated")
                    + "; the seed's PBD projection has no stiffness factor (its stiffness comes "
                    "from the iterations), MuJoCo's is the moduli's")
            else:
                k = float(tm.material["stiffness"])
                stiffness = membrane_stiffness(positions[first:first + count], elements, k)
                poisson = NETWORK_POISSON
                membrane = (f"St. Venant-Kirchhoff membrane for springs of {k:g} N/m on every edge "
                            f"(approximated): E t = {stiffness:.6g} N/m, nu = 1/3")
            rigidity = 0.0
            if tm.bending_method == 3 and bending_curvature > 0:
                rigidity = matched_rigidity(positions[first:first + count], elements,
                                            float(tm.material["bendingStiffness"]),
                                            bending_curvature, poisson)
            # D = E t^3/(12 (1 - nu^2)) with E t fixed: t^2 = 12 (1 - nu^2) D / (E t).
            thickness = (math.sqrt(12 * (1 - poisson**2) * rigidity / stiffness)
                         if rigidity > 0 else 2 * CLOTH_RADIUS)
            flex.radius = CLOTH_RADIUS
            flex.thickness = thickness
            flex.young = stiffness / thickness
            flex.poisson = poisson
            flex.elastic2d = 3 if rigidity > 0 else 2  # both, or stretching only
            settings[f"{path}.membrane"] = (
                f"{membrane}; t = {thickness:.6g} m, E = {stiffness / thickness:.6g} Pa")
            if rigidity > 0:
                settings[f"{path}.bending"] = (
                    f"Kirchhoff shell bending D = {rigidity:.6g} N m (approximated): MuJoCo's "
                    f"quadratic bending matched to the quartic XPBD isometric bending "
                    f"(k = {float(tm.material['bendingStiffness']):g}) on a cylinder of curvature "
                    f"{bending_curvature:g} 1/m")
        else:
            flex.radius = 0.0
            flex.young = float(tm.material["stiffness"])
            flex.poisson = float(tm.material["poissonRatio"])
            flex.elastic3d = 0  # St. Venant-Kirchhoff
            settings[f"{path}.elasticity"] = (
                f"St. Venant-Kirchhoff tets (native): young = {flex.young:g} Pa, "
                f"poisson = {flex.poisson:g}")
        if cloth and f"{path}.bending" not in settings:
            settings[f"{path}.bending"] = (
                "none (native)" if tm.bending_method == 0 else
                f"omitted: method {tm.bending_method} ({tm.bending_method_name}) with "
                "clothBendingCurvature 0, or on a cloth without elasticity")
        settings[f"{path}.radius"] = flex.radius
        settings[f"{path}.friction"] = tm.friction
    return FlexLayout(positions0=positions, dynamic=np.flatnonzero(masses > 0), body_names=names,
                      masses=masses[masses > 0])


def highest_frequency(model: mujoco.MjModel, data: mujoco.MjData, layout: FlexLayout,
                      iterations: int = 60, displacement: float = 1e-7) -> float:
    """omega_max (rad/s) of the particles' elastic forces at the current state: the largest
    eigenvalue of M^-1/2 K M^-1/2 by power iteration, K v from central differences of
    qfrc_passive (the flex elasticity) along v. Deterministic (fixed seed); restores the state."""
    if not len(layout.dynamic):
        return 0.0
    qpos0, qvel0 = data.qpos.copy(), data.qvel.copy()
    dofs = layout.dofs.ravel()
    qadr = layout.qpos.ravel()
    root_mass = np.repeat(np.sqrt(layout.masses), 3)

    def stiffness_times(v: np.ndarray) -> np.ndarray:
        forces = []
        for sign in (1.0, -1.0):
            data.qpos[:] = qpos0
            data.qpos[qadr] += sign * displacement * v
            data.qvel[:] = 0.0
            mujoco.mj_forward(model, data)
            forces.append(data.qfrc_passive[dofs].copy())
        difference: np.ndarray = -(forces[0] - forces[1]) / (2 * displacement)
        return difference

    u = np.random.default_rng(0).standard_normal(len(dofs))
    u /= np.linalg.norm(u)
    eigenvalue = 0.0
    for _ in range(iterations):
        w = stiffness_times(u / root_mass) / root_mass
        eigenvalue = float(u @ w)
        norm = float(np.linalg.norm(w))
        if norm == 0.0:
            break
        u = w / norm
    data.qpos[:] = qpos0
    data.qvel[:] = qvel0
    mujoco.mj_forward(model, data)
    return math.sqrt(max(eigenvalue, 0.0))


def explicit_substeps(omega: float, step: float) -> int:
    """Internal steps per scene step for an integrator explicit in the elastic forces: the
    semi-implicit Euler step is stable for h omega < 2 (RK4: 2.8 on the imaginary axis); take
    h_sub omega <= 1, a factor 2 for the power iteration's underestimate and the stiffening
    under tension."""
    return max(1, math.ceil(omega * step))


def state_matches(data: mujoco.MjData, layout: FlexLayout) -> float:
    """Largest |flexvert_xpos - scene position| (after mj_forward): 0 when flex vertex i is
    scene particle i."""
    if not len(layout.positions0):
        return 0.0
    return float(np.max(np.abs(np.asarray(data.flexvert_xpos) - layout.positions0)))

