"""The scene's particles as Newton particles (docs/engine-newton.md#cloth); numpy only here,
engine.py hands in Newton's ModelBuilder.

Every scene particle is one Newton particle (`add_particle`), in scene order, with its scene mass
and velocity; a static particle (mass 0) is a Newton particle of mass 0, which no solver moves
(`integrate_particles` adds gravity only where the inverse mass is positive, every correction is
weighted by it) and whose velocity is set to 0. Its radius is PARTICLE_RADIUS.

Cloth (TriangleModels):
- method 0 (no constraints): free particles, native.
- method 4 (XPBD distance, k N/m per edge): one Newton spring per distinct triangle edge,
  `add_spring(i, j, ke = k, kd = 0)`, rest length the initial one. SolverXPBD solves it as the
  XPBD distance constraint C = |x_i - x_j| - L with compliance alpha = 1/(ke h^2)
  (`solve_springs`), i.e. the potential (1/2) k C^2 of the seed's method; SolverSemiImplicit and
  SolverFeatherstone apply the spring force -ke C n (`eval_spring`): the same potential,
  integrated explicitly. Native (Newton's XPBD sweeps its constraints Jacobi-style, summing
  the corrections per particle, where the seed's are Gauss-Seidel: a solver difference).
- bending method 3 (XPBD isometric, Bergou et al. 2006): Newton bends cloth at its interior
  edges by the dihedral angle theta (`add_edge`, Grinspun et al. 2003's discrete shells), rest
  angle the initial one. Read from the kernels (xpbd/kernels.py `bending_constraint`,
  semi_implicit/kernels_particle.py `eval_bending`): both use, as the "gradient" of
  C = theta - theta0, the vectors d_1 = -|e| n1^, d_2 = -|e| n2^, d_3, d_4 (n^ the unit face
  normals, e the shared edge), which are 2 A_f times the true gradient of theta (A_f the area of
  the vertex's face; for x_3, x_4 when the two faces have equal areas). SolverXPBD with
  compliance 1/(ke h^2) converges to the force -ke C d: the potential ke A C^2 for equal faces
  (A their area); SolverSemiImplicit applies -|e| ke C d: the potential ke |e| A C^2. Unequal
  faces make either force non-conservative; A is then taken as the faces' mean. Both are
  quadratic in the fold, the seed's potential (1/2) k C_iso^2 quartic (its C_iso is itself
  quadratic in the positions), so no ke matches at every fold: as for MuJoCo's flexes
  (mujoco/flexes.py), ke is matched at one curvature kappa* (parameter clothBendingCurvature,
  default 2 /m): the sheet bent into a cylinder of curvature kappa* (an isometry of its plane)
  stores the seed's energy in both models, Newton's computed as sum_e w_e theta_e^2 (w_e = A_e
  for XPBD, |e| A_e for the explicit solvers) with theta_e the angle Newton's kernels compute.
  Approximated: stiffer than the seed's for smaller folds, softer for larger ones.
- methods 1, 2, 3 and bending methods 1, 2: unsupported by name. The PBD fractions (1; bending
  1, 2) are not stiffnesses. FEM (2) and strain-based (3) triangles: SolverXPBD solves no
  triangle elements, and the explicit solvers' triangles (`eval_triangle`) are a stable
  neo-Hookean membrane whose small-strain Lame parameters are (tri_ke, tri_ka - tri_ke), where the
  seed's method 2 is an orthotropic St. Venant-Kirchhoff projection whose stiffness comes from its
  iterations: not mapped.
Solids (TetModels): method 0 (free particles) native. Method 3 (FEM-XPBD: St. Venant-Kirchhoff
linear tets of Young's modulus E and Poisson ratio nu) under the explicit solvers: Newton's stable
neo-Hookean tets (`add_tetrahedron`, `eval_tetrahedra`; Smith et al., "Stable Neo-Hookean Flesh
Simulation", 2018): P = k_mu (1 - 1/(I_C + 1)) F + k_lambda (J - alpha) cof F,
alpha = 1 + 3 k_mu / (4 k_lambda). Linearised at F = I: dP = (3/2) k_mu eps + (k_lambda -
5/8 k_mu) tr(eps) I, so the small-strain Lame parameters (mu, lambda) of E, nu are those of
k_mu = 4/3 mu, k_lambda = lambda + 5/6 mu (neo_hookean). Both models are linear elasticity at
small strain and differ at large: approximated. nu outside [0, 0.49] is refused (the seed's
range). Under SolverXPBD: unsupported. SolverXPBD's tets (`solve_tetrahedra`) project
C_D = tr(F^T F) - 3 and C_H = det F - 1 with compliances 1/(k_mu V), 1/(k_lambda V): at small
strain C_D = 2 tr(eps) + O(eps^2), so shear (tr eps = 0) costs energy only at fourth order: no
small-strain shear modulus, and no (k_mu, k_lambda) gives the seed's tets. The other solid
methods: unsupported by name. Rods and fluids: unsupported.

Contacts: Newton's particle-shape ("soft") contacts, found once per scene step by the collision
pipeline within the scene's contactTolerance (soft_contact_gap) of each particle's sphere, and
solved in every substep (SolverXPBD: at position level when the particle's sphere touches;
the explicit solvers: penalty ke, kd = the shapes' contactStiffness, contactDamping). Friction
mu = (soft_contact_mu + shape mu)/2, one soft_contact_mu for all particles: engine.py solves it
with the shapes' values so that every (model, body) pair gets the scene's particleMaterial
friction. Particle restitution is not mapped (Newton's soft contacts here are inelastic). No
particle-particle or self contact (radius 1 mm, far below the cloth's 0.125 m edges); a scene
with two or more particle models, which could touch each other, is unsupported by name.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from pbdval import protocol as pp
from pbdval.external import cloth_bending

CLOTH_METHODS = {0: "none", 4: "xpbd_distance"}
BENDING_METHODS = {0: "none", 3: "isometric_xpbd (matched at one curvature)"}
SOLID_METHODS = {0: "none"}
#: The explicit solvers' (eval_tetrahedra) solid methods.
EXPLICIT_SOLID_METHODS = {0: "none", 3: "fem_xpbd (stable neo-Hookean, small-strain E and nu)"}
#: The Poisson ratios of the seed's FEM solids (adapters/features.cpp: solid.femPoissonOutOfRange).
POISSON_RANGE = (0.0, 0.49)
#: Newton's particle radius (m): the sphere its particle-shape contacts keep off a surface, as
#: thin as mujoco-python's cloth (1 mm).
PARTICLE_RADIUS = 1e-3
#: Newton's bending weight of an edge per unit ke: A_e (SolverXPBD) or |e| A_e (the explicit
#: solvers' eval_bending); see the module comment.
XPBD_BENDING = "xpbd"
EXPLICIT_BENDING = "explicit"


def neo_hookean(young: float, poisson: float) -> tuple[float, float]:
    """(k_mu, k_lambda) of Newton's stable neo-Hookean tets with the small-strain Lame
    parameters of (young, poisson): 4/3 mu and lambda + 5/6 mu (module comment)."""
    mu = young / (2 * (1 + poisson))
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    return 4.0 / 3.0 * mu, lam + 5.0 / 6.0 * mu


def unsupported(scene: pp.ResolvedScene, explicit: bool) -> list[str]:
    """The particle features the newton engine cannot represent, each naming its JSON path;
    `explicit`: under SolverSemiImplicit or SolverFeatherstone (their tets)."""
    missing = pp.unsupported_particle_models(scene, "the newton engine", CLOTH_METHODS, BENDING_METHODS,
                                             EXPLICIT_SOLID_METHODS if explicit else SOLID_METHODS)
    for sm in scene.tet_models:
        poisson = float(sm.material["poissonRatio"])
        low, high = POISSON_RANGE
        if sm.simulation_method in (2, 3) and not low <= poisson <= high:
            missing.append(f"{sm.json_path}: FEM solid with solid_poissonRatio {poisson:g} outside "
                           f"[{low:g}, {high:g}]")
    models = [m.json_path for m in (*scene.triangle_models, *scene.tet_models)]
    if len(models) > 1:
        # The runner's feature table has no row for it: the message starts with "contact", as
        # the engine-only refusals of pair materials do.
        missing.append(f"contact between particle models ({', '.join(models)}): the newton engine lets "
                       "particles touch rigid shapes only (no particle-triangle or particle-tet contact is "
                       "mapped), so the models would pass through each other")
    missing += pp.particles_outside_models(scene)
    return missing


def bending_edges(triangles: np.ndarray) -> list[tuple[int, int, int, int]]:
    """Newton's bending elements (i, j, k, l) of the interior edges: k, l the shared edge, i, j
    the opposite vertices, so that the faces are (i, k, l) and (j, l, k) with the mesh's
    winding (add_edge's convention). Sorted by edge; a non-manifold edge (3 faces) is left out."""
    directed: dict[tuple[int, int], int] = {}
    for a, b, c in np.asarray(triangles, dtype=np.int64):
        for k, l, i in ((a, b, c), (b, c, a), (c, a, b)):
            directed[(int(k), int(l))] = int(i)
    out = []
    for (k, l), i in sorted(directed.items()):
        j = directed.get((l, k))
        if j is not None and k < l:
            out.append((i, j, k, l))
    return out


def dihedral_angles(x: np.ndarray, edges: Iterable[tuple[int, int, int, int]]) -> np.ndarray:
    """theta per bending element, as Newton's kernels compute it (atan2 of the face normals)."""
    theta = []
    for i, j, k, l in edges:
        n1 = np.cross(x[k] - x[i], x[l] - x[i])
        n2 = np.cross(x[l] - x[j], x[k] - x[j])
        e = x[l] - x[k]
        n1, n2, e = n1 / np.linalg.norm(n1), n2 / np.linalg.norm(n2), e / np.linalg.norm(e)
        theta.append(np.arctan2(float(np.cross(n1, n2) @ e), float(n1 @ n2)))
    return np.array(theta)


def bending_weights(x: np.ndarray, edges: Iterable[tuple[int, int, int, int]], kind: str) -> np.ndarray:
    """w_e with Newton's bending potential sum_e ke w_e (theta_e - theta0_e)^2 (module comment):
    A_e, the mean area of the edge's faces (XPBD_BENDING), or |e| A_e (EXPLICIT_BENDING)."""
    weights = []
    for i, j, k, l in edges:
        area = 0.25 * (np.linalg.norm(np.cross(x[k] - x[i], x[l] - x[i]))
                       + np.linalg.norm(np.cross(x[l] - x[j], x[k] - x[j])))
        weights.append(area * (float(np.linalg.norm(x[l] - x[k])) if kind == EXPLICIT_BENDING else 1.0))
    return np.array(weights)


def matched_edge_stiffness(positions: np.ndarray, triangles: np.ndarray, stiffness: float,
                           curvature: float, kind: str) -> float:
    """Newton's edge_ke at which the sheet bent into a cylinder of `curvature` stores the seed's
    XPBD isometric energy (bendingStiffness `stiffness`) of the same cylinder (module comment)."""
    x = np.asarray(positions, dtype=np.float64)
    bent = cloth_bending.cylinder(x, triangles, curvature)
    seed = cloth_bending.isometric_xpbd_energy(cloth_bending.bending_stencils(x, triangles), bent, stiffness)
    edges = bending_edges(triangles)
    rest = dihedral_angles(x, edges)
    per_ke = float(np.sum(bending_weights(bent, edges, kind) * (dihedral_angles(bent, edges) - rest) ** 2))
    return seed / per_ke


@dataclass(frozen=True)
class ParticleLayout:
    """Newton particle n is scene particle n; `dynamic` marks the particles that move."""

    count: int
    dynamic: np.ndarray  # (P,) bool


def add_particles(builder: Any, vector: Any, scene: pp.ResolvedScene, bending_kind: str, curvature: float,
                  settings: dict[str, pp.ParameterValue]) -> ParticleLayout:
    """Adds every scene particle, the cloths' springs and bending edges to Newton's `builder`
    (`vector`: Warp's vec3, which the builder's own arithmetic needs), and records the mapping
    in `settings`."""
    for p in scene.particles:
        static = p.mass <= 0
        velocity = (0.0, 0.0, 0.0) if static else tuple(float(v) for v in p.velocity)
        builder.add_particle(vector(*(float(c) for c in p.position)), vector(*velocity),
                             0.0 if static else float(p.mass), radius=PARTICLE_RADIUS)
    positions = np.array([p.position for p in scene.particles], dtype=np.float64).reshape(-1, 3)
    for tm in scene.triangle_models:
        path, first = tm.json_path, tm.first_particle
        x = positions[first:first + tm.particle_count]
        if tm.simulation_method == 0:
            settings[f"{path}.elasticity"] = "none (method 0, native)"
            continue
        k = float(tm.material["stiffness"])
        springs = cloth_bending.mesh_edges(tm.triangles)
        for a, b in springs:
            builder.add_spring(first + int(a), first + int(b), k, 0.0, 0.0)
        settings[f"{path}.springs"] = (f"{len(springs)} springs ke = {k:g} N/m, kd = 0, one per distinct "
                                       "edge: the XPBD distance constraint's (1/2) k C^2 (native)")
        edges = bending_edges(tm.triangles)
        if tm.bending_method == 3 and curvature > 0 and edges:
            ke = matched_edge_stiffness(x, tm.triangles, float(tm.material["bendingStiffness"]), curvature,
                                        bending_kind)
            for (i, j, k_, l), rest in zip(edges, dihedral_angles(x, edges), strict=True):
                builder.add_edge(first + i, first + j, first + k_, first + l, rest=float(rest), edge_ke=ke,
                                 edge_kd=0.0)
            form = "A_e" if bending_kind == XPBD_BENDING else "|e| A_e"
            settings[f"{path}.bending"] = (
                f"{len(edges)} dihedral edges, edge_ke = {ke:.6g} (approximated): Newton's potential "
                f"ke {form} theta^2 per edge matched to the quartic XPBD isometric bending (k = "
                f"{float(tm.material['bendingStiffness']):g}) on a cylinder of curvature {curvature:g} 1/m")
        else:
            settings[f"{path}.bending"] = ("none (native)" if tm.bending_method == 0 else
                                           f"omitted: method {tm.bending_method} with clothBendingCurvature 0, "
                                           "or a mesh without interior edges")
    for sm in scene.tet_models:
        if sm.simulation_method != 3:
            settings[f"{sm.json_path}.elasticity"] = "none (method 0, native)"
            continue
        young, poisson = float(sm.material["stiffness"]), float(sm.material["poissonRatio"])
        k_mu, k_lambda = neo_hookean(young, poisson)
        for a, b, c, d in np.asarray(sm.tets, dtype=np.int64):
            first = sm.first_particle
            builder.add_tetrahedron(first + int(a), first + int(b), first + int(c), first + int(d),
                                    k_mu=k_mu, k_lambda=k_lambda, k_damp=0.0)
        settings[f"{sm.json_path}.elasticity"] = (
            f"{len(sm.tets)} stable neo-Hookean tets, k_mu = {k_mu:.6g}, k_lambda = {k_lambda:.6g} Pa: the "
            f"small-strain E = {young:g} Pa, nu = {poisson:g} of the seed's St. Venant-Kirchhoff tets "
            "(approximated)")
    masses = np.array([p.mass for p in scene.particles], dtype=np.float64)
    settings["particleRadius"] = PARTICLE_RADIUS
    return ParticleLayout(count=len(scene.particles), dynamic=masses > 0)
