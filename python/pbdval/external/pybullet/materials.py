"""Per-body friction and restitution whose products are the scene's pair values.

Bullet combines the materials of two colliding objects by multiplication (btManifoldResult:
friction f_a f_b clamped to 10, restitution e_a e_b), and pybullet exposes no per-pair hook. The
scene gives every contact pair its own combined value (Scene::pairMaterial). This module looks
for per-body values m_i with m_i m_j = M_ij for every pair (i, j) of the resolved scene:

* a body whose pairs are all 0 gets 0 (0 × anything = 0);
* the other pairs must be positive; taking logarithms, y_i + y_j = log M_ij is a linear system,
  solved in the least-squares sense (numpy.linalg.lstsq, minimum norm);
* the solution is accepted when every product reproduces its pair value to a relative 1e-9
  (round-off of exp/log on a handful of pairs is ~1e-15).

Otherwise the pairs are not a product of per-body values and the engine reports the feature
unsupported. A body that is static and in no pair gets 1.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

#: Relative agreement demanded of m_i m_j with M_ij (see the module docstring).
PRODUCT_TOLERANCE = 1e-9
#: Bullet clamps a combined friction to this value (btManifoldResult::calculateCombinedFriction).
BULLET_MAX_FRICTION = 10.0


def per_body_factors(body_count: int, pairs: Sequence[tuple[int, int, float]]) -> list[float] | None:
    """Factors m_i (indexed 0..body_count-1) with m_i m_j = value for every (i, j, value), or
    None when no such factors exist."""
    factors = [1.0] * body_count
    involved: dict[int, list[float]] = {}
    for i, j, value in pairs:
        if value < 0 or not math.isfinite(value):
            return None
        involved.setdefault(i, []).append(value)
        involved.setdefault(j, []).append(value)
    zero = {b for b, values in involved.items() if all(v == 0 for v in values)}
    for b in zero:
        factors[b] = 0.0
    positive = [(i, j, v) for i, j, v in pairs if i not in zero and j not in zero]
    if any(v == 0 for _, _, v in positive):
        return None  # a zero pair between bodies that also have positive pairs
    if positive:
        unknowns = sorted({b for i, j, _ in positive for b in (i, j)})
        column = {b: k for k, b in enumerate(unknowns)}
        a = np.zeros((len(positive), len(unknowns)))
        rhs = np.zeros(len(positive))
        for row, (i, j, v) in enumerate(positive):
            a[row, column[i]] += 1.0
            a[row, column[j]] += 1.0
            rhs[row] = math.log(v)
        solution, *_ = np.linalg.lstsq(a, rhs, rcond=None)
        for b, k in column.items():
            factors[b] = math.exp(float(solution[k]))
    for i, j, v in pairs:
        product = factors[i] * factors[j]
        if abs(product - v) > PRODUCT_TOLERANCE * max(abs(v), 1e-300) and not (v == 0 and product == 0):
            return None
    return factors
