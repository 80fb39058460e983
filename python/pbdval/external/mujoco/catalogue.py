"""mujoco-python's catalogue entry, declared once: its methods are the product integrator x
solver with one parameter list (the discrete integrator's `iterations` differ), and
engines/mujoco-python.json is generated from here:

    .venv/bin/python -m pbdval.external.mujoco --catalogue > engines/mujoco-python.json

(tests/python/test_engines.py checks that the shipped file is current). The engine takes its
parameter defaults from here too (`default`). Imports nothing but the standard library, so the
catalogue prints without loading MuJoCo.
"""

from __future__ import annotations

import json
from typing import Any

from pbdval.external.mujoco.features import FEATURES

ENGINE = "mujoco-python"
#: The MuJoCo release the catalogue announces (the test compares it with mujoco.__version__).
MUJOCO_VERSION = "4.0.0"
#: integrator name (the method's middle part) → how a method's description names it, in
#: catalogue order
INTEGRATORS = {
    "euler": "semi-implicit Euler",
    "rk4": "4th-order Runge-Kutta",
    "implicit": "implicit in velocity",
    "implicitfast": "implicit in velocity, without the Coriolis derivatives",
    "discrete": "discrete-time (velocity-stepping, implicit in position: flex elasticity stable at any step)",
}
#: solver name (the method's last part) → its description, in catalogue order
SOLVERS = {"newton": "Newton", "cg": "conjugate gradient", "pgs": "projected Gauss-Seidel"}
DEFAULT_METHOD = f"{ENGINE}.euler.newton"
#: What a method's description adds for a combination with a restriction.
RESTRICTIONS = {("discrete", "pgs"): " (not with particles: flex elasticity needs Newton or CG)"}

_PARAMETERS: list[dict[str, Any]] = [
    {"name": "iterations", "kind": "integer", "default": 100, "min": 1, "max": 100000, "unit": "",
     "description": "maximum constraint solver iterations per step"},
    {"name": "tolerance", "kind": "real", "default": 1e-08, "min": 0.0, "max": 1.0, "unit": "",
     "description": "constraint solver tolerance"},
    {"name": "cone", "kind": "choice", "default": "elliptic", "choices": ["elliptic", "pyramidal"],
     "unit": "", "description": "friction cone: elliptic (isotropic) or pyramidal"},
    {"name": "contactTimeconstSteps", "kind": "real", "default": 4.0, "min": 2.0, "max": 1000.0,
     "unit": "steps",
     "description": "contact time constant tau as a multiple of the step h (MuJoCo raises anything below 2h)"},
    {"name": "equalityTimeconstSteps", "kind": "real", "default": 2.0, "min": 2.0, "max": 1000.0,
     "unit": "steps",
     "description": "time constant of equality constraints (loop-closing joints, distance joints) as a "
                    "multiple of h, the built-in engine's equalityTimeconst"},
    {"name": "equalityDampratio", "kind": "real", "default": 1.0, "min": 1e-06, "max": 1000000.0,
     "unit": "", "description": "damping ratio of equality constraints (solref[1])"},
    {"name": "servoTimeconstSteps", "kind": "real", "default": 4.0, "min": 2.0, "max": 1000.0,
     "unit": "steps",
     "description": "time constant of the motor servos as a multiple of h, the built-in engine's "
                    "servoTimeconst"},
    {"name": "substeps", "kind": "integer", "default": 0, "min": 0, "max": 10000, "unit": "",
     "description": "internal steps per scene step; 0: automatic, 1 without particles or under the "
                    "discrete integrator, else the fewest with h_internal * omega_max <= 1 for the "
                    "stiffest elastic mode of the particles (flex elasticity is explicit in euler and rk4)"},
    {"name": "clothBendingCurvature", "kind": "real", "default": 2.0, "min": 0.0, "max": 1000.0,
     "unit": "1/m",
     "description": "curvature at which MuJoCo's quadratic shell bending is matched to the quartic "
                    "XPBD isometric bending (clothBendingMethod 3): both store the same energy on "
                    "the cloth bent into a cylinder of this curvature; 2/m folds a 0.125 m grid by "
                    "about 0.25 rad per edge; 0: no bending"},
]
#: integrator → what its parameter list changes: `discrete` also spends `iterations` on its
#: iterative solve of M + h^2 K, which 100 leaves under-converged on a tet bar.
_OVERRIDES: dict[str, dict[str, dict[str, Any]]] = {
    "discrete": {"iterations": {
        "default": 1000,
        "description": "maximum constraint solver iterations per step, and of the discrete "
                       "integrator's iterative solve of M + h^2 K (100 leaves the tet bar's under-converged)"}},
}


def parameters(integrator: str) -> list[dict[str, Any]]:
    """The parameter list of every method with this integrator."""
    overrides = _OVERRIDES.get(integrator, {})
    return [{**p, **overrides.get(p["name"], {})} for p in _PARAMETERS]


def default(integrator: str, name: str) -> Any:
    """The default of parameter `name` under `integrator`."""
    return next(p["default"] for p in parameters(integrator) if p["name"] == name)


def catalogue() -> dict[str, Any]:
    """engines/mujoco-python.json as a document."""
    methods = [{"name": f"{ENGINE}.{integrator}.{solver}",
                "description": f"MuJoCo {integrator_text} integrator, {solver_text} constraint solver"
                               + RESTRICTIONS.get((integrator, solver), ""),
                "parameters": parameters(integrator)}
               for integrator, integrator_text in INTEGRATORS.items()
               for solver, solver_text in SOLVERS.items()]
    return {
        "protocol": 1,
        "name": ENGINE,
        "description": f"MuJoCo {MUJOCO_VERSION} through its Python package, the built-in engine's MJCF "
                       "compiled by MuJoCo 4 (python/pbdval/external/mujoco/, run as python -m pbdval.external.mujoco; "
                       "particles as flexes, python/pbdval/external/mujoco/flexes.py; "
                       "docs/external-engines.md#mujoco-python). Not the built-in 'mujoco' engine "
                       "(MuJoCo 2.2.2, C++).",
        "command": ["{python}", "-m", "pbdval.external.mujoco"],
        # Every run builds its own MjModel and MjData; one child may serve RUNS_PER_CHILD of them.
        "serve": {"protocol": 1, "command": ["{python}", "-m", "pbdval.external.mujoco", "--serve"],
                  "runsPerChild": RUNS_PER_CHILD},
        "defaultMethod": DEFAULT_METHOD,
        "version": f"mujoco {MUJOCO_VERSION}",
        "methods": methods,
        "features": FEATURES,
    }


#: The most runs one served child makes in turn (docs/external-engines.md#persistent-engines):
#: the fork's copy-on-write faults are paid once per child, and whatever a run leaks is bounded.
RUNS_PER_CHILD = 50


def catalogue_text() -> str:
    """The catalogue file's text, as shipped (two-space indentation, a final newline)."""
    return json.dumps(catalogue(), indent=2, ensure_ascii=False) + "\n"
