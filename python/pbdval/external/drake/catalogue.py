"""drake's catalogue entry, declared once (methods, their parameters, the feature table);
engines/drake.json is generated from here:

    .venv/bin/python -m pbdval.external.drake --catalogue > engines/drake.json

(tests/python/test_drake_engine.py checks that the shipped file is current). The engine takes its
parameter defaults from here too (`default`). Imports nothing but the standard library, so the
catalogue prints without loading Drake.
"""

from __future__ import annotations

import json
from typing import Any

from pbdval.external.drake.features import FEATURES

ENGINE = "drake"
#: The Drake release the catalogue announces (the test compares it with the installed one).
DRAKE_VERSION = "1.51.1"
#: Discrete methods: the plant's contact approximation, time step = the scene's step.
DISCRETE = {
    "sap": ("kSap", "SAP (Castro et al. 2022, the semi-analytic primal solver: convex, unconditionally stable)"),
    "tamsi": ("kTamsi", "TAMSI (Castro et al. 2019, transition-aware modified semi-implicit)"),
}
#: Continuous methods: the integrator's name for pydrake.systems.analysis.ResetIntegratorFromFlags.
CONTINUOUS = {
    "rk3": ("runge_kutta3", "3rd-order Runge-Kutta with an embedded 2nd-order error estimate"),
    "radau": ("radau3", "3rd-order two-stage Radau IIA (implicit, L-stable)"),
    "implicit_euler": ("implicit_euler", "implicit Euler with step doubling for its error estimate"),
}
DEFAULT_METHOD = f"{ENGINE}.sap"

_CONTACT_PARAMETERS: list[dict[str, Any]] = [
    {"name": "penetrationAllowance", "kind": "real", "default": 0.001, "min": 1e-09, "max": 1.0, "unit": "m",
     "description": "MultibodyPlant::set_penetration_allowance: the point contact's stiffness and "
                    "dissipation are estimated so that the bodies rest this deep in each other "
                    "(Drake's default 1 mm)"},
]
_CONTINUOUS_PARAMETERS: list[dict[str, Any]] = [
    {"name": "targetAccuracy", "kind": "real", "default": 1e-06, "min": 1e-14, "max": 1.0, "unit": "",
     "description": "the integrator's target accuracy (IntegratorBase::set_target_accuracy): the "
                    "relative local error its step-size control aims at; the step never exceeds "
                    "the scene's step"},
    {"name": "stepControl", "kind": "choice", "default": "error", "choices": ["error", "fixed"], "unit": "",
     "description": "error: the integrator chooses its steps from its error estimate, at most the "
                    "scene's step (sweep targetAccuracy); fixed: it takes the scene's step, no error "
                    "control (IntegratorBase::set_fixed_step_mode; sweep timeStepSize for the "
                    "scheme's order; an implicit scheme still stops its Newton iteration at a "
                    "tolerance from targetAccuracy)"},
]
_FRICTION_PARAMETERS: list[dict[str, Any]] = [
    {"name": "stictionTolerance", "kind": "real", "default": 0.0001, "min": 1e-09, "max": 1.0,
     "unit": "m/s",
     "description": "MultibodyPlant::set_stiction_tolerance: below this slip speed friction is "
                    "regularised (continuous plant and TAMSI; Drake's default 1e-4 m/s)"},
]


def parameters(method: str) -> list[dict[str, Any]]:
    """The parameter list of a method (its last name part)."""
    if method in CONTINUOUS:
        return _CONTINUOUS_PARAMETERS + _FRICTION_PARAMETERS + _CONTACT_PARAMETERS
    if method == "tamsi":
        return _FRICTION_PARAMETERS + _CONTACT_PARAMETERS
    return list(_CONTACT_PARAMETERS)


def default(method: str, name: str) -> Any:
    """The default of parameter `name` of `method` (its last name part)."""
    return next(p["default"] for p in parameters(method) if p["name"] == name)


def catalogue() -> dict[str, Any]:
    """engines/drake.json as a document."""
    methods = [{"name": f"{ENGINE}.{name}",
                "description": f"discrete MultibodyPlant (time step = the scene's step), {text} contact solver",
                "parameters": parameters(name)} for name, (_, text) in DISCRETE.items()]
    methods += [{"name": f"{ENGINE}.{name}",
                 "description": f"continuous MultibodyPlant, error-controlled {text} integrator "
                                "(at targetAccuracy 1e-10: the converged reference)",
                 "parameters": parameters(name)} for name, (_, text) in CONTINUOUS.items()]
    return {
        "protocol": 1,
        "name": ENGINE,
        "description": f"Drake {DRAKE_VERSION}'s MultibodyPlant through pydrake (python/pbdval/external/drake/, "
                       "run as python -m pbdval.external.drake; docs/engine-drake.md): rigid bodies in "
                       "reduced coordinates, compliant point contact, discrete (SAP, TAMSI) or "
                       "error-controlled continuous integration",
        "command": ["{python}", "-m", "pbdval.external.drake"],
        "serve": {"protocol": 1, "command": ["{python}", "-m", "pbdval.external.drake", "--serve"]},
        "defaultMethod": DEFAULT_METHOD,
        "version": f"drake {DRAKE_VERSION}",
        "methods": methods,
        "features": FEATURES,
    }


def catalogue_text() -> str:
    """The catalogue file's text, as shipped (two-space indentation, a final newline)."""
    return json.dumps(catalogue(), indent=2, ensure_ascii=False) + "\n"
