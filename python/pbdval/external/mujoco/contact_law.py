"""The contact law of the MuJoCo engines: a mass-normalised Kelvin-Voigt spring-damper per pair.

With MuJoCo's direct solref = (-stiffness, -damping) and a constant impedance d (solimp
d0 = d_width = d), the impedance-weighted reference acceleration is exactly a damped oscillator,
d a_ref = -damping r' - stiffness r, so a contact is a spring with omega = 1/tau and damping
ratio zeta = damping / (2 omega) (docs/methods.md, "Contacts"; the same law as the built-in
engine, adapters/mujoco/contact_softness.h).

Restitution of such a contact that lets go when its force reaches zero (Schwager & Poeschel
2007, Granular Matter 9):
  e(zeta) = exp(-zeta phi / sqrt(1 - zeta^2)), phi = atan2(2 zeta sqrt(1 - zeta^2), 2 zeta^2 - 1)
  e(1) = exp(-2)
  e(zeta) = exp(-zeta psi / sqrt(zeta^2 - 1)), psi = ln((zeta + s) / (zeta - s)), s = sqrt(zeta^2 - 1)
e falls monotonically from 1 to 0, so zeta(e) is found by bisection. The damping is explicit in
the time step: zeta is capped at tau / (2 h), and smaller restitutions are clamped to e(cap).
"""

from __future__ import annotations

import math
from dataclasses import dataclass


def restitution_of_damping_ratio(zeta: float) -> float:
    if zeta <= 0:
        return 1.0
    if zeta < 1:
        root = math.sqrt(1 - zeta * zeta)
        phase = math.atan2(2 * zeta * root, 2 * zeta * zeta - 1)
        return math.exp(-zeta * phase / root)
    if zeta == 1:
        return math.exp(-2.0)
    root = math.sqrt(zeta * zeta - 1)
    return math.exp(-zeta * math.log((zeta + root) / (zeta - root)) / root)


def damping_ratio_for_restitution(restitution: float, max_damping_ratio: float) -> float:
    """zeta in [0, max] with e(zeta) = restitution; max when restitution < e(max)."""
    if restitution >= 1:
        return 0.0
    if restitution <= restitution_of_damping_ratio(max_damping_ratio):
        return max_damping_ratio
    low, high = 0.0, max_damping_ratio  # e(low) > restitution >= e(high)
    while high - low > 1e-15 * max_damping_ratio:
        middle = 0.5 * (low + high)
        if restitution_of_damping_ratio(middle) > restitution:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


@dataclass(frozen=True)
class DirectSolref:
    stiffness: float  # 1/tau^2, 1/s^2
    damping: float  # 2 zeta / tau, 1/s
    damping_ratio: float


def contact_solref(time_constant: float, step_size: float, restitution: float) -> DirectSolref:
    zeta = damping_ratio_for_restitution(restitution, time_constant / (2 * step_size))
    return DirectSolref(stiffness=1 / time_constant**2, damping=2 * zeta / time_constant,
                        damping_ratio=zeta)
