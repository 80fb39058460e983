// Contact dynamics against closed forms: resting penetration, rebound e², the incline's stick
// and slide law, the stopping distance, the seed's documented flaws and their corrections,
// particle contacts, materials and determinism. Both contact models run where they should
// agree. Expected values come from the formulas in each test's comment, never from a run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/scene_fixtures.h"
#include "pbd/contacts/contact_materials.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

constexpr Real kG = Real(9.81);
const ContactModel kModels[] = {ContactModel::Seed, ContactModel::Corrected};

Scene baseScene(Real h, ContactModel model) {
  Scene s;
  s.simulation.timeStepSize = h;
  s.simulation.subSteps = 5;
  s.simulation.contactModel = model;
  return s;
}

/// A static box whose top face is the plane y = 0.
RigidBodyDesc ground(Real friction = Real(0.2), Real restitution = Real(0.6)) {
  RigidBodyDesc g = test::boxBody(0, Vector3(4, 1, 4), Vector3(0, Real(-0.5), 0), 1, false);
  g.friction = friction;
  g.restitution = restitution;
  return g;
}

void setPairMaterial(Scene& s, int a, int b, Real friction, Real restitution) {
  s.contactPairs.push_back(pbd::test::contactPair(a, b, friction, restitution));
}

/// The depth into the contact shell at which a resting body's penalty holds it: during a step
/// gravity moves it by g h_s² n(n+1)/2 = g h² (n+1)/(2n) towards the ground, and the velocity
/// pass leaves it moving out at k_c |d|; equilibrium when k_c |d| h = g h² (n+1)/(2n). One
/// contact gives exactly this; several contacts solved by Gauss–Seidel add up to one penalty
/// each in the first sweep, so they hold the body at least D/N deep (N contacts), never
/// deeper than D.
Real restingShellDepth(const Scene& s, Real stiffness) {
  const Real h = s.simulation.timeStepSize, n = Real(s.simulation.subSteps);
  return kG * h * (n + 1) / (2 * n) / stiffness;
}

// --- Resting box ------------------------------------------------------------------------------

TEST(RestingBox, SinksNoDeeperThanThePenaltyEquilibriumAndDoesNotDrift) {
  for (ContactModel model : kModels) {
    for (Real stiffness : {Real(1), Real(100)}) {
      Scene s = baseScene(Real(0.005), model);  // the seed's defaults: h 5 ms, 5 substeps
      s.simulation.contactStiffnessRigidBody = stiffness;
      // Released at rest with its bottom on the shell (contactTolerance above the ground).
      const Real tolerance = s.simulation.contactTolerance;
      s.rigidBodies = {ground(),
                       test::boxBody(1, Vector3::Constant(Real(0.2)),
                                     Vector3(Real(0.3), Real(0.1) + tolerance, Real(-0.2)), 1000)};
      World w = buildWorld(s, CollisionShapeOptions{"", 0});
      const Real bound = restingShellDepth(s, stiffness);
      Real deepest = 0, finalDepth = 0;
      const Vector3 start = w.bodies.rigid.position[1];
      Vector3 settled = start;
      for (int step = 0; step < 2000; ++step) {  // 10 s: 10 time constants 1/k_c at k_c = 1
        w.step();
        finalDepth = tolerance - (w.bodies.rigid.position[1].y() - Real(0.1));
        deepest = std::max(deepest, finalDepth);
        if (step == 999) settled = w.bodies.rigid.position[1];
      }
      const Vector3 moved = w.bodies.rigid.position[1] - start;
      const Vector3 drift = w.bodies.rigid.position[1] - settled;
      std::printf(
          "  resting box, %-9s k_c = %5.1f: depth in the shell %.3e m (bound %.3e), below the "
          "ground %.3e m, sideways %.1e m, then %.1e m in 5 s\n",
          contactModelName(model), double(stiffness), double(finalDepth), double(bound),
          double(finalDepth - tolerance), double(std::hypot(moved.x(), moved.z())),
          double(std::hypot(drift.x(), drift.z())));
      // Round-off allowance on the bound: the depth is a difference of O(1) positions.
      EXPECT_LE(deepest, bound + 64 * kEpsilon) << contactModelName(model) << " k " << stiffness;
      EXPECT_GE(finalDepth, bound / 4) << contactModelName(model) << " k " << stiffness;
      // Nothing pushes sideways. While the box settles, Gauss–Seidel's order asymmetry may
      // shift it a little: at most 1/1000 of the contact tolerance. Once settled it must not
      // drift at all: a sideways friction error of even 1 mm/s² would move it 1.25 cm in the
      // last 5 s; 100 nm is round-off level on a 1 m scale over 1000 steps.
      EXPECT_LE(std::hypot(moved.x(), moved.z()), tolerance / 1000) << contactModelName(model);
      EXPECT_LE(std::hypot(drift.x(), drift.z()), std::max(Real(1e-7), 1000 * kEpsilon))
          << contactModelName(model);
    }
  }
}

