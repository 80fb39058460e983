"""The seed's XPBD isometric bending (clothBendingMethod 3; Bergou et al., "A Quadratic Bending
Model for Inextensible Surfaces", SGP 2006) as plain numpy: its stencils, its energy, and the
flat sheet bent into a cylinder, on which the external engines that have another bending model
(MuJoCo's flexes, Newton's dihedral edges) match their stiffness to it at one curvature
(docs/external-engines.md, docs/engine-newton.md#cloth); and the mesh's distinct edges, which
the engines' springs follow. numpy only: no engine is imported.
"""

from __future__ import annotations

import numpy as np

Stencil = tuple[list[int], np.ndarray, float]


def mesh_edges(triangles: np.ndarray) -> np.ndarray:
    """The distinct edges (i < j) of a triangle mesh, sorted."""
    t = np.asarray(triangles, dtype=np.int64)
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def bending_stencils(positions: np.ndarray, triangles: np.ndarray) -> list[Stencil]:
    """The seed's isometric-bending stencils at `positions` (the rest state), one per interior
    edge (x0, x1) with opposite vertices x2, x3: (indices, K, 3/(A0 + A1)),
    K = (cot b0 + cot b1, cot a0 + cot a1, -cot a0 - cot b0, -cot a1 - cot b1), a at x0 and b at
    x1 in each triangle (pbd/constraints/isometric_bending.h)."""
    x = np.asarray(positions, dtype=np.float64)
    faces: dict[tuple[int, int], list[int]] = {}
    for a, b, c in np.asarray(triangles, dtype=np.int64):
        for i, j, k in ((a, b, c), (b, c, a), (c, a, b)):
            faces.setdefault((min(int(i), int(j)), max(int(i), int(j))), []).append(int(k))

    def cot(at: np.ndarray, p: np.ndarray, q: np.ndarray) -> float:
        u, v = p - at, q - at
        return float(u @ v) / float(np.linalg.norm(np.cross(u, v)))

    stencils = []
    for (i, j), opposite in sorted(faces.items()):
        if len(opposite) != 2:
            continue
        k, m = opposite
        x0, x1, x2, x3 = x[i], x[j], x[k], x[m]
        a0, b0, a1, b1 = cot(x0, x1, x2), cot(x1, x0, x2), cot(x0, x1, x3), cot(x1, x0, x3)
        weights = np.array([b0 + b1, a0 + a1, -a0 - b0, -a1 - b1])
        area = 0.5 * (np.linalg.norm(np.cross(x1 - x0, x2 - x0)) + np.linalg.norm(np.cross(x1 - x0, x3 - x0)))
        stencils.append(([i, j, k, m], weights, float(3.0 / area)))
    return stencils


def isometric_xpbd_energy(stencils: list[Stencil], x: np.ndarray, stiffness: float) -> float:
    """The seed's XPBD bending potential, sum of (1/2) k C^2 with C = (scale/2) |sum K_i x_i|^2."""
    total = 0.0
    for indices, weights, scale in stencils:
        h = weights @ x[indices]
        c = 0.5 * scale * float(h @ h)
        total += 0.5 * stiffness * c * c
    return total


def cylinder(positions: np.ndarray, triangles: np.ndarray, curvature: float) -> np.ndarray:
    """The flat sheet bent into a cylinder of `curvature` (an isometry of its plane): arc length
    along u, the direction of the first triangle's first edge, wraps onto a circle of radius
    1/curvature that bulges along the sheet's normal."""
    x = np.asarray(positions, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)[0]
    u = x[t[1]] - x[t[0]]
    u /= np.linalg.norm(u)
    n = np.cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]])
    n /= np.linalg.norm(n)
    s = (x - x.mean(axis=0)) @ u
    radius = 1.0 / curvature
    return (x + np.outer(radius * np.sin(s / radius) - s, u)
            + np.outer(radius * (1 - np.cos(s / radius)), n))
