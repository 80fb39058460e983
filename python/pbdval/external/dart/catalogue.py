"""dart's catalogue entry, declared once; engines/dart.json is generated from here:

    .venv/bin/python -m pbdval.external.dart --catalogue > engines/dart.json

(tests/python/test_dart.py checks that the shipped file is current). The engine takes its
parameter defaults from here. Standard library only.
"""

from __future__ import annotations

import json
from typing import Any

from pbdval.external.dart.features import FEATURES

ENGINE = "dart"
#: The dartpy release the catalogue announces (the test compares it with dartpy.__version__).
#: 6.20.0, not 6.20.3: PyPI has 6.20.1+ wheels for CPython 3.12 and later only, and the
#: project's venv is CPython 3.11 (docs/engine-dart.md#version).
DART_VERSION = "6.20.0"
#: method suffix → (the boxed LCP solver, description)
SOLVERS = {
    "dantzig": "DantzigBoxedLcpSolver: Dantzig's pivoting method on the boxed LCP of contacts and "
               "joint limits (DART's default), PGS as its fallback",
    "pgs": "PgsBoxedLcpSolver: projected Gauss-Seidel on the boxed LCP",
}
DEFAULT_METHOD = f"{ENGINE}.dantzig"
#: collisionDetector choice → DART's class
DETECTORS = {"fcl": "FCLCollisionDetector", "bullet": "BulletCollisionDetector",
             "ode": "OdeCollisionDetector", "dart": "DARTCollisionDetector"}

_COMMON: list[dict[str, Any]] = [
    {"name": "collisionDetector", "kind": "choice", "default": "fcl", "choices": list(DETECTORS),
     "unit": "", "description": "DART's collision detector: fcl (FCL with primitive shapes, DART's "
                                "default), bullet, ode, or dart (DART's own: spheres and boxes)"},
    {"name": "maxContactsPerPair", "kind": "integer", "default": 4, "min": 1, "max": 1000, "unit": "",
     "description": "contact points kept per pair of shapes (CollisionOption.maxNumContactsPerPair)"},
]
_PGS: list[dict[str, Any]] = [
    {"name": "iterations", "kind": "integer", "default": 1000, "min": 1, "max": 1000000, "unit": "",
     "description": "projected Gauss-Seidel sweeps per step at most (PgsBoxedLcpSolverOption.mMaxIteration)"},
]


def parameters(solver: str) -> list[dict[str, Any]]:
    return _COMMON + (_PGS if solver == "pgs" else [])


def default(solver: str, name: str) -> Any:
    return next(p["default"] for p in parameters(solver) if p["name"] == name)


def catalogue() -> dict[str, Any]:
    """engines/dart.json as a document."""
    return {
        "protocol": 1,
        "name": ENGINE,
        "description": f"DART {DART_VERSION} through dartpy (python/pbdval/external/dart/, run as "
                       "python -m pbdval.external.dart; docs/engine-dart.md): skeletons in reduced "
                       "coordinates, semi-implicit Euler, contacts and joint limits as a boxed LCP",
        "command": ["{python}", "-m", "pbdval.external.dart"],
        "serve": {"protocol": 1, "command": ["{python}", "-m", "pbdval.external.dart", "--serve"]},
        "defaultMethod": DEFAULT_METHOD,
        "version": f"dartpy {DART_VERSION}",
        "methods": [{"name": f"{ENGINE}.{s}", "description": text, "parameters": parameters(s)}
                    for s, text in SOLVERS.items()],
        "features": FEATURES,
    }


def catalogue_text() -> str:
    return json.dumps(catalogue(), indent=2, ensure_ascii=False) + "\n"