// The seed applies restitution to resting contacts: each step, the approach speed gravity
// builds up (≈ g h) is reflected, and a box with e = 1 hops instead of resting, staying much
// shallower than with e = 0. The corrected model applies restitution only above 2|g|h:
// resting, e makes no difference at all (bitwise).
TEST(RestingBox, RestitutionActsOnRestingContactsOnlyInTheSeedModel) {
  auto finalDepth = [](ContactModel model, Real restitution) {
    Scene s = baseScene(Real(0.005), model);
    s.rigidBodies = {
        ground(), test::boxBody(1, Vector3::Constant(Real(0.2)), Vector3(0, Real(0.1), 0), 1000)};
    setPairMaterial(s, 0, 1, Real(0.5), restitution);
    World w = buildWorld(s, CollisionShapeOptions{"", 0});
    Real sum = 0;
    for (int step = 0; step < 2000; ++step) {
      w.step();
      if (step >= 1600)
        sum += s.simulation.contactTolerance - (w.bodies.rigid.position[1].y() - Real(0.1));
    }
    return sum / 400;  // mean depth in the shell over the last 2 s
  };
  const Real seedElastic = finalDepth(ContactModel::Seed, 1);
  const Real seedInelastic = finalDepth(ContactModel::Seed, 0);
  std::printf("  resting box, mean shell depth: seed e=1 %.3e m, e=0 %.3e m\n", double(seedElastic),
              double(seedInelastic));
  EXPECT_LT(seedElastic, seedInelastic / 2);
  EXPECT_EQ(finalDepth(ContactModel::Corrected, 1), finalDepth(ContactModel::Corrected, 0));
}

// --- Rebound ------------------------------------------------------------------------------------

/// The sphere drop of the parity suite: r = 0.1 m from 1 m onto the ground, h = 1 ms. Returns
/// the first rebound's apex over the drop, both from the contact height, and the impact speed.
struct Rebound {
  Real ratio = 0, impactSpeed = 0;
};
Rebound dropSphere(Scene s) {
  World w = buildWorld(s, CollisionShapeOptions{"", 0});
  Real previousY = w.bodies.rigid.position[1].y(), previousV = 0, contactY = 0, apex = 0;
  Real impact = 0;
  bool bounced = false;
  for (int step = 0; step < 2000; ++step) {
    w.step();
    const Real y = w.bodies.rigid.position[1].y(), v = w.bodies.rigid.velocity[1].y();
    if (!bounced && v > 0) {
      bounced = true;
      contactY = std::min(y, previousY);
      apex = y;
      impact = -previousV;
    } else if (bounced) {
      if (v < 0) break;
      apex = std::max(apex, y);
    }
    previousY = y;
    previousV = v;
  }
  const Real dropHeight = s.rigidBodies[1].translation.y() - contactY;
  return {(apex - contactY) / dropHeight, impact};
}

// The rebound speed is e u_n plus the penalty k_c |d| (|d| ≤ the last step's travel v h into
// the shell), and semi-implicit Euler loses g h_s/2 per unit of speed on the way down and up:
// ratio = e² + 2e k_c |d|/v − (e + e²) g h_s/v to first order. Tolerance: twice those terms.
Real reboundTolerance(Real e, Real stiffness, Real h, Real hs, Real v) {
  return 2 * (2 * e * stiffness * h + (e + e * e) * kG * hs / v);
}

