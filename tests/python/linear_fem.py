"""An independent reference for solids: the static solution of linear elasticity on linear
tetrahedra (small strain, isotropic), assembled and solved with numpy alone -- no pbdval code.

For a tet with vertices x_0..x_3 the shape-function gradients g_a = grad N_a are constant
(rows of the inverse of [x_1 - x_0, x_2 - x_0, x_3 - x_0]^T, g_0 = -(g_1 + g_2 + g_3)); with
Lame's mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)) the element stiffness block
between vertices a and b is

    K_ab = V (mu (g_a . g_b) I + mu g_b g_a^T + lambda g_a g_b^T)      (3 x 3),

the Hessian of V (mu eps:eps + lambda/2 (tr eps)^2) with eps = sym(sum_a u_a g_a^T). The load is
the particles' weight m_i g (the masses the scene lumped); static particles are fixed (u = 0).
Used by the reference-engine tests and to derive the cantilever case's expected deflection
(cases/tet_cantilever.json).
"""

from __future__ import annotations

import numpy as np


def lame(young: float, poisson: float) -> tuple[float, float]:
    """(mu, lambda) of Young's modulus and Poisson's ratio."""
    return young / (2 * (1 + poisson)), young * poisson / ((1 + poisson) * (1 - 2 * poisson))


def stiffness_matrix(positions: np.ndarray, tets: np.ndarray, young: float, poisson: float) -> np.ndarray:
    """The (3n x 3n) stiffness matrix, degrees of freedom 3 i + c."""
    mu, lam = lame(young, poisson)
    n = len(positions)
    k = np.zeros((3 * n, 3 * n))
    for tet in tets:
        x = positions[tet]
        edges = (x[1:] - x[0]).T  # columns x_a - x_0
        volume = np.linalg.det(edges) / 6
        if volume <= 0:
            raise ValueError(f"tet {tuple(tet)} is not positively oriented (volume {volume:g})")
        inverse = np.linalg.inv(edges)  # rows: gradients of N_1..N_3
        g = np.vstack([-inverse.sum(axis=0), inverse])
        for a in range(4):
            for b in range(4):
                block = volume * (mu * (g[a] @ g[b]) * np.eye(3) + mu * np.outer(g[b], g[a])
                                  + lam * np.outer(g[a], g[b]))
                k[3 * tet[a]:3 * tet[a] + 3, 3 * tet[b]:3 * tet[b] + 3] += block
    return k


def static_displacement(positions: np.ndarray, tets: np.ndarray, masses: np.ndarray,
                        fixed: np.ndarray, gravity: np.ndarray, young: float,
                        poisson: float) -> np.ndarray:
    """The (n, 3) displacements u solving K u = f, f_i = m_i g, with u_i = 0 for i in `fixed`."""
    k = stiffness_matrix(positions, tets, young, poisson)
    f = (masses[:, None] * np.asarray(gravity)[None, :]).reshape(-1)
    free_nodes = np.setdiff1d(np.arange(len(positions)), fixed)
    free = (3 * free_nodes[:, None] + np.arange(3)[None, :]).reshape(-1)
    u = np.zeros(3 * len(positions))
    u[free] = np.linalg.solve(k[np.ix_(free, free)], f[free])
    return u.reshape(-1, 3)


def tet_lattice(cells: tuple[int, int, int], lower: tuple[float, float, float],
                spacing: float) -> tuple[np.ndarray, np.ndarray]:
    """A block of cubic cells, each split into the six Kuhn tets around its main diagonal
    (corner c at (c & 1, c >> 1 & 1, c >> 2 & 1)), vertex (i, j, k) at index
    i + (nx + 1)(j + (ny + 1) k): the layout of scripts/make-models' tet meshes."""
    nx, ny, nz = cells
    grid = np.array([(lower[0] + spacing * i, lower[1] + spacing * j, lower[2] + spacing * k)
                     for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)])
    kuhn = ((0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7))
    tets = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                corner = [(i + (c & 1)) + (nx + 1) * ((j + (c >> 1 & 1)) + (ny + 1) * (k + (c >> 2 & 1)))
                          for c in range(8)]
                for t in kuhn:
                    tet = [corner[c] for c in t]
                    x = grid[tet]
                    if np.linalg.det((x[1:] - x[0]).T) < 0:
                        tet[2], tet[3] = tet[3], tet[2]
                    tets.append(tet)
    return grid, np.array(tets)


