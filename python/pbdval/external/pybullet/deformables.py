"""Cloth (triangle models) and solids (tet models) as pybullet soft bodies in Bullet's deformable
world (btDeformableMultiBodyDynamicsWorld, `resetSimulation(RESET_USE_DEFORMABLE_WORLD)`);
the mapping and its measured numbers: docs/external-engines.md#pybullet.

What pybullet 3.2.7 does with a soft body, read from its source (bullet3 PhysicsServerCommand
Processor::processDeformable, btDeformableBodySolver, btDeformableBackwardEulerObjective) and
checked by experiment (tests/python/test_pybullet_deformables.py):

* The mesh comes from a file. An OBJ becomes btSoftBodyHelpers::CreateFromTriMesh (one node per
  `v` line, in order; a link per distinct triangle edge), a legacy VTK unstructured grid
  CreateFromVtkFile (one node per point, in order; a tet and its six edges per cell). The nodes
  are read back with getMeshData(MESH_DATA_SIMULATION_MESH) and matched to the scene's particles
  by position (`node_order`): a run stops with an error if that is not a bijection.
* Masses: every node starts at 1 kg and setTotalMass(mass) scales them: **every node of a body
  gets mass/N**. There is no call to set one node's mass (only createSoftBodyAnchor, which sets
  it to 0). So the lumped masses of the scene are replaced by their mean over the dynamic
  particles (the total dynamic mass is kept); the largest relative difference per node is
  recorded in effectiveSettings.approximations.
* Forces: Bullet's deformable world (the default `m_implicit = false`, which pybullet does not
  expose) integrates elastic forces **explicitly** (symplectic Euler: v += h M⁻¹ f(x_n),
  x += h v; damping forces implicitly): stable only for h ω_max < 2. The scene's step is split
  into `substeps` internal steps with h_s ω_max ≤ 1 (`substep_count`, ω_max bounded by
  Gershgorin on the small-strain stiffness).
* Springs (btDeformableMassSpringForce): f = k (‖d‖ − L) d/‖d‖ per link, k in N/m: the XPBD
  distance cloth's k per edge.
* Neo-Hookean (btDeformableNeoHookeanForce) is Smith et al.'s stable Neo-Hookean,
  ψ = μ/2 (I_C − 3) + λ/2 (J − 1 − 3μ/(4λ))² − μ/2 log(I_C + 1), whose small-strain limit is
  linear elasticity with Lamé parameters (3μ/4, λ − 5μ/8), not (μ, λ). For a linear-elastic
  (E, ν) material it therefore gets μ_B = 4/3 μ and λ_B = λ + 5/6 μ (`stable_neo_hookean`).
* Contacts: node–rigid (signed distance of the rigid shape, margin = the soft body's collision
  margin) and node–face between soft bodies, inelastic (no restitution). Friction: the soft
  body's kDF times the rigid body's lateralFriction, or kDF × kDF between two soft bodies
  (btSoftBodyInternals.h).
* Velocities: getMeshData gives positions only (3.2.7 has no velocity flag), so a sample's
  velocity is (x_n − x_{n−1})/h_s over the last internal step, which is Bullet's v_n since its
  update is x_{n+1} = x_n + h_s v_{n+1} (plus a split-impulse term in contact).
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pybullet as pb

from pbdval import protocol as pp
from pbdval.external.cloth_bending import mesh_edges

#: triangle-model simulationMethod → name; only the XPBD distance cloth has a physical
#: stiffness (N/m per edge) that a spring can take.
CLOTH_METHODS = {4: "xpbd_distance"}
#: tet-model simulationMethod → name; FEM-XPBD is linear elasticity (E, ν).
SOLID_METHODS = {3: "fem_xpbd"}
#: bendingMethod values: 0 none; 3 isometric XPBD (physical stiffness), only approximated.
BENDING_NONE, BENDING_ISOMETRIC_XPBD = 0, 3
#: Internal steps keep h_s ω_max at most this (symplectic Euler is stable below 2).
COURANT = 1.0
#: Positions read back from a mesh file are matched to the scene's within this many metres
#: (the files are written with 17 significant digits, so the match is exact up to round-off).
MATCH_TOLERANCE = 1e-9
#: Bullet's default sparse-SDF voxel size of the deformable world, m (not changed here).
SPARSE_SDF_VOXEL = 0.005


@dataclass
class SoftModel:
    """One triangle or tet model as loaded: its scene slice and its pybullet body."""

    json_path: str
    kind: str  # "cloth" | "solid"
    first: int
    count: int
    body: int = -1
    #: order[i] = pybullet's node index of the model's local particle i
    order: np.ndarray | None = None
    node_mass: float = 0.0
    mass_difference: float = 0.0  # max over dynamic particles of |m_B − m_i| / m_i
    friction: float = 0.0  # kDF (frictionCoeff)


def models(scene: Any) -> list[tuple[str, Any]]:
    """("cloth", TriangleModel) … then ("solid", TetModel) …, in particle order."""
    return ([("cloth", m) for m in scene.triangle_models] +
            [("solid", m) for m in scene.tet_models])


def has_deformables(scene: Any) -> bool:
    return bool(scene.triangle_models) or bool(scene.tet_models)


def unsupported_features(scene: Any) -> list[str]:
    """What this mapping cannot represent, each naming its model."""
    missing = pp.unsupported_particle_models(scene, "Bullet's deformables", CLOTH_METHODS,
                                             (BENDING_NONE, BENDING_ISOMETRIC_XPBD), SOLID_METHODS)
    for m in scene.tet_models:
        if m.simulation_method in SOLID_METHODS:
            nu = float(m.material.get("poissonRatio", 0.3))
            if not 0.0 <= nu < 0.5:
                missing.append(f"{m.json_path}: poissonRatio {nu} (Neo-Hookean needs "
                               "0 <= nu < 0.5)")
    if has_deformables(scene):
        moving = [i for i, p in enumerate(scene.particles)
                  if p.mass > 0 and any(v != 0.0 for v in p.velocity)]
        if moving:
            missing.append(f"particles[{moving[0]}]: initial particle velocity (pybullet 3.2.7 "
                           "cannot set a soft body's node velocities)")
        covered = sum(m.particle_count for _, m in models(scene))
        if covered != len(scene.particles):
            missing.append(f"particles: {len(scene.particles) - covered} particles outside the "
                           "triangle and tet models")
    return missing


def lame(young: float, poisson: float) -> tuple[float, float]:
    """Lamé parameters (μ, λ) of E and ν."""
    return young / (2 * (1 + poisson)), young * poisson / ((1 + poisson) * (1 - 2 * poisson))


def stable_neo_hookean(young: float, poisson: float) -> tuple[float, float]:
    """Bullet's NeoHookeanMu, NeoHookeanLambda whose small-strain limit is linear elasticity
    (E, ν): the stable Neo-Hookean linearises to (3/4 μ_B, λ_B − 5/8 μ_B) (Smith, de Goes and
    Kim 2018, sec. 3.4), so μ_B = 4/3 μ and λ_B = λ + 5/6 μ."""
    mu, lam = lame(young, poisson)
    return 4.0 * mu / 3.0, lam + 5.0 * mu / 6.0


def write_obj(path: str, positions: np.ndarray, triangles: np.ndarray) -> None:
    """One `v` per particle in order (17 significant digits: exact in double), one `f` per
    triangle (1-based)."""
    with open(path, "w", encoding="ascii") as f:
        f.writelines(f"v {float(x[0]):.17g} {float(x[1]):.17g} {float(x[2]):.17g}\n" for x in positions)
        f.writelines(f"f {int(t[0]) + 1} {int(t[1]) + 1} {int(t[2]) + 1}\n" for t in triangles)


def write_vtk(path: str, positions: np.ndarray, tets: np.ndarray) -> None:
    """A legacy VTK unstructured grid as Bullet's reader wants it: one point per line, one
    cell "4 a b c d" per line, cell type 10 (tetra)."""
    with open(path, "w", encoding="ascii") as f:
        f.write("# vtk DataFile Version 2.0\npbdval tet model\nASCII\nDATASET UNSTRUCTURED_GRID\n")
        f.write(f"POINTS {len(positions)} double\n")
        f.writelines(f"{float(x[0]):.17g} {float(x[1]):.17g} {float(x[2]):.17g}\n" for x in positions)
        f.write(f"\nCELLS {len(tets)} {5 * len(tets)}\n")
        f.writelines(f"4 {int(t[0])} {int(t[1])} {int(t[2])} {int(t[3])}\n" for t in tets)
        f.write(f"\nCELL_TYPES {len(tets)}\n")
        f.writelines("10\n" for _ in range(len(tets)))


def node_order(loaded: np.ndarray, expected: np.ndarray, what: str) -> np.ndarray:
    """order[i] = the index in `loaded` of the expected particle i, matched by position (within
    MATCH_TOLERANCE); ValueError unless it is a bijection."""
    if len(loaded) != len(expected):
        raise ValueError(f"{what}: pybullet made {len(loaded)} nodes of {len(expected)} particles")
    if np.array_equal(loaded, expected):
        return np.arange(len(expected))
    order = np.empty(len(expected), dtype=np.int64)
    for i, x in enumerate(expected):
        d = np.linalg.norm(loaded - x, axis=1)
        hits = np.flatnonzero(d <= MATCH_TOLERANCE)
        if len(hits) != 1:
            raise ValueError(f"{what}: particle {i} at {x.tolist()} matches {len(hits)} pybullet "
                             "nodes (the node order cannot be mapped one to one)")
        order[i] = hits[0]
    if len(set(order.tolist())) != len(order):
        raise ValueError(f"{what}: two particles map to one pybullet node")
    return order


def second_neighbours(edges: np.ndarray, count: int) -> np.ndarray:
    """Pairs (i < j) at graph distance exactly 2: where Bullet's generateBendingConstraints(2)
    puts its bending springs."""
    neighbours: list[set[int]] = [set() for _ in range(count)]
    for a, b in edges:
        neighbours[a].add(int(b))
        neighbours[b].add(int(a))
    pairs = set()
    for i in range(count):
        for j in neighbours[i]:
            for k in neighbours[j]:
                if k > i and k not in neighbours[i]:
                    pairs.add((i, k))
    return np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2)


def spring_row_sums(positions: np.ndarray, pairs: np.ndarray, k: float) -> np.ndarray:
    """Σ_j |K_ij| per degree of freedom (count, 3) of springs k d̂d̂ᵀ at rest."""
    sums = np.zeros_like(positions)
    if len(pairs) == 0 or k == 0:
        return sums
    d = positions[pairs[:, 1]] - positions[pairs[:, 0]]
    d /= np.linalg.norm(d, axis=1)[:, None]
    row = 2.0 * k * np.abs(d) * np.abs(d).sum(axis=1)[:, None]  # diagonal and off-diagonal block
    np.add.at(sums, pairs[:, 0], row)
    np.add.at(sums, pairs[:, 1], row)
    return sums


def tet_row_sums(positions: np.ndarray, tets: np.ndarray, young: float,
                 poisson: float) -> np.ndarray:
    """Σ_j |K_ij| per degree of freedom of the linear-elastic (small-strain) tet stiffness
    K_e = V Bᵀ D B, which Bullet's Neo-Hookean with stable_neo_hookean's parameters has at
    rest."""
    mu, lam = lame(young, poisson)
    x = positions[tets]  # (n, 4, 3)
    dm = np.transpose(x[:, 1:] - x[:, :1], (0, 2, 1))  # columns x_a − x_0
    volume = np.abs(np.linalg.det(dm)) / 6.0
    inv = np.linalg.inv(dm)  # rows: ∇N_1..3
    grads = np.concatenate([-inv.sum(axis=1, keepdims=True), inv], axis=1)  # (n, 4, 3)
    # K_e[a i, b j] = V (μ g_a·g_b δ_ij + μ g_a_j g_b_i + λ g_a_i g_b_j)
    gg = np.einsum("nai,nbi->nab", grads, grads)
    ke = (mu * gg[:, :, None, :, None] * np.eye(3)[None, None, :, None, :]
          + mu * np.einsum("naj,nbi->naibj", grads, grads)
          + lam * np.einsum("nai,nbj->naibj", grads, grads)) * volume[:, None, None, None, None]
    rows = np.abs(ke).sum(axis=(3, 4))  # (n, 4, 3)
    sums = np.zeros_like(positions)
    np.add.at(sums, tets, rows)
    return sums


def omega_max_bound(row_sums: np.ndarray, node_mass: float, dynamic: np.ndarray) -> float:
    """Gershgorin's bound on the highest angular frequency, √(max_i Σ_j |K_ij| / m)."""
    if not dynamic.any() or node_mass <= 0:
        return 0.0
    return math.sqrt(float(row_sums[dynamic].max()) / node_mass)


