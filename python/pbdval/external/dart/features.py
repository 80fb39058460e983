"""dart's feature table (docs/engines.md#features), declared once: catalogue.py puts it into
engines/dart.json, from which the runner reports a run `unsupported` without starting the engine
and the parity pages are generated; engine.py's own check (unsupported_features) refuses the same
runs. Standard library only.
"""

from __future__ import annotations

from typing import Any

#: Seed joint type → the DART joint of a tree joint (engine.py builds them; joint_trees.py plans).
TREE_JOINTS = {"hinge": "RevoluteJoint", "slider": "PrismaticJoint", "ball": "BallJoint",
               "universal": "UniversalJoint", "damper": "PrismaticJoint"}
#: Shapes dart builds (the others are refused).
SHAPES = ("none", "sphere", "box", "cylinder")

FEATURES: list[dict[str, Any]] = [
    {"feature": "shape.none", "support": "native", "text": "a BodyNode without a ShapeNode"},
    {"feature": "shape.sphere", "support": "native", "text": "SphereShape"},
    {"feature": "shape.box", "support": "native", "text": "BoxShape (full side lengths)"},
    {"feature": "shape.cylinder", "support": "native", "text": "CylinderShape, turned: DART's axis is z"},
    {"feature": "shape.torus", "support": "unsupported",
     "text": "DART has no torus shape; the body's mesh (a MeshShape) is not mapped"},
    {"feature": "shape.sdf", "support": "unsupported",
     "text": "meshes are not mapped by the dart engine (DART's MeshShape could carry them; not done)"},
    {"feature": "shape.hollowSphere", "support": "unsupported", "text": "DART has no hollow shapes"},
    {"feature": "shape.hollowBox", "support": "unsupported", "text": "DART has no hollow shapes"},
    {"feature": "shape.invertSDF", "support": "unsupported", "text": "DART has no inside-out shapes"},
    {"feature": "joint.hinge", "support": "native", "text": "RevoluteJoint in the skeleton's tree"},
    {"feature": "joint.slider", "support": "native", "text": "PrismaticJoint in the skeleton's tree"},
    {"feature": "joint.ball", "support": "native", "text": "BallJoint in the skeleton's tree"},
    {"feature": "joint.universal", "support": "native",
     "text": "UniversalJoint, axis1 in the parent, axis2 in the child"},
    {"feature": "joint.damper", "support": "native",
     "text": "PrismaticJoint with DART's joint spring (stiffness k, rest position the initial offset)"},
    {"feature": "joint.ballOnLine", "support": "unsupported",
     "text": "DART has no ball-on-line joint (a PrismaticJoint then a BallJoint through an extra link "
             "could carry it; not done)"},
    {"feature": "joint.rigidBodyParticleBall", "support": "unsupported",
     "text": "the dart engine maps no particles"},
    {"feature": "joint.rigidBodySpring", "support": "unsupported",
     "text": "not mapped (a force between the two points applied every step could carry it; not done)"},
    {"feature": "joint.distance", "support": "unsupported",
     "text": "not mapped: dartpy's joint constraints (ball, cylindrical, revolute, weld) include no "
             "distance constraint"},
    {"feature": "joint.targetAngleMotorHinge", "support": "unsupported",
     "text": "not mapped: DART's SERVO actuator sets a velocity, not a position"},
    {"feature": "joint.targetVelocityMotorHinge", "support": "unsupported",
     "text": "not mapped (DART's SERVO actuator could drive it; not done)"},
    {"feature": "joint.targetPositionMotorSlider", "support": "unsupported",
     "text": "not mapped: DART's SERVO actuator sets a velocity, not a position"},
    {"feature": "joint.targetVelocityMotorSlider", "support": "unsupported",
     "text": "not mapped (DART's SERVO actuator could drive it; not done)"},
    {"feature": "joint.stiffRod", "support": "unsupported", "text": "the dart engine maps no rods"},
    {"feature": "joint.closingLoop", "support": "unsupported",
     "text": "DART's skeletons are trees; a loop-closing constraint is not mapped"},
    {"feature": "body.initialVelocityOfJointedBody", "support": "approximated",
     "text": "the scene's velocities projected onto the joints' free motions in the kinetic-energy "
             "norm (reduced coordinates cannot hold a velocity that violates a joint)"},
    {"feature": "contact.rigidPairs", "support": "approximated",
     "text": "FCL collision (primitive shapes), DART's boxed LCP with its contact error reduction; "
             "friction per body, combined by DART as the minimum, restitution as the product: "
             "the per-body values are chosen to give every pair's"},
    {"feature": "contact.nonSeparableMaterials", "support": "unsupported",
     "text": "DART combines per-body friction by the minimum and restitution by the product: pair "
             "values not of that form cannot be given"},
    {"feature": "particle", "support": "unsupported", "text": "the dart engine maps no particles"},
    {"feature": "cloth", "support": "unsupported",
     "text": "not mapped: DART's soft bodies (SoftBodyNode) are volumetric point masses on a rigid "
             "body, not a cloth model"},
    {"feature": "solid", "support": "unsupported",
     "text": "not mapped: DART's SoftBodyNode is a skin of point masses on a rigid body, not an "
             "elastic tet model"},
    {"feature": "rod", "support": "unsupported", "text": "DART has no rod model"},
    {"feature": "fluid", "support": "unsupported", "text": "DART has no fluid model"},
]