TEST(Rebound, ApexRatioIsESquaredForEveryCombinationRule) {
  // In float, the velocity update v = (x − x_old)/h_s cancels: |x| ≈ 1 m against steps of
  // v h_s ≈ 1 mm at h_s = 0.2 ms leaves 3–4 digits, and the free fall's speed is already 9 %
  // off after 50 steps. That is the integrator's precision, not the contact's.
  if (sizeof(Real) < 8) GTEST_SKIP() << "float cannot resolve this drop's velocities";
  const Real sphereE = Real(0.9), groundE = Real(0.5);
  struct Case {
    ContactCombineRule rule;
    Real e;
  };
  const Case cases[] = {{ContactCombineRule::Seed, sphereE * groundE},
                        {ContactCombineRule::Product, sphereE * groundE},
                        {ContactCombineRule::Average, (sphereE + groundE) / 2},
                        {ContactCombineRule::Min, groundE},
                        {ContactCombineRule::Max, sphereE}};
  for (ContactModel model : kModels) {
    for (const Case& c : cases) {
      Scene s = baseScene(Real(0.001), model);
      s.simulation.contactCombineRule = c.rule;
      RigidBodyDesc ball = test::sphereBody(1, Real(0.1), Vector3(0, Real(1.1), 0), 1000);
      ball.restitution = sphereE;
      s.rigidBodies = {ground(Real(0.2), groundE), ball};
      ASSERT_EQ(s.pairMaterial(0, 1).restitution, c.e);
      const Rebound r = dropSphere(s);
      const Real tolerance =
          reboundTolerance(c.e, s.simulation.contactStiffnessRigidBody, s.simulation.timeStepSize,
                           Real(0.0002), r.impactSpeed);
      std::printf("  rebound %-9s rule %-7s e = %.2f: ratio %.5f (e^2 = %.5f, tolerance %.1e)\n",
                  contactModelName(model), contactCombineRuleName(c.rule), double(c.e),
                  double(r.ratio), double(c.e * c.e), double(tolerance));
      EXPECT_NEAR(r.ratio, c.e * c.e, tolerance)
          << contactModelName(model) << " " << contactCombineRuleName(c.rule);
    }
  }
}

// --- Incline ------------------------------------------------------------------------------------

struct InclineRun {
  Real distance = 0, acceleration = 0;
};

/// A 0.2 m block on a static incline (the parity suite's), μ = 0.25 + 0.25 by the seed's sum
/// rule; displacement and acceleration along the slope between t = 0.5 s and 1.5 s.
InclineRun incline(ContactModel model, Real theta) {
  Scene s = baseScene(Real(0.002), model);
  const Quaternion tilt(AngleAxis(theta, Vector3::UnitZ()));
  const Vector3 normal = tilt * Vector3::UnitY();
  RigidBodyDesc slope = test::boxBody(0, Vector3(4, Real(0.2), 4), Vector3::Zero(), 1, false, tilt);
  RigidBodyDesc block =
      test::boxBody(1, Vector3::Constant(Real(0.2)), normal * Real(0.2), 1000, true, tilt);
  slope.friction = block.friction = Real(0.25);
  slope.restitution = block.restitution = 0;
  s.rigidBodies = {slope, block};
  World w = buildWorld(s, CollisionShapeOptions{"", 0});
  const Vector3 downhill = tilt * Vector3(-1, 0, 0);
  Vector3 x0 = Vector3::Zero(), v0 = Vector3::Zero();
  for (int step = 1; step <= 750; ++step) {
    w.step();
    if (step == 250) x0 = w.bodies.rigid.position[1], v0 = w.bodies.rigid.velocity[1];
  }
  return {(w.bodies.rigid.position[1] - x0).dot(downhill),
          (w.bodies.rigid.velocity[1] - v0).dot(downhill) / 1};
}

