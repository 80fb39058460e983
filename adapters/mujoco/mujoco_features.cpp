// How the MuJoCo 2.2.2 adapter maps every scene feature (adapters/features.h): the one
// declaration that MujocoEngine::unsupported and docs/parity-mujoco.md are made from.
#include "adapters/mujoco/mujoco_engine.h"

namespace pbdval {

FeatureTable mujocoFeatures() {
  const Support N = Support::Native, A = Support::Approximated, U = Support::Unsupported;
  const char* noParticles =
      "MuJoCo has no particles in this adapter (flexes: through MuJoCo 4, the mujoco-python "
      "engine)";
  return {{
      {"shape.none", N, "no geom"},
      {"shape.sphere", N, "sphere, radius"},
      {"shape.box", N, "box, half extents"},
      {"shape.cylinder", N,
       "cylinder (radius, half height), turned −90° about x: MuJoCo's axis is z, the seed's y"},
      {"shape.torus", U,
       "MuJoCo has no torus, and a mesh collides as its convex hull, which fills the hole"},
      {"shape.sdf.mesh", A,
       "the mesh (× collisionObjectScale) as a MuJoCo mesh, which always collides as its convex "
       "hull; exact for convex meshes; recorded as a warning"},
      {"shape.sdf.fileOnly", U, "MuJoCo needs the mesh (it cannot read SDF files)"},
      {"shape.sdf.precomputedFile", A, "not used: MuJoCo collides the body's mesh"},
      {"shape.hollowSphere", U, "MuJoCo collides meshes as convex hulls, which are solid"},
      {"shape.hollowBox", U, "MuJoCo collides meshes as convex hulls, which are solid"},
      {"shape.invertSDF", U, "MuJoCo has no inside-out collision shapes"},
      {"joint.ball", N, "ball at the anchor"},
      {"joint.ballOnLine", N,
       "slide then ball (or ball then slide when the line's body is the child)"},
      {"joint.hinge", N, "hinge"},
      {"joint.universal", N,
       "two hinges in one body, axis1 first (fixed in the parent), axis2 second"},
      {"joint.slider", N, "slide"},
      {"joint.rigidBodyParticleBall", U, noParticles},
      {"joint.rigidBodySpring", A,
       "a spatial tendon with stiffness k and springlength L: a force, explicit in the "
       "integrators"},
      {"joint.distance", A,
       "never in the tree: a spatial tendon between the anchors and a soft tendon equality holding "
       "its initial length"},
      {"joint.damper", N,
       "slide with joint stiffness k, springref = the initial offset; no damping (as the scene's)"},
      {"joint.targetAngleMotorHinge", A,
       "hinge + critically damped PD servo (kp = m/τ_s², kv = 2m/τ_s): a ramp lags by 2τ_s·slope, "
       "a static load F leaves F/kp"},
      {"joint.targetVelocityMotorHinge", A,
       "hinge + velocity servo kv = m/τ_s: a load F leaves a speed error F/kv"},
      {"joint.targetPositionMotorSlider", A, "slide + PD servo, as the angle motor"},
      {"joint.targetVelocityMotorSlider", A, "slide + velocity servo"},
      {"joint.stiffRod", U,
       "stiff-rod joints (CosseratJoints, elastic bending and twisting between rod segments) are "
       "not mapped by the MuJoCo adapter"},
      {"joint.closingLoop.ballOrHinge", A,
       "soft equality constraints (equalityTimeconst, solimp*): a ball is one connect, a hinge two "
       "connects along the axis"},
      {"joint.closingLoop.other", U,
       "MuJoCo has no equality constraint for this joint type (only ball and hinge joints can "
       "close loops in this adapter)"},
      {"body.initialVelocityOfJointedBody", A,
       "the scene's velocities projected onto the joints' free motions in the kinetic-energy norm "
       "(reduced coordinates cannot hold a velocity that violates a joint); recorded as a warning"},
      {"contact.rigidPairs", N,
       "explicit <pair>s with Scene::pairMaterial's friction (MuJoCo's max rule never enters); "
       "restitution approximated by a spring-damper whose damping ratio gives e"},
      {"contact.nonSeparableMaterials", N, "every pair is an explicit <pair> with its own values"},
      {"particle", U, noParticles},
      {"cloth", U, noParticles},
      {"solid", U, noParticles},
      {"rod", U, noParticles},
      {"fluid", U, noParticles},
  }};
}

}  // namespace pbdval