def substep_count(step: float, omega: float) -> int:
    """The fewest internal steps with (step / n) ω ≤ COURANT."""
    return max(1, math.ceil(step * omega / COURANT - 1e-12))


class SoftBodies:
    """The scene's triangle and tet models loaded into a deformable world: `models` (scene
    order), `omega` (the bound on ω_max over all of them), `notes` (approximations made)."""

    def __init__(self, client: int, scene: Any, folder: str, margin: float,
                 bending_spring_stiffness: float, friction: Sequence[float]) -> None:
        self.client = client
        self.folder = folder
        self.bending_spring_stiffness = bending_spring_stiffness
        self.models: list[SoftModel] = []
        self.notes: list[str] = []
        self.positions0 = np.array([p.position for p in scene.particles], dtype=np.float64)
        self.masses = np.array([p.mass for p in scene.particles], dtype=np.float64)
        self.omega = 0.0
        for index, (kind, m) in enumerate(models(scene)):
            self._load(index, kind, m, margin, float(friction[index]))
        worst = max((sm.mass_difference, sm.json_path) for sm in self.models)
        if worst[0] > 1e-12:
            self.notes.append(
                "particle masses: pybullet gives every node of a soft body the same mass (the "
                "model's dynamic mass over its dynamic nodes); largest relative difference from "
                f"the scene's lumped masses {worst[0]:.3g} ({worst[1]})")
        can_touch = len(self.models) > 1 or any(b.shape.type != "none" for b in scene.bodies)
        if can_touch and any(m.restitution != 0 for _, m in models(scene)):
            self.notes.append("particle contacts are inelastic in Bullet's deformable solver "
                              "(the models' restitution is not used)")

    def _load(self, index: int, kind: str, m: Any, margin: float, friction: float) -> None:
        first, count = m.first_particle, m.particle_count
        x = self.positions0[first:first + count]
        masses = self.masses[first:first + count]
        static = {int(i) for i in m.static_particles} | set(np.flatnonzero(masses <= 0).tolist())
        dynamic = np.ones(count, dtype=bool)
        dynamic[sorted(static)] = False
        model = SoftModel(m.json_path, kind, first, count, friction=friction)
        # Uniform node masses keeping the dynamic mass: m_B = Σ m_i / (dynamic count).
        model.node_mass = float(masses[dynamic].sum()) / max(1, int(dynamic.sum()))
        if dynamic.any():
            model.mass_difference = float(np.max(np.abs(model.node_mass - masses[dynamic]) /
                                                 masses[dynamic]))
        common: dict[str, Any] = {"scale": 1.0, "mass": model.node_mass * count,
                                  "collisionMargin": margin, "frictionCoeff": friction,
                                  "physicsClientId": self.client}
        if kind == "cloth":
            body, row_sums = self._cloth(index, m, x, common)
        else:
            body, row_sums = self._solid(index, m, x, common)
        if body < 0:
            raise RuntimeError(f"{m.json_path}: pybullet could not load the soft body")
        model.body = body
        model.order = node_order(self._nodes(body), x, m.json_path)
        # No sleeping: a resting soft body must keep being simulated.
        pb.changeDynamics(body, -1, activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING,
                          physicsClientId=self.client)
        for i in sorted(static):
            pb.createSoftBodyAnchor(body, int(model.order[i]), -1, -1, physicsClientId=self.client)
        self.omega = max(self.omega, omega_max_bound(row_sums, model.node_mass, dynamic))
        self.models.append(model)

    def _cloth(self, index: int, m: Any, x: np.ndarray,
               common: dict[str, Any]) -> tuple[int, np.ndarray]:
        """A mass-spring soft body of k per edge (and bending springs if asked for)."""
        path = os.path.join(self.folder, f"model{index}.obj")
        triangles = np.asarray(m.triangles, dtype=np.int64)
        write_obj(path, x, triangles)
        k = float(m.material["stiffness"])
        edges = mesh_edges(triangles)
        row_sums = spring_row_sums(x, edges, k)
        springs: dict[str, Any] = {"useMassSpring": 1, "springElasticStiffness": k,
                                   "springDampingStiffness": 0.0, "useNeoHookean": 0}
        bending = self.bending_spring_stiffness
        if m.bending_method == BENDING_ISOMETRIC_XPBD and bending > 0:
            springs.update(useBendingSprings=1, springBendingStiffness=bending)
            row_sums = row_sums + spring_row_sums(x, second_neighbours(edges, len(x)), bending)
            self._note_once(f"{m.json_path}: isometric XPBD bending (clothBendingMethod 3) as "
                            "Bullet's bending springs between second neighbours, k = "
                            f"{bending:g} N/m (they also resist in-plane shear, and resist a "
                            "fold of a flat sheet only at second order)")
        elif m.bending_method == BENDING_ISOMETRIC_XPBD:
            self._note_once(f"{m.json_path}: isometric XPBD bending (clothBendingMethod 3) left "
                            "out: Bullet's deformables have no bending energy (parameter "
                            "bendingSpringStiffness adds bending springs instead)")
        return pb.loadSoftBody(path, **springs, **common), row_sums

    def _solid(self, index: int, m: Any, x: np.ndarray,
               common: dict[str, Any]) -> tuple[int, np.ndarray]:
        """A Neo-Hookean soft body whose small-strain limit is the scene's (E, ν)."""
        path = os.path.join(self.folder, f"model{index}.vtk")
        tets = np.asarray(m.tets, dtype=np.int64)
        write_vtk(path, x, tets)
        young = float(m.material["stiffness"])
        poisson = float(m.material.get("poissonRatio", 0.3))
        mu_b, lambda_b = stable_neo_hookean(young, poisson)
        body = pb.loadSoftBody(path, useNeoHookean=1, NeoHookeanMu=mu_b,
                               NeoHookeanLambda=lambda_b, NeoHookeanDamping=0.0,
                               useMassSpring=0, **common)
        return body, tet_row_sums(x, tets, young, poisson)

    def _note_once(self, note: str) -> None:
        if note not in self.notes:
            self.notes.append(note)

    def _nodes(self, body: int) -> np.ndarray:
        _, vertices = pb.getMeshData(body, -1, flags=pb.MESH_DATA_SIMULATION_MESH,
                                     physicsClientId=self.client)
        return np.array(vertices, dtype=np.float64).reshape(-1, 3)

    def positions(self) -> np.ndarray:
        """Every particle's position (scene order), (P, 3)."""
        out = np.empty_like(self.positions0)
        for m in self.models:
            out[m.first:m.first + m.count] = self._nodes(m.body)[m.order]
        return out
