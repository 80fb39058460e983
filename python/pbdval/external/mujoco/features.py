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
    # The rigid part is the built-in engine's own model (its MJCF, compiled by MuJoCo 4): these
    # entries are adapters/mujoco/mujoco_features.cpp's, which tests/python/test_features.py
    # holds them to.
    {"feature": "joint.ball", "support": "native", "text": "ball at the anchor"},
    {"feature": "joint.ballOnLine", "support": "native",
     "text": "slide then ball (or ball then slide when the line's body is the child)"},
    {"feature": "joint.hinge", "support": "native", "text": "hinge"},
    {"feature": "joint.universal", "support": "native",
     "text": "two hinges in one body, axis1 first (fixed in the parent), axis2 second"},
    {"feature": "joint.slider", "support": "native", "text": "slide"},
    {"feature": "joint.rigidBodyParticleBall", "support": "unsupported",
     "text": "no joints between rigid bodies and flex vertices"},
    {"feature": "joint.rigidBodySpring", "support": "approximated",
     "text": "a spatial tendon with stiffness k and springlength L: a force, explicit in the integrators"},
    {"feature": "joint.distance", "support": "approximated",
     "text": "never in the tree: a spatial tendon between the anchors and a soft tendon equality holding "
             "its initial length"},
    {"feature": "joint.damper", "support": "native",
     "text": "slide with joint stiffness k, springref = the initial offset; no damping (as the scene's)"},
    {"feature": "joint.targetAngleMotorHinge", "support": "approximated",
     "text": "hinge + critically damped PD servo (kp = m/τ_s², kv = 2m/τ_s): a ramp lags by 2τ_s·slope, "
             "a static load F leaves F/kp"},
    {"feature": "joint.targetVelocityMotorHinge", "support": "approximated",
     "text": "hinge + velocity servo kv = m/τ_s: a load F leaves a speed error F/kv"},
    {"feature": "joint.targetPositionMotorSlider", "support": "approximated",
     "text": "slide + PD servo, as the angle motor"},
    {"feature": "joint.targetVelocityMotorSlider", "support": "approximated", "text": "slide + velocity servo"},
    {"feature": "joint.stiffRod", "support": "unsupported",
     "text": "stiff-rod joints (CosseratJoints, elastic bending and twisting between rod segments) are not "
             "mapped by the MuJoCo adapter"},
    {"feature": "joint.closingLoop.ballOrHinge", "support": "approximated",
     "text": "soft equality constraints (equalityTimeconstSteps, equalityDampratio): a ball is one connect, "
             "a hinge two connects along the axis"},
    {"feature": "joint.closingLoop.other", "support": "unsupported",
     "text": "MuJoCo has no equality constraint for this joint type (only ball and hinge joints can close "
             "loops)"},
    {"feature": "body.initialVelocityOfJointedBody", "support": "approximated",
     "text": "the scene's velocities projected onto the joints' free motions in the kinetic-energy norm "
             "(reduced coordinates cannot hold a velocity that violates a joint); recorded as a warning"},
    {"feature": "contact.rigidPairs", "support": "native",
     "text": "explicit <pair>s with the pair's friction and a direct solref whose Kelvin-Voigt rebound is "
             "the pair's restitution"},
    {"feature": "contact.nonSeparableMaterials", "support": "native", "text": "every pair is explicit"},
    {"feature": "particle.initialVelocity", "support": "native", "text": "the flex vertices' slide joints' qvel"},
    {"feature": "cloth.method.none", "support": "native", "text": "a flex without elasticity"},
    {"feature": "cloth.method.fem", "support": "approximated",
     "text": "flex elasticity for 2-D elements: young × thickness = cloth_xxStiffness, poisson = "
             "cloth_xyPoissonRatio; exact for an isotropic cloth with G = E/(1+ν), else the shear modulus "
             "ratio is recorded; orthotropic moduli unsupported by name"},
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