def lumped_masses(positions: np.ndarray, tets: np.ndarray, density: float) -> np.ndarray:
    """A quarter of each tet's mass to each of its vertices."""
    masses = np.zeros(len(positions))
    for tet in tets:
        x = positions[tet]
        masses[tet] += density * abs(np.linalg.det((x[1:] - x[0]).T)) / 24
    return masses


def membrane_static_displacement(positions: np.ndarray, triangles: np.ndarray, masses: np.ndarray,
                                 fixed: np.ndarray, gravity: np.ndarray, stretch: float,
                                 poisson: float) -> np.ndarray:
    """The in-plane static solution of a flat membrane of linear (constant-strain) triangles
    under plane stress, for a load in its plane: (n, 3) displacements u solving K u = f,
    f_i = m_i g (projected onto the plane), u_i = 0 for i in `fixed`. `stretch` is E t (N/m).
    With 2D coordinates in an orthonormal basis of the plane and, per triangle of area A, the
    shape-function gradients g_a (rows of the inverse of [x_1 - x_0, x_2 - x_0]^T,
    g_0 = -(g_1 + g_2)), the element block between vertices a and b is

        K_ab = A (mu (g_a . g_b) I + mu g_b g_a^T + lambda* g_a g_b^T)      (2 x 2),

    mu = E t / (2 (1 + nu)), lambda* = E t nu / (1 - nu^2): the Hessian of
    A (mu eps:eps + lambda*/2 (tr eps)^2), linear plane-stress elasticity."""
    x = np.asarray(positions, dtype=np.float64)
    origin = x[0]
    first = np.asarray(triangles[0])
    e1 = x[first[1]] - x[first[0]]
    e1 /= np.linalg.norm(e1)
    normal = np.cross(x[first[1]] - x[first[0]], x[first[2]] - x[first[0]])
    normal /= np.linalg.norm(normal)
    if np.max(np.abs((x - origin) @ normal)) > 1e-12:
        raise ValueError("the membrane is not flat")
    basis = np.vstack([e1, np.cross(normal, e1)])  # (2, 3)
    p = (x - origin) @ basis.T
    mu = stretch / (2 * (1 + poisson))
    lam = stretch * poisson / (1 - poisson**2)
    n = len(p)
    k = np.zeros((2 * n, 2 * n))
    for tri in np.asarray(triangles):
        edges = (p[tri[1:]] - p[tri[0]]).T
        area = abs(np.linalg.det(edges)) / 2
        inverse = np.linalg.inv(edges)
        g = np.vstack([-inverse.sum(axis=0), inverse])
        for a in range(3):
            for b in range(3):
                block = area * (mu * (g[a] @ g[b]) * np.eye(2) + mu * np.outer(g[b], g[a])
                                + lam * np.outer(g[a], g[b]))
                k[2 * tri[a]:2 * tri[a] + 2, 2 * tri[b]:2 * tri[b] + 2] += block
    f = (masses[:, None] * (basis @ np.asarray(gravity))[None, :]).reshape(-1)
    free_nodes = np.setdiff1d(np.arange(n), fixed)
    free = (2 * free_nodes[:, None] + np.arange(2)[None, :]).reshape(-1)
    u = np.zeros(2 * n)
    u[free] = np.linalg.solve(k[np.ix_(free, free)], f[free])
    displacement: np.ndarray = u.reshape(-1, 2) @ basis
    return displacement
