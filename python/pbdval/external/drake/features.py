"""drake's feature table (docs/external-engines.md#features): how this engine maps every scene
feature, declared once. catalogue.py puts it into engines/drake.json, from which the runner
reports a run `unsupported` without starting the engine, and the parity pages are generated.
engine.py refuses a scene from the same declarations (SHAPES, JOINTS). Standard library only.

Entries: {"feature": key or group, "support": native | approximated | unsupported, "text": how
or why, "methods": [...] (optional)}; the keys are those of adapters/features.cpp
(`pbdval features --list`).
"""

from __future__ import annotations

from typing import Any

#: Resolved-scene shape type → the Drake geometry it becomes (every other type is refused).
SHAPES = {"none": "no geometry", "sphere": "Sphere", "box": "Box", "cylinder": "Cylinder"}
#: Resolved-scene joint type → the Drake element it becomes (every other type is refused).
JOINTS = {
    "hinge": "RevoluteJoint",
    "slider": "PrismaticJoint",
    "ball": "BallRpyJoint",
    "universal": "UniversalJoint",
    "damper": "PrismaticJoint + PrismaticSpring",
    "rigid_body_spring": "LinearSpringDamper",
}
#: Joint types that are force elements, not edges of the kinematic tree.
FORCE_ELEMENT_JOINTS = ("rigid_body_spring",)

_MOTOR = ("Drake drives joints through actuators and a controller system (or SAP's PD gains, "
          "discrete only); the seed's set-point motors are not mapped")
_PBD_FRACTION = "a fraction per iteration of the PBD solver; Drake's MultibodyPlant has rigid bodies only here"

FEATURES: list[dict[str, Any]] = [
    {"feature": "shape.none", "support": "native", "text": "a body without geometry"},
    {"feature": "shape.sphere", "support": "native", "text": "Sphere"},
    {"feature": "shape.box", "support": "native", "text": "Box (full extents)"},
    {"feature": "shape.cylinder", "support": "native", "text": "Cylinder, turned: Drake's axis is z"},
    {"feature": "shape.torus", "support": "unsupported",
     "text": "Drake has no torus, and point contact collides a mesh as its convex hull, which fills the hole"},
    {"feature": "shape.sdf", "support": "unsupported",
     "text": "Drake's point contact collides a mesh as its convex hull (Convex); exact only for a convex "
             "mesh, which the engine does not establish, so meshes are not used"},
    {"feature": "shape.hollowSphere", "support": "unsupported", "text": "Drake's shapes are solid"},
    {"feature": "shape.hollowBox", "support": "unsupported", "text": "Drake's shapes are solid"},
    {"feature": "shape.invertSDF", "support": "unsupported", "text": "Drake has no inside-out shapes"},
    {"feature": "joint.hinge", "support": "native", "text": "RevoluteJoint about the hinge axis"},
    {"feature": "joint.slider", "support": "native", "text": "PrismaticJoint along the slider axis"},
    {"feature": "joint.ball", "support": "native",
     "text": "BallRpyJoint at the anchor, roll axis horizontal across the arm: regular for any swing in the "
             "arm's vertical plane; its coordinates are singular at pitch ±π/2 (a swing of π/2 out of that plane)"},
    {"feature": "joint.universal", "support": "native",
     "text": "UniversalJoint: the parent's axis as its first (x), the child's as its second (y)"},
    {"feature": "joint.damper", "support": "native",
     "text": "PrismaticJoint with a PrismaticSpring of stiffness k at the initial offset; no damping (as the scene's)"},
    {"feature": "joint.rigidBodySpring", "support": "native",
     "text": "LinearSpringDamper between the anchors, free length L, stiffness k, no damping"},
    {"feature": "joint.ballOnLine", "support": "unsupported",
     "text": "Drake has no point-on-line joint (a prismatic and a ball joint through a massless body are not mapped)"},
    {"feature": "joint.distance", "support": "unsupported",
     "text": "Drake's distance constraint exists only under SAP and is compliant; not mapped"},
    {"feature": "joint.rigidBodyParticleBall", "support": "unsupported", "text": "no particles in this engine"},
    {"feature": "joint.targetAngleMotorHinge", "support": "unsupported", "text": _MOTOR},
    {"feature": "joint.targetVelocityMotorHinge", "support": "unsupported", "text": _MOTOR},
    {"feature": "joint.targetPositionMotorSlider", "support": "unsupported", "text": _MOTOR},
    {"feature": "joint.targetVelocityMotorSlider", "support": "unsupported", "text": _MOTOR},
    {"feature": "joint.stiffRod", "support": "unsupported",
     "text": "stiff-rod joints (CosseratJoints) are elastic rod segments; not mapped"},
    {"feature": "joint.closingLoop", "support": "unsupported",
     "text": "MultibodyPlant is a tree: a joint that closes a loop would need a SAP constraint, not mapped"},
    {"feature": "body.initialVelocityOfJointedBody", "support": "approximated",
     "text": "the scene's velocities projected onto the joints' free motions in the kinetic-energy norm "
             "(reduced coordinates cannot hold a velocity that violates a joint); recorded in the settings"},
    {"feature": "contact.rigidPairs", "support": "approximated",
     "text": "compliant point contact, one point per pair (the deepest: a box on a face rocks on a corner), "
             "with the pair's friction (per-geometry values whose harmonic combination is the pair's); "
             "stiffness and dissipation from Drake's penetration allowance (parameter penetrationAllowance), "
             "so the pair's restitution is not used; regularised friction below stictionTolerance in the "
             "continuous methods and TAMSI"},
    {"feature": "contact.nonSeparableMaterials", "support": "unsupported",
     "text": "the pairs' friction is not the harmonic combination 2ab/(a+b) of per-geometry values "
             "(Drake combines the geometries' friction so)"},
    {"feature": "particle", "support": "unsupported", "text": "no particles in this engine"},
    {"feature": "cloth", "support": "unsupported", "text": _PBD_FRACTION},
    {"feature": "solid", "support": "unsupported", "text": _PBD_FRACTION},
    {"feature": "rod", "support": "unsupported", "text": "no rods in this engine"},
    {"feature": "fluid", "support": "unsupported", "text": "no fluids in this engine"},
]
