"""mujoco-python's feature table (docs/external-engines.md#features): how this engine maps every
scene feature, declared once. catalogue.py puts it into engines/mujoco-python.json, from which
the runner reports a run `unsupported` without starting the engine, and the parity pages
(docs/parity-*.md, the report) are generated. Standard library only.

Entries: {"feature": key or group, "support": native | approximated | unsupported, "text": how
or why, "methods": [...] (optional: only these methods)}; the keys are those of
adapters/features.cpp (`pbdval features --list`).
"""

from __future__ import annotations

from typing import Any

_INTEGRATORS = ("euler", "rk4", "implicit", "implicitfast", "discrete")
_SOLVERS = ("newton", "cg", "pgs")


def _methods(integrators: tuple[str, ...], solvers: tuple[str, ...] = _SOLVERS) -> list[str]:
    return [f"mujoco-python.{i}.{s}" for i in integrators for s in solvers]


_NO_JOINT = "this engine maps ball and hinge joints only"

FEATURES: list[dict[str, Any]] = [
    {"feature": "shape.none", "support": "native", "text": "no geom"},
    {"feature": "shape.sphere", "support": "native", "text": "sphere"},
    {"feature": "shape.box", "support": "native", "text": "box, half extents"},
    {"feature": "shape.cylinder", "support": "native", "text": "cylinder, turned: MuJoCo's axis is z"},
    {"feature": "shape.torus", "support": "unsupported",
     "text": "MuJoCo has no torus, and a mesh collides as its convex hull, which fills the hole"},
    {"feature": "shape.sdf.mesh", "support": "approximated",
     "text": "the mesh as a MuJoCo mesh, which collides as its convex hull"},
    {"feature": "shape.sdf.fileOnly", "support": "unsupported", "text": "MuJoCo needs the geometry mesh"},
    {"feature": "shape.sdf.precomputedFile", "support": "approximated", "text": "not used: the mesh is collided"},
    {"feature": "shape.hollowSphere", "support": "unsupported", "text": "a convex hull is solid"},
    {"feature": "shape.hollowBox", "support": "unsupported", "text": "a convex hull is solid"},
    {"feature": "shape.invertSDF", "support": "unsupported", "text": "MuJoCo has no inside-out shapes"},
    {"feature": "joint", "support": "unsupported", "text": _NO_JOINT},
    {"feature": "joint.ball", "support": "native", "text": "ball joint in the child body"},
    {"feature": "joint.hinge", "support": "native", "text": "hinge joint in the child body"},
    {"feature": "joint.rigidBodyParticleBall", "support": "unsupported",
     "text": "no joints between rigid bodies and flex vertices"},
    {"feature": "joint.closingLoop", "support": "unsupported",
     "text": "closes a kinematic loop (equality constraints are not implemented in this engine)"},
    {"feature": "body.initialVelocityOfJointedBody", "support": "unsupported",
     "text": "an initial velocity of a body jointed to a moving body is not set (reduced coordinates)"},
    {"feature": "contact.rigidPairs", "support": "native",
     "text": "explicit <pair>s with the pair's friction and a direct solref whose Kelvin-Voigt rebound is "
             "the pair's restitution"},
    {"feature": "contact.nonSeparableMaterials", "support": "native", "text": "every pair is explicit"},
    {"feature": "particle.initialVelocity", "support": "native", "text": "the flex vertices' slide joints' qvel"},
    {"feature": "cloth.method.none", "support": "native", "text": "a flex without elasticity"},
    {"feature": "cloth.method.xpbdDistance", "support": "approximated",
     "text": "a St. Venant-Kirchhoff membrane with the spring network's small-strain stiffness averaged "
             "over directions (the network's anisotropy is lost)"},
    {"feature": "cloth.method", "support": "unsupported",
     "text": "a fraction per iteration of the PBD solver, not a stiffness MuJoCo's flexes can take"},
    {"feature": "cloth.bending.none", "support": "native", "text": "no bending"},
    {"feature": "cloth.bending.isometricXpbd", "support": "approximated",
     "text": "quadratic shell bending matched to the quartic XPBD isometric energy at one curvature "
             "(clothBendingCurvature)"},
    {"feature": "cloth.bending", "support": "unsupported",
     "text": "a fraction per iteration of the PBD solver, not a stiffness MuJoCo's flexes can take"},
    {"feature": "solid.method.none", "support": "native", "text": "a flex without elasticity"},
    {"feature": "solid.method.femXpbd", "support": "native",
     "text": "flex elasticity young = E, poisson = ν: St. Venant-Kirchhoff on linear tets, the method's energy"},
    {"feature": "solid.method", "support": "unsupported",
     "text": "a fraction per iteration of the PBD solver, not a stiffness MuJoCo's flexes can take"},
    {"feature": "solid.femPoissonOutOfRange", "support": "native", "text": "MuJoCo's poisson in [0, 0.5)"},
    {"feature": "cloth", "support": "unsupported", "methods": _methods(("implicit", "implicitfast")),
     "text": "MuJoCo 4 refuses flex elasticity under implicit and implicitfast (use discrete, euler or rk4)"},
    {"feature": "solid", "support": "unsupported", "methods": _methods(("implicit", "implicitfast")),
     "text": "MuJoCo 4 refuses flex elasticity under implicit and implicitfast (use discrete, euler or rk4)"},
    {"feature": "cloth", "support": "unsupported", "methods": _methods(("discrete",), ("pgs",)),
     "text": "MuJoCo's discrete integrator needs the Newton or CG solver for flex elasticity"},
    {"feature": "solid", "support": "unsupported", "methods": _methods(("discrete",), ("pgs",)),
     "text": "MuJoCo's discrete integrator needs the Newton or CG solver for flex elasticity"},
    {"feature": "rod", "support": "unsupported", "text": "MuJoCo's flexes have no rod model"},
    {"feature": "fluid", "support": "unsupported", "text": "MuJoCo's flexes have no fluid model"},
]
