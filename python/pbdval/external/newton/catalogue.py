"""newton's catalogue entry, declared once; engines/newton.json is generated from here:

    .venv/bin/python -m pbdval.external.newton --catalogue > engines/newton.json

(tests/python/test_newton.py checks that the shipped file is current). Standard library only.
"""

from __future__ import annotations

import json
from typing import Any

from pbdval.external.newton.features import FEATURES

ENGINE = "newton"
NEWTON_VERSION = "1.8.0"
WARP_VERSION = "1.19.0"
#: method suffix → (Newton's solver class, description)
SOLVERS = {
    "xpbd": ("SolverXPBD", ("extended position-based dynamics (Macklin et al. 2016; rigid bodies as in "
                            "Müller et al. 2020), maximal coordinates")),
    "featherstone": ("SolverFeatherstone", ("Featherstone's articulated-body algorithm in reduced "
                                            "coordinates, semi-implicit Euler, penalty contacts")),
    "semiImplicit": ("SolverSemiImplicit", ("semi-implicit Euler in maximal coordinates, joints and "
                                            "contacts as penalty forces")),
}
DEFAULT_METHOD = f"{ENGINE}.xpbd"
#: SolverXPBD's joint relaxation here, linear and angular alike (Newton's defaults, 0.7 and 0.4,
#: give a positional joint row's rotational correction 0.4/0.7 of its translational one: the
#: bodies then turn under joint forces as if their inertia about the centre of mass were 1.75×
#: larger; docs/engine-newton.md#relaxation). Newton's angular default for both: at its linear
#: default, 0.7, for both, SolverXPBD's Jacobi sweeps overshoot and robot_dm_acrobot and
#: robot_pendulum5 diverge (at 0.4 they run, as at Newton's defaults).
JOINT_RELAXATION = 0.4

_COMMON: list[dict[str, Any]] = [
    {"name": "angularDamping", "kind": "real", "default": 0.0, "min": 0.0, "max": 1000.0, "unit": "1/s",
     "description": "Newton's angular damping of rigid bodies (its default 0.05 for Featherstone and "
                    "semi-implicit; 0 here, as the scene's bodies are undamped)"},
    {"name": "clothBendingCurvature", "kind": "real", "default": 2.0, "min": 0.0, "max": 1000.0, "unit": "1/m",
     "description": "curvature at which Newton's dihedral edge bending (quadratic in the angle) is matched to "
                    "the quartic XPBD isometric bending (clothBendingMethod 3): both store the same energy on "
                    "the cloth bent into a cylinder of this curvature (docs/engine-newton.md#cloth); 0: no "
                    "bending"},
]
_PER_SOLVER: dict[str, list[dict[str, Any]]] = {
    "xpbd": [
        {"name": "iterations", "kind": "integer", "default": 2, "min": 1, "max": 100000, "unit": "",
         "description": "constraint projection iterations per step (SolverXPBD's default 2)"},
        {"name": "substeps", "kind": "integer", "default": 1, "min": 1, "max": 10000, "unit": "",
         "description": "solver steps per scene step (collision once per scene step)"},
        {"name": "jointLinearRelaxation", "kind": "real", "default": JOINT_RELAXATION, "min": 0.0, "max": 1.0,
         "unit": "", "description": "SolverXPBD joint_linear_relaxation: the factor on a positional joint "
                                    "row's linear correction (Newton's default 0.7)"},
        {"name": "jointAngularRelaxation", "kind": "real", "default": JOINT_RELAXATION, "min": 0.0, "max": 1.0,
         "unit": "", "description": "SolverXPBD joint_angular_relaxation: the factor on an angular joint row "
                                    "and on the rotational part of a positional row's correction (Newton's "
                                    "default 0.4; unequal to the linear one it scales the joint's torque on "
                                    "each body by angular/linear: docs/engine-newton.md#relaxation)"},
    ],
    "featherstone": [
        {"name": "substeps", "kind": "integer", "default": 10, "min": 1, "max": 10000, "unit": "",
         "description": "solver steps per scene step: penalty contacts and joints are explicit"},
        {"name": "contactStiffness", "kind": "real", "default": 1e5, "min": 0.0, "max": 1e12, "unit": "N/m",
         "description": "penalty contact stiffness ke of every shape"},
        {"name": "contactDamping", "kind": "real", "default": 1e3, "min": 0.0, "max": 1e12, "unit": "N s/m",
         "description": "penalty contact damping kd of every shape"},
    ],
    "semiImplicit": [
        {"name": "substeps", "kind": "integer", "default": 10, "min": 1, "max": 10000, "unit": "",
         "description": "solver steps per scene step: penalty contacts and joints are explicit"},
        {"name": "contactStiffness", "kind": "real", "default": 1e5, "min": 0.0, "max": 1e12, "unit": "N/m",
         "description": "penalty contact stiffness ke of every shape"},
        {"name": "contactDamping", "kind": "real", "default": 1e3, "min": 0.0, "max": 1e12, "unit": "N s/m",
         "description": "penalty contact damping kd of every shape"},
        {"name": "jointStiffness", "kind": "real", "default": 1e4, "min": 0.0, "max": 1e12, "unit": "",
         "description": "joint attachment stiffness (SolverSemiImplicit joint_attach_ke, its default)"},
        {"name": "jointDamping", "kind": "real", "default": 100.0, "min": 0.0, "max": 1e12, "unit": "",
         "description": "joint attachment damping (SolverSemiImplicit joint_attach_kd, its default)"},
    ],
}


def parameters(solver: str) -> list[dict[str, Any]]:
    return _COMMON + _PER_SOLVER[solver]


def default(solver: str, name: str) -> Any:
    return next(p["default"] for p in parameters(solver) if p["name"] == name)


def catalogue() -> dict[str, Any]:
    """engines/newton.json as a document."""
    return {
        "protocol": 1,
        "name": ENGINE,
        "description": f"NVIDIA Newton {NEWTON_VERSION} on Warp {WARP_VERSION}'s CPU kernels "
                       "(python/pbdval/external/newton/, run as python -m pbdval.external.newton; "
                       "docs/engine-newton.md): float32 state, kernels compiled once into "
                       "build/cache/warp",
        # Warp's CPU kernels make newton.xpbd take 158 s for the case library with 2 jobs (DART:
        # 15 s): named with --engines, not in the routine run (docs/engine-newton.md#cost).
        "runByDefault": False,
        "command": ["{python}", "-m", "pbdval.external.newton"],
        "serve": {"protocol": 1, "command": ["{python}", "-m", "pbdval.external.newton", "--serve"]},
        "defaultMethod": DEFAULT_METHOD,
        "version": f"newton {NEWTON_VERSION}, warp-lang {WARP_VERSION}",
        "methods": [{"name": f"{ENGINE}.{s}", "description": f"{cls}: {text}", "parameters": parameters(s)}
                    for s, (cls, text) in SOLVERS.items()],
        "features": FEATURES,
    }


def catalogue_text() -> str:
    return json.dumps(catalogue(), indent=2, ensure_ascii=False) + "\n"
