// How the ODE adapter maps every scene feature (adapters/features.h): the one declaration that
// OdeEngine::unsupported and docs/parity-ode.md are made from.
#include "adapters/ode/ode_engine.h"

namespace pbdval {

FeatureTable odeFeatures() {
  const Support N = Support::Native, A = Support::Approximated, U = Support::Unsupported;
  const char* noParticles = "ODE has no particles";
  return {{
      {"shape.none", N, "no geom"},
      {"shape.sphere", N, "dCreateSphere(r = collisionObjectScale[0])"},
      {"shape.box", N, "dCreateBox(collisionObjectScale) (full extents)"},
      {"shape.cylinder", N,
       "dCreateCylinder(r, h), turned by −90° about x: ODE's axis is z, the seed's y"},
      {"shape.torus.mesh", A,
       "the body's geometryFile mesh as a trimesh (dCreateTriMesh), assumed to be the same solid "
       "as the analytic torus (the models' size convention)"},
      {"shape.torus.analytic", U,
       "ODE collides the body's geometryFile as a trimesh, and there is none"},
      {"shape.sdf.mesh", A, "the body's mesh as a trimesh instead of a distance field"},
      {"shape.sdf.fileOnly", U,
       "ODE collides the body's geometryFile as a trimesh, and there is none"},
      {"shape.sdf.precomputedFile", U,
       "ODE cannot read a precomputed SDF; it collides the geometry mesh (leave "
       "collisionObjectFileName empty)"},
      {"shape.hollowSphere", U, "ODE has no hollow shape (a wall of thickness thicknessSDF)"},
      {"shape.hollowBox", U, "ODE has no hollow shape (a wall of thickness thicknessSDF)"},
      {"shape.invertSDF", U, "ODE's shapes and trimeshes have no inside-out form"},
      {"joint.ball", N, "dJointCreateBall at position"},
      {"joint.ballOnLine",
       A,
       "ODE has no point-on-line joint: an auxiliary carriage body (carriageMassRatio = 1e-3 of "
       "the lighter dynamic end) slides on a dJointCreateSlider along axis in body 0 and carries "
       "body 1 on a ball joint; it adds 0.1 % of the mass to the motion along the line",
       {"ode.step"}},
      {"joint.ballOnLine",
       U,
       "ODE has no ball-on-line joint; the light carriage body that emulates it is beyond "
       "QuickStep's iterative solver (the anchor leaves the line by 0.1 m in "
       "cases/joint_ball_on_line.json): use ode.step",
       {"ode.quickstep"}},
      {"joint.hinge", N, "dJointCreateHinge at position, axis"},
      {"joint.universal", N,
       "dJointCreateUniversal: axis1 fixed in body 0, axis2 in body 1 (ODE fixes its axis 1 in its "
       "first body)"},
      {"joint.slider", N, "dJointCreateSlider along axis"},
      {"joint.rigidBodyParticleBall", U, noParticles},
      {"joint.rigidBodySpring", A,
       "dJointCreateDBall between position1 and position2, its row made a spring: ERP = h k/(h k + "
       "c), CFM = 1/(h k + c) with c = 0: implicit Euler on the spring (the seed's XPBD spring is "
       "implicit Euler per substep)"},
      {"joint.distance", N,
       "dJointCreateDBall, rest length ‖position2 − position1‖, joint ERP/CFM"},
      {"joint.damper", A,
       "slider with both stops at 0 (a bilateral limit row) and the stop ERP/CFM made an implicit "
       "spring, no damping, as the seed's"},
      {"joint.targetAngleMotorHinge", A,
       "hinge motor as a servo: dParamVel = (set point at the end of the step − angle)/h, "
       "dParamFMax = ∞; ODE's rotation update lags the angle by (h ω)³/12 per step"},
      {"joint.targetVelocityMotorHinge", N,
       "hinge motor: dParamVel = the set point at the end of the step, dParamFMax = ∞"},
      {"joint.targetPositionMotorSlider", A, "slider motor as a servo, as the angle motor"},
      {"joint.targetVelocityMotorSlider", N,
       "slider motor: dParamVel = the set point, dParamFMax = ∞"},
      {"joint.stiffRod", U,
       "stiff-rod joints (CosseratJoints, elastic bending and twisting between rod segments) are "
       "not mapped by the ODE adapter"},
      {"joint.closingLoop", N, "maximal coordinates: every joint is a constraint, loops included"},
      {"body.initialVelocityOfJointedBody", N, "dBodySetLinearVel / AngularVel, as given"},
      {"contact.rigidPairs", N,
       "per pair from Scene::pairMaterial in the near callback (ODE has no combination rule); "
       "bounce = e, bounce_vel 0; Coulomb pyramid (dContactApprox1), world-aligned"},
      {"contact.nonSeparableMaterials", N, "every pair gets its own values"},
      {"particle", U, noParticles},
      {"cloth", U, noParticles},
      {"solid", U, noParticles},
      {"rod", U, noParticles},
      {"fluid", U, noParticles},
  }};
}

}  // namespace pbdval
