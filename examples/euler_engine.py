"""A minimal external engine: semi-implicit (symplectic) Euler for free rigid bodies.

The template to copy for a new engine (docs/external-engines.md). Run by the runner as

    .venv/bin/python examples/euler_engine.py --scene RESOLVED.json --out OUTDIR

Per step of size h, for every dynamic body (centre of mass x, velocity v, angular velocity w
and principal-frame orientation q, all in world):

    v += h g                       x += h v
    w += h I⁻¹ (−w × I w)          q += (h/2) (0, w) ⊗ q,  normalised

(the gyroscopic term explicit, I = R diag(I_p) Rᵀ with R of q). Free fall is therefore
x_n = x_0 + n h v_0 + n(n+1)/2 h² g, the semi-implicit Euler closed form. Joints, contacts and
particles are reported as unsupported, by name.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

# The runner puts the source tree's python/ first on PYTHONPATH for a "{python}" command
# (docs/external-engines.md#the-catalogue): pbdval imports as an installed package would.
from pbdval import protocol as pp

ENGINE_VERSION = "example-euler 1"
METHOD = "example-euler.symplectic"


def unsupported_features(scene: pp.ResolvedScene) -> list[str]:
    """Everything this engine cannot simulate, each by a name the runner reports."""
    missing = sorted({f"joint:{j.type}" for j in scene.joints})
    if scene.contact_pairs:
        missing.append("contacts")
    if scene.particles or scene.triangle_models or scene.tet_models:
        missing.append("particles")
    if scene.method.name not in ("", METHOD):
        missing.append(f"method:{scene.method.name}")
    return missing


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def run(scene: pp.ResolvedScene, out_dir: Path) -> pp.Status:
    h = scene.time_step_size
    g = np.array(scene.gravity)
    x = [np.array(b.position) for b in scene.bodies]
    v = [np.array(b.velocity) for b in scene.bodies]
    w = [np.array(b.angular_velocity) for b in scene.bodies]
    q = [np.array(b.world_principal_rotation) for b in scene.bodies]

    def states() -> list[pp.BodyState]:
        # The CSV's rotation is the scene frame's: q_world_scene = q_world_principal ⊗ q_scene_principal⁻¹.
        return [pp.BodyState(b.id, x[i], pp.quat_multiply(q[i], pp.quat_conjugate(b.principal_rotation)),
                             v[i], w[i]) for i, b in enumerate(scene.bodies)]

    def step() -> None:
        for i, b in enumerate(scene.bodies):
            if not b.dynamic:
                continue
            v[i] = v[i] + h * g
            x[i] = x[i] + h * v[i]
            r = rotation_matrix(q[i])
            inertia = r @ np.diag(b.principal_inertia) @ r.T
            w[i] = w[i] + h * np.linalg.solve(inertia, -np.cross(w[i], inertia @ w[i]))
            q[i] = q[i] + 0.5 * h * np.array(pp.quat_multiply((0.0, *w[i]), q[i]))
            q[i] = q[i] / np.linalg.norm(q[i])

    status = pp.simulate(scene, out_dir, step, lambda t: states())
    status.engine_version = ENGINE_VERSION
    status.effective_settings = {"integrator": "semi-implicit Euler"}
    return status


def main(argv: list[str] | None = None) -> int:
    return pp.serve(argv, __doc__.splitlines()[0], unsupported_features, run, ENGINE_VERSION)


if __name__ == "__main__":
    sys.exit(main())