// Below the friction angle the block sticks, up to the creep of velocity-level friction
// applied after the substeps: g sin θ h (n+1)/(2n) per second (see parity_profiles.cpp),
// +25 % for rocking on the four corners. Above, it slides with a = g (sin θ − μ cos θ): the
// friction impulse per step is μ times the normal impulse, which is m g cos θ h plus the
// change of the penalty velocity k_c |d|; over the 1 s window |d| changes by at most the
// resting depth D, so |a − law| ≤ μ k_c D / 1 s.
TEST(Incline, SticksBelowTheFrictionAngleAndSlidesAboveWithTheCoulombLaw) {
  const Real mu = Real(0.5), frictionAngle = std::atan(mu), margin = Real(5 * M_PI / 180);
  for (ContactModel model : kModels) {
    const Real stick = frictionAngle - margin;
    const InclineRun sticking = incline(model, stick);
    const Real creep = Real(1.25) * kG * std::sin(stick) * Real(0.002) * Real(0.6);
    EXPECT_LE(std::abs(sticking.distance), creep) << contactModelName(model);
    const Real slide = frictionAngle + margin;
    const InclineRun sliding = incline(model, slide);
    const Real law = kG * (std::sin(slide) - mu * std::cos(slide));
    const Real depth = kG * Real(0.002) * Real(0.6) / 1;  // k_c = 1
    EXPECT_NEAR(sliding.acceleration, law, mu * 1 * depth / 1) << contactModelName(model);
    std::printf(
        "  incline %-9s: %.2f deg moved %.2e m in 1 s (creep bound %.2e); %.2f deg a = %.5f "
        "(law %.5f)\n",
        contactModelName(model), double(stick * 180 / M_PI), double(sticking.distance),
        double(creep), double(slide * 180 / M_PI), double(sliding.acceleration), double(law));
  }
}

// --- Sliding to rest on flat ground -------------------------------------------------------------

struct SlideRun {
  Real distance = 0, mostNegativeVelocity = 0;
};

/// A resting block on flat ground (μ = 0.5, e = 0) pushed to v₀ along x.
SlideRun slideToRest(ContactModel model, Real v0) {
  Scene s = baseScene(Real(0.002), model);
  s.rigidBodies = {ground(),
                   test::boxBody(1, Vector3::Constant(Real(0.2)), Vector3(0, Real(0.1), 0), 1000)};
  setPairMaterial(s, 0, 1, Real(0.5), 0);
  World w = buildWorld(s, CollisionShapeOptions{"", 0});
  for (int step = 0; step < 1500; ++step)  // settle into the shell (3 s, 3 time constants)
    w.step();
  const Real x0 = w.bodies.rigid.position[1].x();
  w.bodies.rigid.velocity[1].x() = v0;
  SlideRun run;
  for (int step = 0; step < 1000; ++step) {
    w.step();
    run.mostNegativeVelocity = std::min(run.mostNegativeVelocity, w.bodies.rigid.velocity[1].x());
  }
  run.distance = w.bodies.rigid.position[1].x() - x0;
  return run;
}

// Friction takes μ g h off the speed every step: the block stops after v₀²/(2μg), to within
// one step of travel v₀ h.
TEST(Sliding, StopsAfterTheCoulombDistance) {
  const Real v0 = 2, mu = Real(0.5);
  for (ContactModel model : kModels) {
    const SlideRun run = slideToRest(model, v0);
    EXPECT_NEAR(run.distance, v0 * v0 / (2 * mu * kG), v0 * Real(0.002)) << contactModelName(model);
  }
}

