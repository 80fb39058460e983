// How the Bullet adapter maps every scene feature (adapters/features.h): the one declaration
// that BulletEngine::unsupported and docs/parity-bullet.md are made from.
#include "adapters/bullet/bullet_engine.h"

namespace pbdval {

FeatureTable bulletFeatures() {
  const Support N = Support::Native, A = Support::Approximated, U = Support::Unsupported;
  const char* rigidOnly =
      "the Bullet adapter maps rigid bodies only (btSoftBody is not mapped; Bullet's deformables "
      "run through pybullet)";
  const char* noMesh = "built from the body's mesh in Bullet, and the body has no geometryFile";
  return {{
      {"shape.none", N, "btEmptyShape, broad-phase group and mask 0: no collision"},
      {"shape.sphere", N, "btSphereShape(r) (its margin is its radius: exact)"},
      {"shape.box", N,
       "btBoxShape(extents/2), margin 1 mm kept inside: faces exact, edges rounded with r = 1 mm"},
      {"shape.cylinder", N,
       "btCylinderShape(r, h/2, r), axis y as the scene's; margin inside as the box"},
      {"shape.torus.mesh", A,
       "the body's mesh as a triangle mesh (btGImpactMeshShape if dynamic, btBvhTriangleMeshShape "
       "if static): faceted, surfaces thickened by the margin; the analytic (R, r) is not used"},
      {"shape.torus.analytic", U, noMesh},
      {"shape.sdf.mesh", A,
       "the body's mesh: btConvexHullShape when convex (hull shrunk by the margin), else a "
       "triangle mesh as for the torus; the SDF grid is not used"},
      {"shape.sdf.fileOnly", U, noMesh},
      {"shape.sdf.precomputedFile", A, "not used: Bullet collides the body's mesh"},
      {"shape.hollowSphere", U, "Bullet has no hollow-sphere shape"},
      {"shape.hollowBox", A,
       "btCompoundShape of six wall boxes 2 × thicknessSDF thick, centred on the faces (outer "
       "edges square instead of rounded)"},
      {"shape.invertSDF", U, "Bullet shapes collide on their outside only"},
      {"joint.ball", N, "btPoint2PointConstraint"},
      {"joint.ballOnLine", N,
       "btGeneric6DofSpring2Constraint at position, x = axis: linear x free, y, z locked"},
      {"joint.hinge", N, "btHingeConstraint, frame z = axis"},
      {"joint.universal", N,
       "btGeneric6DofSpring2Constraint, Euler order XYZ, z = axis1 (in A), x = axis2 (in B): the "
       "middle angle locked at 0, both outer angles free"},
      {"joint.slider", N,
       "btGeneric6DofSpring2Constraint at B's centre of mass, x = axis: linear x free"},
      {"joint.rigidBodyParticleBall", U, "Bullet rigid bodies have no particles"},
      {"joint.rigidBodySpring", A,
       "a force F = −k (‖c_B − c_A‖ − L) n at both connectors before each step, integrated "
       "explicitly (the seed's spring is implicit XPBD)"},
      {"joint.distance", U,
       "Bullet has no distance constraint between two rigid bodies (its constraints join points or "
       "act along body-fixed axes; a rod would need a massless body)"},
      {"joint.damper", N,
       "the slider with a linear-x spring of stiffness k, damping 0 (explicit; the seed's is "
       "implicit XPBD)"},
      {"joint.targetAngleMotorHinge", N,
       "btHingeConstraint motor, setMotorTarget(θ*(t+h), h) every step"},
      {"joint.targetVelocityMotorHinge", N,
       "btHingeConstraint angular motor at ω*(t+h), unlimited impulse"},
      {"joint.targetPositionMotorSlider", N,
       "the slider with linear x locked at s*(t+h), stop ERP 1"},
      {"joint.targetVelocityMotorSlider", N,
       "the slider with a linear-x motor at v*(t+h), unlimited force"},
      {"joint.stiffRod", U,
       "stiff-rod joints (CosseratJoints, elastic bending and twisting between rod segments) are "
       "not mapped by the Bullet adapter"},
      {"joint.closingLoop", N, "maximal coordinates: every joint is a constraint, loops included"},
      {"body.initialVelocityOfJointedBody", N, "setLinearVelocity, setAngularVelocity, as given"},
      {"contact.rigidPairs", N,
       "combine callbacks look up Scene::pairMaterial for each pair; restitution threshold 0"},
      {"contact.nonSeparableMaterials", N, "every pair gets its own values (combine callbacks)"},
      {"particle", U, rigidOnly},
      {"cloth", U, rigidOnly},
      {"solid", U, rigidOnly},
      {"rod", U, rigidOnly},
      {"fluid", U, rigidOnly},
  }};
}

}  // namespace pbdval
