"""newton's feature table (docs/engines.md#features), declared once: catalogue.py puts it into
engines/newton.json; engine.py's own check refuses the same runs. Standard library only."""

from __future__ import annotations

from typing import Any

#: Seed joint type → Newton's joint (engine.py builds them; joint_trees.py plans the forest).
TREE_JOINTS = {"hinge": "revolute", "slider": "prismatic", "ball": "ball", "universal": "d6 (two angular axes)"}
SHAPES = ("none", "sphere", "box", "cylinder")
#: Newton 1.8.0's fourth solver, which this machine cannot run: not in the catalogue (a method no
#: scene can run); the engine answers a run that names it `unsupported` with this reason
#: (docs/engine-newton.md#methods).
MUJOCO_WARP = "newton.mujoco"
MUJOCO_WARP_REASON = ("SolverMuJoCo needs mujoco-warp~=3.17.0 and mujoco~=3.17.0 (newton 1.8.0's "
                      "`sim` extra), whose `mujoco` module conflicts with the pinned mujoco-core 4.0.0")
_PENALTY = ["newton.featherstone", "newton.semiImplicit"]

_TABLE: list[dict[str, Any]] = [
    {"feature": "shape.none", "support": "native", "text": "a body without a shape"},
    {"feature": "shape.sphere", "support": "native", "text": "add_shape_sphere"},
    {"feature": "shape.box", "support": "native", "text": "add_shape_box, half extents"},
    {"feature": "shape.cylinder", "support": "native", "text": "add_shape_cylinder, turned: Newton's axis is z"},
    {"feature": "shape.torus", "support": "unsupported", "text": "Newton has no torus; meshes are not mapped"},
    {"feature": "shape.sdf", "support": "unsupported", "text": "meshes are not mapped by the newton engine"},
    {"feature": "shape.hollowSphere", "support": "unsupported", "text": "Newton has no hollow shapes"},
    {"feature": "shape.hollowBox", "support": "unsupported", "text": "Newton has no hollow shapes"},
    {"feature": "shape.invertSDF", "support": "unsupported", "text": "Newton has no inside-out shapes"},
    {"feature": "joint.hinge", "support": "native", "text": "add_joint_revolute"},
    {"feature": "joint.slider", "support": "native", "text": "add_joint_prismatic"},
    {"feature": "joint.ball", "support": "native", "text": "add_joint_ball"},
    {"feature": "joint.universal", "support": "native",
     "text": "add_joint_d6 with two angular axes, axis1 first (fixed in the parent)"},
    {"feature": "joint.ballOnLine", "support": "unsupported",
     "text": "not mapped (a d6 joint could carry it; not done)"},
    {"feature": "joint.rigidBodyParticleBall", "support": "unsupported",
     "text": "not mapped (Newton has no joint between a body and a particle)"},
    {"feature": "joint.rigidBodySpring", "support": "unsupported", "text": "not mapped"},
    {"feature": "joint.distance", "support": "unsupported",
     "text": "not mapped (Newton has add_joint_distance; not done)"},
    {"feature": "joint.damper", "support": "unsupported",
     "text": "not mapped (a prismatic joint's stiffness; not done)"},
    {"feature": "joint.targetAngleMotorHinge", "support": "unsupported",
     "text": "not mapped (Newton's joint targets; not done)"},
    {"feature": "joint.targetVelocityMotorHinge", "support": "unsupported",
     "text": "not mapped (Newton's joint targets; not done)"},
    {"feature": "joint.targetPositionMotorSlider", "support": "unsupported",
     "text": "not mapped (Newton's joint targets; not done)"},
    {"feature": "joint.targetVelocityMotorSlider", "support": "unsupported",
     "text": "not mapped (Newton's joint targets; not done)"},
    {"feature": "joint.stiffRod", "support": "unsupported", "text": "the newton engine maps no rods"},
    {"feature": "joint.closingLoop", "support": "unsupported",
     "text": "Newton's articulations are trees; a loop-closing joint is not mapped"},
    {"feature": "body.initialVelocityOfJointedBody", "support": "approximated",
     "text": "XPBD and semi-implicit: the bodies' velocities as given; Featherstone: projected onto the "
             "joints by Newton's eval_ik"},
    {"feature": "contact.rigidPairs", "support": "approximated",
     "text": "Newton's collision pipeline (GJK/MPR); friction and restitution per shape, Newton averages "
             "the two shapes' values: the per-body values are solved to give every pair's; float32 state"},
    {"feature": "contact.rigidPairs", "support": "approximated", "methods": _PENALTY,
     "text": "penalty contacts (ke, kd per shape, contactStiffness/contactDamping): the bodies sink by "
             "m g / ke and restitution is the damper's, not the pair's"},
    {"feature": "contact.nonSeparableMaterials", "support": "unsupported",
     "text": "Newton averages the two shapes' friction and restitution: pair values that are not averages "
             "of per-body values cannot be given"},
    {"feature": "particle.initialVelocity", "support": "native", "text": "add_particle's velocity"},
    {"feature": "cloth.method.none", "support": "native", "text": "free Newton particles (add_particle)"},
    {"feature": "cloth.method.xpbdDistance", "support": "native",
     "text": "a spring per distinct edge, add_spring(ke = k, kd = 0): SolverXPBD's distance constraint "
             "with compliance 1/k, the explicit solvers' force k (l - L): the potential ½ k C² of the method"},
    {"feature": "cloth.method.fem", "support": "unsupported",
     "text": "SolverXPBD solves no triangles, and the explicit solvers' triangles are a stable neo-Hookean "
             "membrane, where the seed's FEM triangles are an orthotropic St. Venant-Kirchhoff projection whose "
             "stiffness comes from its iterations: not mapped"},
    {"feature": "cloth.method.other", "support": "unsupported", "text": "no such cloth method"},
    {"feature": "cloth.method", "support": "unsupported",
     "text": "a fraction per iteration of the PBD solver, not a stiffness Newton's springs or triangles can take"},
    {"feature": "cloth.bending.none", "support": "native", "text": "no bending edges"},
    {"feature": "cloth.bending.isometricXpbd", "support": "approximated",
     "text": "Newton's dihedral edge bending (add_edge), quadratic in the angle, matched to the quartic XPBD "
             "isometric energy at one curvature (clothBendingCurvature)"},
    {"feature": "cloth.bending.other", "support": "unsupported", "text": "no such bending method"},
    {"feature": "cloth.bending", "support": "unsupported",
     "text": "a fraction per iteration of the PBD solver, not a stiffness Newton's edges can take"},
    {"feature": "solid.method.none", "support": "native", "text": "free Newton particles (add_particle)"},
    {"feature": "solid.method.femXpbd", "support": "unsupported",
     "text": "SolverXPBD's tets (solve_tetrahedra: tr(FᵀF) − 3 and det F − 1 as XPBD constraints) have no "
             "small-strain shear stiffness, so no E, ν matches the seed's St. Venant-Kirchhoff tets"},
    {"feature": "solid.method.femXpbd", "support": "approximated", "methods": _PENALTY,
     "text": "Newton's stable neo-Hookean tets (add_tetrahedron) with the seed's small-strain Lamé parameters: "
             "k_mu = 4/3 μ, k_lambda = λ + 5/6 μ; the seed's St. Venant-Kirchhoff tets differ at large strain"},
    {"feature": "solid.method.distanceVolumeXpbd", "support": "unsupported",
     "text": "Newton has springs for the edges (k N/m) but no tet-volume constraint (its tets are the FEM "
             "above): not mapped"},
    {"feature": "solid.method.other", "support": "unsupported", "text": "no such solid method"},
    {"feature": "solid.method", "support": "unsupported",
     "text": "a fraction per iteration of the PBD solver, not a stiffness Newton's tets can take"},
    {"feature": "solid.femPoissonOutOfRange", "support": "unsupported",
     "text": "the seed's range [0, 0.49] is the one mapped (and SolverXPBD maps no FEM solid)"},
    {"feature": "rod", "support": "unsupported", "text": "not mapped by the newton engine"},
    {"feature": "fluid", "support": "unsupported", "text": "Newton has no position-based fluid"},

]
FEATURES: list[dict[str, Any]] = _TABLE