// Friction capped per iteration (the seed): each of the block's four contacts may apply up to
// the impulse that would stop it alone, so a slow block (v₀ = 4 mm/s < μ g h = 9.8 mm/s: one
// step of friction suffices) is thrown backwards, by more than 10 % of v₀ (double: 29 %,
// float: 16 %). On the accumulated impulse (corrected) the friction stops it; what remains is
// the box tilting back on its penalty-held corners after the stop (the COM moves by ω × r),
// well below 10 % of v₀.
TEST(Sliding, TheSeedsPerIterationCapReversesASlowBlockTheCorrectedModelDoesNot) {
  const Real v0 = Real(0.004);
  const SlideRun seed = slideToRest(ContactModel::Seed, v0);
  const SlideRun corrected = slideToRest(ContactModel::Corrected, v0);
  std::printf("  slow block (4 mm/s): most negative speed seed %.2e, corrected %.2e m/s\n",
              double(seed.mostNegativeVelocity), double(corrected.mostNegativeVelocity));
  EXPECT_LT(seed.mostNegativeVelocity, -v0 / 10);
  EXPECT_GT(corrected.mostNegativeVelocity, -v0 / 10);
}

// --- Particles ----------------------------------------------------------------------------------

/// One free particle (a one-triangle cloth with two static vertices far away) dropped from
/// 1 m onto the ground.
Scene particleDrop(ContactCombineRule rule) {
  Scene s = baseScene(Real(0.001), ContactModel::Seed);
  s.simulation.contactCombineRule = rule;
  // Free particles: the default cloth method (2) would hold the particle by its FEM triangle.
  s.simulation.clothSimulationMethod = 0;
  s.rigidBodies = {ground(Real(0.2), Real(1.0))};
  TriangleModelDesc cloth;
  cloth.mesh.vertices = {Vector3(0, 1, 0), Vector3(10, 5, 0), Vector3(10, 5, 1)};
  cloth.mesh.triangles = {{0, 1, 2}};
  cloth.restitution = Real(0.6);
  s.triangleModels.push_back(cloth);
  for (const Vector3& v : cloth.mesh.vertices)
    s.particles.push_back({v, Vector3::Zero(), 1});
  s.particles[1].mass = s.particles[2].mass = 0;
  return s;
}

// A single contact, so the velocity pass is exact in closed form: the first iteration sets the
// normal velocity to ū + k_p |d| (ū = −e u⁰ the restitution target of the approach velocity
// u⁰ after the substeps, k_p |d| the penalty of the depth d at detection), and the later
// iterations leave it there (each removes and re-adds the same penalty). u⁰ is the previous
// step's velocity minus g h (semi-implicit Euler). The material is the particle's triangle
// model's combined with the body's by the rule: e = 0.6 · 1.0 (product), (0.6 + 1.0)/2
// (average). (The apex ratio is not e² here: while the particle is still inside the shell in
// the next steps, the penalty, 100/s, keeps pushing it out.)
TEST(ParticleContacts, ReboundVelocityIsTheRestitutionTargetPlusThePenalty) {
  for (ContactCombineRule rule : {ContactCombineRule::Product, ContactCombineRule::Average}) {
    const Scene s = particleDrop(rule);
    const Real e = s.particleMaterial(0, 0).restitution;
    EXPECT_EQ(e, rule == ContactCombineRule::Product ? Real(0.6) : Real(0.8));
    World w = buildWorld(s, CollisionShapeOptions{"", 0});
    Real previous = 0;
    for (int step = 0; step < 1000 && w.contacts.particle.empty(); ++step) {
      previous = w.bodies.particles.velocity[0].y();
      w.step();
    }
    ASSERT_EQ(w.contacts.particle.size(), 1u);
    const Real approach = previous - kG * s.simulation.timeStepSize;
    const Real depth = -w.contacts.geometry.particle[0].distance;
    const Real expected = -e * approach + s.simulation.contactStiffnessParticleRigidBody * depth;
    // Round-off: a few operations on velocities of ~4 m/s.
    EXPECT_NEAR(w.bodies.particles.velocity[0].y(), expected, 64 * kEpsilon * 4)
        << contactCombineRuleName(rule);
    std::printf(
        "  particle rebound, rule %-7s e = %.2f: %.6f m/s after %.6f m/s (predicted %.6f)\n",
        contactCombineRuleName(rule), double(e), double(w.bodies.particles.velocity[0].y()),
        double(approach), double(expected));
  }
}

// --- Materials ----------------------------------------------------------------------------------

TEST(ContactMaterials, EqualTheScenesPairAndParticleMaterials) {
  for (ContactCombineRule rule :
       {ContactCombineRule::Seed, ContactCombineRule::Product, ContactCombineRule::Average,
        ContactCombineRule::Min, ContactCombineRule::Max}) {
    Scene s = particleDrop(rule);
    s.rigidBodies.push_back(test::boxBody(1, Vector3::Ones(), Vector3(0, 5, 0)));
    s.rigidBodies.push_back(test::boxBody(2, Vector3::Ones(), Vector3(0, 9, 0)));
    s.rigidBodies[1].friction = Real(0.7);
    s.rigidBodies[2].restitution = Real(0.1);
    ContactPairDesc pair;
    pair.body1 = 2;
    pair.body2 = 0;
    pair.hasFriction = true;
    pair.friction = Real(0.05);
    s.contactPairs.push_back(pair);
    const ContactMaterials materials(s);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        if (a == b) continue;
        EXPECT_EQ(materials.rigid(a, b).friction, s.pairMaterial(a, b).friction);
        EXPECT_EQ(materials.rigid(a, b).restitution, s.pairMaterial(a, b).restitution);
      }
      const ContactMaterial expected = combineMaterials(
          rule, {Real(0.2), Real(0.6)},
          {s.rigidBodies[std::size_t(a)].friction, s.rigidBodies[std::size_t(a)].restitution});
      EXPECT_EQ(s.particleMaterial(0, a).friction, expected.friction);
      EXPECT_EQ(s.particleMaterial(0, a).restitution, expected.restitution);
      EXPECT_EQ(materials.particle(0, a).friction, expected.friction);
      EXPECT_EQ(materials.particle(0, a).restitution, expected.restitution);
    }
    EXPECT_EQ(materials.rigid(0, 2).friction, Real(0.05));
  }
}

// --- Determinism --------------------------------------------------------------------------------

/// A stack, a pile of spheres and a grid-SDF body on the ground.
Scene pile(ContactModel model) {
  Scene s = baseScene(Real(0.005), model);
  s.rigidBodies.push_back(ground());
  int id = 1;
  for (int i = 0; i < 4; ++i)
    s.rigidBodies.push_back(test::boxBody(id++, Vector3::Constant(Real(0.2)),
                                          Vector3(Real(0.01) * i, Real(0.1 + 0.21 * i), 0), 500));
  for (int i = 0; i < 6; ++i)
    s.rigidBodies.push_back(test::sphereBody(
        id++, Real(0.08), Vector3(Real(0.5) + Real(0.05) * (i % 2), Real(0.1 + 0.17 * i), 0), 500));
  RigidBodyDesc ball = test::sphereBody(id++, Real(0.15), Vector3(-Real(0.5), Real(0.4), 0), 300);
  auto mesh = loadObj(std::string(PBDVAL_SOURCE_DIR) + "/cases/models/sphere.obj");
  for (Vector3& v : mesh.vertices)
    v *= Real(0.15);
  ball.mesh = std::make_shared<const TriangleMesh>(mesh);
  ball.scale = Vector3::Constant(Real(0.15));
  ball.collision.type = CollisionObjectType::SignedDistanceField;
  ball.collision.scale = ball.scale;
  s.rigidBodies.push_back(ball);
  return s;
}

TEST(ContactDeterminism, SameContactSceneGivesBitwiseIdenticalStates) {
  for (ContactModel model : kModels) {
    const Scene scene = pile(model);
    World a = buildWorld(scene, CollisionShapeOptions{"", 0});
    World b = buildWorld(scene, CollisionShapeOptions{"", 0});
    std::size_t contacts = 0;
    for (int step = 0; step < 400; ++step) {
      a.step();
      b.step();
      contacts = std::max(contacts, a.contacts.rigid.size());
    }
    EXPECT_GT(contacts, 20u) << "the scene must be in contact";
    EXPECT_EQ(a.stateHash(), b.stateHash()) << contactModelName(model);
    EXPECT_EQ(a.contacts.geometry.droppedContacts + a.contacts.geometry.droppedPairs, 0u);
  }
}

}  // namespace
}  // namespace pbd
