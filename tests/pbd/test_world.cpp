// World-level properties: determinism, solve order, and no heap allocation inside a step.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>

#include "common/scene_fixtures.h"
#include "common/stiff_rod_scenes.h"
#include "common/tet_blocks.h"
#include "pbd/model/world.h"

// Counting allocator for this test binary: every operator new (plain and nothrow, which
// std::stable_sort's temporary buffer uses) bumps the counter; array forms forward to these.
// Only the no-allocation tests read it.
namespace {
std::atomic<long> gAllocations{0};
}
void* operator new(std::size_t size) {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
// GCC inlines these into callers that got the memory from the operator new above and then
// warns about free() on memory from "new" (-Wmismatched-new-delete); they are a matched pair.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
#pragma GCC diagnostic pop

namespace pbd {
namespace {

// A chain of 10 boxes on alternating joint types, plus a motorised end, so that every kind
// of solve runs.
Scene chainScene() {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.rigidBodies.push_back(test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 5, 0), 1, false));
  const JointType types[] = {JointType::Ball,
                             JointType::Hinge,
                             JointType::Universal,
                             JointType::BallOnLine,
                             JointType::Distance,
                             JointType::TargetVelocityMotorHinge,
                             JointType::RigidBodySpring,
                             JointType::TargetAngleMotorHinge,
                             JointType::Ball};
  for (int i = 1; i <= 9; ++i) {
    const Vector3 pos(0.5 * i, 5, 0.01 * i);
    s.rigidBodies.push_back(test::boxBody(i, Vector3(0.4, 0.1, 0.1), pos, 50));
    JointDesc j = test::makeJointDesc(types[i - 1], i - 1, i);
    j.position = pos - Vector3(0.25, 0, 0);
    j.axis = Vector3(0, 0, 1);
    j.axis1 = Vector3(0, 0, 1);
    j.axis2 = Vector3(0, 1, 0);
    j.position1 = pos - Vector3(0.3, 0, 0);
    j.position2 = pos - Vector3(0.2, 0, 0);
    j.stiffness = 5000;
    j.target.times = {0, 1, 2};
    j.target.values = {0, 0.5, -0.5};
    j.target.repeat = true;
    s.joints.push_back(j);
  }
  return s;
}

TEST(World, SameSceneGivesBitwiseIdenticalStates) {
  const Scene scene = chainScene();
  World a = buildWorld(scene);
  World b = buildWorld(scene);
  for (int n = 0; n < 400; ++n) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.stateHash(), b.stateHash());
  // The hash sees a one-ulp change.
  b.bodies.rigid.position[3].x() = std::nextafter(b.bodies.rigid.position[3].x(), Real(1e9));
  EXPECT_NE(a.stateHash(), b.stateHash());
}

TEST(World, StepAllocatesNothing) {
  World world = buildWorld(chainScene());
  world.step();  // warm-up (nothing is lazily allocated, but do not count construction)
  const long before = gAllocations.load();
  for (int n = 0; n < 200; ++n)
    world.step();
  EXPECT_EQ(gAllocations.load() - before, 0);
  // The counter works: a vector allocation is seen.
  std::vector<int> probe(10);
  EXPECT_GT(gAllocations.load() - before, 0);
}

// A world with generic constraints (constraints/generic_constraint.h) allocates nothing in
// either step method: a pendulum on a generic distance constraint with its analytic gradient,
// a second one on central differences, and a two-component line pin (captureless callbacks,
// so std::function stores them in place; the solve's matrices have fixed maximum sizes).
TEST(GenericConstraintWorld, StepAllocatesNothing) {
  auto distanceValue = [](const GenericPositions& x, GenericValue& c) {
    c(0) = (x.col(0) - x.col(1)).norm() - 1;
  };
  auto distanceGradient = [](const GenericPositions& x, GenericJacobian& j) {
    const Vector3 n = (x.col(0) - x.col(1)).normalized();
    j.block<1, 3>(0, 0) = n.transpose();
    j.block<1, 3>(0, 3) = -n.transpose();
  };
  auto onVerticalLine = [](const GenericPositions& x, GenericValue& c) {  // x = 2, z = 0
    c(0) = x(0, 0) - 2;
    c(1) = x(2, 0);
  };
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd}) {
    Scene scene;
    scene.simulation.stepMethod = stepMethod;
    scene.particles.push_back({Vector3::Zero(), Vector3::Zero(), 0});
    scene.particles.push_back({Vector3(1, 0, 0), Vector3::Zero(), 1});
    scene.particles.push_back({Vector3(0, 0, 1), Vector3::Zero(), 0});
    scene.particles.push_back({Vector3(0, 1, 1), Vector3::Zero(), 2});
    scene.particles.push_back({Vector3(2, 0, 0.5), Vector3::Zero(), 1});
    World world = buildWorld(scene);
    world.constraints.genericConstraints.emplace_back(std::vector<int>{0, 1}, 1, distanceValue,
                                                      distanceGradient);
    world.constraints.genericConstraints.emplace_back(std::vector<int>{2, 3}, 1, distanceValue);
    world.constraints.genericConstraints.emplace_back(std::vector<int>{4}, 2, onVerticalLine);
    world.step();
    const long before = gAllocations.load();
    for (int n = 0; n < 200; ++n)
      world.step();
    EXPECT_EQ(gAllocations.load() - before, 0);
    // The constraints held: the line pin is linear (exact to round-off of O(1) numbers, 16 ε).
    const Vector3& pinned = world.bodies.particles.position[4];
    EXPECT_NEAR(pinned.x(), 2, 16 * kEpsilon);
    EXPECT_NEAR(pinned.z(), 0, 16 * kEpsilon);
  }
}

// A world with generic rigid-body constraints (constraints/generic_rigid_constraint.h)
// allocates nothing in either step method: a box hanging from a static one on a generic ball
// joint with its analytic gradient, a second box hanging from the first on a compliant generic
// distance between body-fixed points with central differences (12 evaluations of C per body,
// the fixed-size poses copied each time), and a one-body pin of the first box's height. The
// callbacks capture their anchors (std::function may allocate when they are stored, at
// construction, never when they are called).
TEST(GenericRigidConstraintWorld, StepAllocatesNothing) {
  // Body 0 at (0, 2, 0), 1 at (0.3, 1.5, 0), 2 at (0.35, 0.9, 0): the ball joint at body 0's
  // centre, the distance (0.21 m, rest 0.2 m) from body 1's bottom to near body 2's top; the
  // boxes 0.2 m apart, so no contact moves them after the pin.
  const Vector3 a0(0, 0, 0), a1(-0.3, 0.5, 0), b1(0, -0.2, 0), b2(0, 0.2, 0.05);
  auto ballValue = [a0, a1](const GenericRigidPoses& p, GenericRigidValue& c) {
    c.head<3>() = p.position[1] + p.rotation[1] * a1 - p.position[0] - p.rotation[0] * a0;
  };
  auto ballGradient = [a0, a1](const GenericRigidPoses& p, GenericRigidJacobian& j) {
    j.block<3, 3>(0, 0) = -Matrix3::Identity();
    j.block<3, 3>(0, 3) = crossMatrix(p.rotation[0] * a0);
    j.block<3, 3>(0, 6) = Matrix3::Identity();
    j.block<3, 3>(0, 9) = -crossMatrix(p.rotation[1] * a1);
  };
  auto distanceValue = [b1, b2](const GenericRigidPoses& p, GenericRigidValue& c) {
    c(0) = (p.position[1] + p.rotation[1] * b2 - p.position[0] - p.rotation[0] * b1).norm() -
           Real(0.2);
  };
  auto heightPin = [](const GenericRigidPoses& p, GenericRigidValue& c) {
    c(0) = p.position[0].z();
  };
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd}) {
    Scene scene;
    scene.simulation.stepMethod = stepMethod;
    scene.simulation.xpbd.substeps = 5;
    scene.rigidBodies.push_back(
        test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1, false));
    scene.rigidBodies.push_back(
        test::boxBody(1, Vector3(0.1, 0.4, 0.1), Vector3(0.3, 1.5, 0), 100));
    scene.rigidBodies.push_back(
        test::boxBody(2, Vector3(0.1, 0.4, 0.1), Vector3(0.35, 0.9, 0), 100));
    World world = buildWorld(scene);
    world.constraints.genericRigidConstraints.emplace_back(std::vector<int>{0, 1}, 3, ballValue,
                                                           ballGradient);
    world.constraints.genericRigidConstraints.emplace_back(
        std::vector<int>{1, 2}, 1, distanceValue, GenericRigidGradientFunction(), 1, Real(1e-4));
    world.constraints.genericRigidConstraints.emplace_back(std::vector<int>{1}, 1, heightPin);
    world.step();
    const long before = gAllocations.load();
    for (int n = 0; n < 200; ++n)
      world.step();
    EXPECT_EQ(gAllocations.load() - before, 0);
    // The boxes swung (gravity acts), and the pin (linear, solved last) held to round-off.
    EXPECT_GT((world.bodies.rigid.position[2] - Vector3(0.35, 0.9, 0)).norm(), 0.01);
    EXPECT_NEAR(world.bodies.rigid.position[1].z(), 0, 16 * kEpsilon);
  }
}

// The families are swept once per position iteration, in their list order
// (constraints/constraint_families.h), by both step methods: a generic rigid-body constraint
// (first in the list) and a generic particle constraint (after every scene family) log each
// evaluation of their C, so the log is one run of rigid evaluations followed by one run of
// particle ones per iteration — maxIterations × subSteps pairs in the seed's step, one per
// substep in the XPBD step. Both constraints have analytic gradients and move their body or
// particle (gravity pulls them off the constraint), so every sweep evaluates each at least once.
TEST(ConstraintFamilies, BothStepsSweepTheFamiliesOncePerIterationInListOrder) {
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd}) {
    Scene scene;
    scene.simulation.stepMethod = stepMethod;
    scene.simulation.subSteps = 2;
    scene.simulation.maxIterations = 3;
    scene.simulation.xpbd.substeps = 4;
    scene.rigidBodies.push_back(test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 1));
    scene.particles.push_back({Vector3(5, 2, 0), Vector3::Zero(), 1});
    World world = buildWorld(scene);
    std::string log;
    log.reserve(1000);
    std::string* record = &log;
    world.constraints.genericRigidConstraints.emplace_back(
        std::vector<int>{0}, 1,
        [record](const GenericRigidPoses& p, GenericRigidValue& c) {
          record->push_back('R');
          c(0) = p.position[0].y() - 2;
        },
        [](const GenericRigidPoses&, GenericRigidJacobian& j) { j(0, 1) = 1; });
    world.constraints.genericConstraints.emplace_back(
        std::vector<int>{0}, 1,
        [record](const GenericPositions& x, GenericValue& c) {
          record->push_back('P');
          c(0) = x(1, 0) - 2;
        },
        [](const GenericPositions&, GenericJacobian& j) { j(0, 1) = 1; });
    world.step();
    ASSERT_FALSE(log.empty());
    EXPECT_EQ(log.front(), 'R') << log;
    EXPECT_EQ(log.back(), 'P') << log;
    int rigidToParticle = 0, particleToRigid = 0;
    for (std::size_t k = 1; k < log.size(); ++k) {
      rigidToParticle += log[k - 1] == 'R' && log[k] == 'P';
      particleToRigid += log[k - 1] == 'P' && log[k] == 'R';
    }
    const int sweeps = stepMethod == StepMethod::Seed ? 3 * 2 : 4;
    EXPECT_EQ(rigidToParticle, sweeps) << log;
    EXPECT_EQ(particleToRigid, sweeps - 1) << log;
  }
}

// A unit cube of five tets whose bottom (y = 0) particles are static, for the solid methods
// allocation tests below.
Scene cubeOfFiveTets() {
  Scene scene;
  TetModelDesc solid;
  for (int k = 0; k < 8; ++k)
    solid.mesh.vertices.push_back(Vector3(Real(k & 1), Real((k >> 1) & 1), Real((k >> 2) & 1)));
  solid.mesh.tetrahedra = {{0, 1, 2, 4}, {1, 3, 2, 7}, {1, 4, 5, 7}, {2, 4, 7, 6}, {1, 2, 4, 7}};
  scene.tetModels.push_back(solid);
  for (int k = 0; k < 8; ++k)
    scene.particles.push_back({solid.mesh.vertices[std::size_t(k)], Vector3::Zero(),
                               ((k >> 1) & 1) ? Real(1) : Real(0)});  // bottom (y = 0) static
  return scene;
}

/// The world of `scene` with vertex 6 pushed through its opposite face: one tet starts inverted.
World withInvertedTet(const Scene& scene) {
  World world = buildWorld(scene);
  world.bodies.particles.position[6] = Vector3(Real(0.2), Real(-0.5), Real(0.8));
  return world;
}

/// After one warm-up step, 200 steps of two worlds of the same input allocate nothing and leave
/// them bitwise identical.
void expectStepsAllocateNothingAndAgree(World& a, World& b, int method) {
  a.step();
  b.step();
  const long before = gAllocations.load();
  for (int n = 0; n < 200; ++n) {
    a.step();
    b.step();
  }
  EXPECT_EQ(gAllocations.load() - before, 0) << method;
  EXPECT_EQ(a.stateHash(), b.stateHash()) << method;
}

// FEM solids (solidSimulationMethod 2 and 3, both step methods) allocate nothing, the inversion
// path's fixed-size SVD included (one tet starts inverted), and two worlds stay bitwise
// identical.
TEST(World, FemSolidStepAllocatesNothing) {
  Scene scene = cubeOfFiveTets();
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd})
    for (int method : {2, 3}) {
      scene.simulation.solidSimulationMethod = method;
      scene.simulation.stepMethod = stepMethod;
      World a = withInvertedTet(scene);
      World b = withInvertedTet(scene);
      ASSERT_EQ(a.constraints.femTets.size(), 5u);
      int inverted = 0;
      for (const FemTetConstraint& c : a.constraints.femTets) {
        std::array<Vector3, 4> x;
        for (std::size_t i = 0; i < 4; ++i)
          x[i] = a.bodies.particles.position[std::size_t(c.particles[i])];
        inverted += femTetEnergy(x, c).inverted ? 1 : 0;
      }
      ASSERT_EQ(inverted, 1);
      expectStepsAllocateNothingAndAgree(a, b, method);
    }
}

// Strain-based tets (solidSimulationMethod 4) and shape matching (5), both step methods,
// allocate nothing (shape matching's fixed-size SVD and its reflection fix included: one tet
// starts inverted), and two worlds stay bitwise identical.
TEST(World, StrainTetAndShapeMatchingStepAllocatesNothing) {
  Scene scene = cubeOfFiveTets();
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd})
    for (int method : {4, 5}) {
      scene.simulation.solidSimulationMethod = method;
      scene.simulation.stepMethod = stepMethod;
      World a = withInvertedTet(scene);
      World b = withInvertedTet(scene);
      ASSERT_EQ(a.constraints.strainTets.size() + a.constraints.shapeMatching.size(), 5u);
      expectStepsAllocateNothingAndAgree(a, b, method);
    }
}

// A fluid (FluidModels, fluids/fluid_model.h) in a container, both step methods: the neighbour
// search, density iterations and XSPH allocate nothing, and two worlds stay bitwise identical.
// A small block breaking in a box, so that the neighbour lists change every substep.
TEST(World, FluidStepAllocatesNothing) {
  Scene scene;
  FluidModelDesc fluid;
  fluid.jsonPath = "FluidModels[0]";
  fluid.blocks.push_back({Vector3::Zero(), Vector3(Real(0.2), Real(0.3), Real(0.1))});
  fluid.container = AxisAlignedBox{Vector3::Zero(), Vector3(Real(0.6), Real(0.5), Real(0.1))};
  fluid.firstParticle = 0;
  for (const Vector3& x : fluidBlockParticles(fluid.blocks.front(), fluid.particleRadius))
    scene.particles.push_back({x, Vector3::Zero(), fluid.particleMass()});
  fluid.particleCount = static_cast<int>(scene.particles.size());
  scene.fluidModels.push_back(fluid);
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd}) {
    scene.simulation.stepMethod = stepMethod;
    World a = buildWorld(scene);
    World b = buildWorld(scene);
    ASSERT_EQ(a.fluids.size(), 1u);
    expectStepsAllocateNothingAndAgree(a, b, static_cast<int>(stepMethod));
    EXPECT_EQ(a.fluids.front().droppedNeighbours, 0u);
  }
}

// A contact scene: a stack of boxes, spheres, a body with a grid SDF (type 5, built from a
// cube mesh) and free particles, all on a static ground; contacts in both models.
Scene contactScene(ContactModel model) {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.simulation.contactModel = model;
  s.rigidBodies.push_back(test::boxBody(0, Vector3(4, 1, 4), Vector3(0, -0.5, 0), 1, false));
  for (int i = 1; i <= 3; ++i)
    s.rigidBodies.push_back(test::boxBody(i, Vector3::Constant(Real(0.2)),
                                          Vector3(0, Real(0.1 + 0.2 * (i - 1)), 0), 500));
  for (int i = 4; i <= 6; ++i)
    s.rigidBodies.push_back(
        test::sphereBody(i, Real(0.1), Vector3(Real(0.5), Real(0.1 + 0.19 * (i - 4)), 0), 500));
  RigidBodyDesc grid = test::boxBody(7, Vector3::Constant(Real(0.3)), Vector3(-0.5, 0.2, 0), 500);
  TriangleMesh cube;
  for (int k = 0; k < 8; ++k)
    cube.vertices.push_back(Real(0.3) * Vector3(Real(k & 1) - Real(0.5),
                                                Real((k >> 1) & 1) - Real(0.5),
                                                Real((k >> 2) & 1) - Real(0.5)));
  cube.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  grid.mesh = std::make_shared<const TriangleMesh>(cube);
  grid.scale = Vector3::Constant(Real(0.3));
  grid.collision.type = CollisionObjectType::SignedDistanceField;
  grid.collision.scale = grid.scale;
  s.rigidBodies.push_back(grid);
  TriangleModelDesc cloth;
  cloth.mesh.vertices = {Vector3(1, Real(0.3), 0), Vector3(Real(1.2), Real(0.3), 0),
                         Vector3(1, Real(0.3), Real(0.2))};
  cloth.mesh.triangles = {{0, 1, 2}};
  s.triangleModels.push_back(cloth);
  for (const Vector3& v : cloth.mesh.vertices)
    s.particles.push_back({v, Vector3::Zero(), 1});
  return s;
}

TEST(World, StepWithContactsAllocatesNothing) {
  for (ContactModel model : {ContactModel::Seed, ContactModel::Corrected}) {
    World world = buildWorld(contactScene(model), CollisionShapeOptions{"", 0});
    world.step();
    const long before = gAllocations.load();
    std::size_t rigidContacts = 0, particleContacts = 0;
    for (int n = 0; n < 300; ++n) {
      world.step();
      rigidContacts = std::max(rigidContacts, world.contacts.rigid.size());
      particleContacts = std::max(particleContacts, world.contacts.particle.size());
    }
    EXPECT_EQ(gAllocations.load() - before, 0) << contactModelName(model);
    // The scene really is in contact, rigid and particle alike.
    EXPECT_GT(rigidContacts, 10u);
    EXPECT_GT(particleContacts, 0u);
  }
}

// Particle–tet contacts (a tet cube dropped on a tet cube clamped at its bottom) allocate
// nothing in any schedule: the seed's (found after the substeps), the corrected one and the
// XPBD step's (found in every substep), detection, set-up and solve.
TEST(World, StepWithParticleTetContactsAllocatesNothing) {
  for (int schedule = 0; schedule < 3; ++schedule) {
    Scene scene;
    test::appendTetCube(scene, Vector3(0, 0, 0), 2, Real(0.25));
    test::appendTetCube(scene, Vector3(0.1, 0.52, 0.1), 2, Real(0.25));
    for (std::size_t i = 0; i < 27; ++i)
      if (scene.particles[i].position.y() == 0) scene.particles[i].mass = 0;
    scene.simulation.solidSimulationMethod = 3;
    scene.simulation.contactModel = schedule == 0 ? ContactModel::Seed : ContactModel::Corrected;
    scene.simulation.stepMethod = schedule == 2 ? StepMethod::Xpbd : StepMethod::Seed;
    World world = buildWorld(scene);
    world.step();
    const long before = gAllocations.load();
    std::size_t contacts = 0;
    for (int n = 0; n < 100; ++n) {
      world.step();
      contacts = std::max(contacts, world.tetContacts.contacts.size());
    }
    EXPECT_EQ(gAllocations.load() - before, 0) << schedule;
    EXPECT_GT(contacts, 0u) << schedule;  // it really is in contact
  }
}

// The XPBD step (pbd.xpbd) allocates nothing either: joints (the chain) and contacts (rigid and
// particle) with their per-step set-up and per-substep solves, with closed-form contacts (its
// default: box-box, sphere-box, sphere-sphere here, the grid box by samples) and with samples.
TEST(World, XpbdStepAllocatesNothing) {
  Scene chain = chainScene();
  chain.simulation.stepMethod = StepMethod::Xpbd;
  Scene contacts = contactScene(ContactModel::Seed);
  contacts.simulation.stepMethod = StepMethod::Xpbd;
  Scene sampled = contacts;
  sampled.simulation.contactGeometry = ContactGeometry::Samples;
  Scene chainStart = chain;  // the joints along their substep-start directions
  chainStart.simulation.xpbd.jointDirections = JointDirections::Start;
  Scene chainSweeps = chainStart;  // and swept twice per substep
  chainSweeps.simulation.xpbd.jointIterations = 2;
  for (const Scene* scene : {&chain, &chainStart, &chainSweeps, &contacts, &sampled}) {
    World world = buildWorld(*scene, CollisionShapeOptions{"", 0});
    world.step();
    const long before = gAllocations.load();
    std::size_t xpbdContacts = 0;
    for (int n = 0; n < 300; ++n) {
      world.step();
      xpbdContacts = std::max(xpbdContacts, world.xpbd.contacts.contacts.size());
    }
    EXPECT_EQ(gAllocations.load() - before, 0);
    if (scene != &chain && scene != &chainStart && scene != &chainSweeps) {
      EXPECT_GT(xpbdContacts, 10u);  // it really is in contact
    }
  }
}

// Two XPBD worlds from one scene stay bitwise identical (contacts included).
TEST(World, XpbdStepIsBitwiseDeterministic) {
  Scene scene = contactScene(ContactModel::Seed);
  scene.simulation.stepMethod = StepMethod::Xpbd;
  World a = buildWorld(scene, CollisionShapeOptions{"", 0});
  World b = buildWorld(scene, CollisionShapeOptions{"", 0});
  for (int n = 0; n < 300; ++n) {
    a.step();
    b.step();
  }
  EXPECT_EQ(a.stateHash(), b.stateHash());
  // And it is a different method: the seed's step gives another state.
  World seed = buildWorld(contactScene(ContactModel::Seed), CollisionShapeOptions{"", 0});
  for (int n = 0; n < 300; ++n)
    seed.step();
  EXPECT_NE(a.stateHash(), seed.stateHash());
}

// The parallel narrow phase (detectionThreads > 1) finds the same contacts in the same order as
// the serial one: both step methods and both contact models give bitwise the same states for
// 1, 2 and 3 threads, and a step with threads allocates nothing.
TEST(World, ParallelDetectionIsBitwiseEqualForEveryThreadCount) {
  for (StepMethod method : {StepMethod::Seed, StepMethod::Xpbd})
    for (ContactModel model : {ContactModel::Seed, ContactModel::Corrected}) {
      std::vector<std::uint64_t> hashes;
      std::vector<std::size_t> contactCounts;
      for (int threads : {1, 2, 3}) {
        Scene scene = contactScene(model);
        scene.simulation.stepMethod = method;
        scene.simulation.detectionThreads = threads;
        World world = buildWorld(scene, CollisionShapeOptions{"", 0});
        EXPECT_EQ(world.collision.threads(), threads);
        world.step();
        const long before = gAllocations.load();
        std::size_t contacts = 0;
        for (int n = 0; n < 200; ++n) {
          world.step();
          contacts +=
              world.contacts.geometry.rigid.size() + world.contacts.geometry.particle.size();
        }
        EXPECT_EQ(gAllocations.load() - before, 0) << threads << " threads";
        hashes.push_back(world.stateHash());
        contactCounts.push_back(contacts);
      }
      EXPECT_EQ(hashes[1], hashes[0]) << stepMethodName(method) << " " << contactModelName(model);
      EXPECT_EQ(hashes[2], hashes[0]) << stepMethodName(method) << " " << contactModelName(model);
      EXPECT_EQ(contactCounts[1], contactCounts[0]);
      EXPECT_GT(contactCounts[0], 1000u);  // the scene really is in contact
    }
  Scene scene = contactScene(ContactModel::Seed);
  scene.simulation.detectionThreads = 0;
  EXPECT_THROW(buildWorld(scene, CollisionShapeOptions{"", 0}), std::invalid_argument);
}

// Settings the XPBD step cannot run with are refused when the world is built, naming them.
TEST(World, XpbdRejectsInvalidSettings) {
  Scene scene = chainScene();
  scene.simulation.stepMethod = StepMethod::Xpbd;
  scene.simulation.xpbd.substeps = 0;
  try {
    buildWorld(scene);
    FAIL() << "substeps = 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("substeps"), std::string::npos) << e.what();
  }
  scene.simulation.xpbd.substeps = 4;
  scene.simulation.xpbd.contactCompliance = -1;
  EXPECT_THROW(buildWorld(scene), std::invalid_argument);
}

// Greedy colouring in creation order: a joint joins the first group in which none of its
// bodies is used. A chain 0-1, 1-2, 2-3, 3-4 splits into {0-1, 2-3} {1-2, 3-4}.
TEST(World, JointOrderIsTheSeedsGreedyColouring) {
  const std::vector<JointEnds> chain = {{0, 1, -1}, {1, 2, -1}, {2, 3, -1}, {3, 4, -1}};
  EXPECT_EQ(colouredJointOrder(chain, 5), (std::vector<int>{0, 2, 1, 3}));
  // Particles use their own slots: body 0 with particle 0 does not clash with body 1.
  const std::vector<JointEnds> mixed = {{0, -1, 0}, {1, 2, -1}, {0, -1, 1}, {2, -1, 0}};
  EXPECT_EQ(colouredJointOrder(mixed, 3), (std::vector<int>{0, 1, 2, 3}));
  const std::vector<JointEnds> clash = {{0, -1, 0}, {1, -1, 0}};
  EXPECT_EQ(colouredJointOrder(clash, 2), (std::vector<int>{0, 1}));
}

// The seed's ChainDemo: 10 boxes on ball joints, released horizontally. Gauss–Seidel with one
// iteration per substep solves each joint exactly but its neighbours' corrections move it
// again, so a chain keeps first-order residuals: at most one per-substep drift δ from each of
// the other joints, error ≤ N δ with δ = h_s² (|a| + (|ω|² + |α|) ℓ) the largest drift of any
// link (measured from the links' motion, ℓ = half a link). We assert that.
TEST(World, BallChainResidualIsBoundedByNeighbourDrift) {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.rigidBodies.push_back(test::boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 5, 0), 1, false));
  for (int i = 1; i <= 10; ++i) {
    s.rigidBodies.push_back(
        test::boxBody(i, Vector3(0.5, 0.1, 0.1), Vector3(0.5 * i - 0.25, 5, 0), 50));
    JointDesc j = test::makeJointDesc(JointType::Ball, i - 1, i);
    j.position = Vector3(0.5 * (i - 1), 5, 0);
    s.joints.push_back(j);
  }
  World world = buildWorld(s);
  const Real h = s.simulation.timeStepSize, hs = h / s.simulation.subSteps, lever = 0.25;
  const auto& b = world.bodies.rigid;
  Real maxDelta = 0, worst = 0;
  for (int n = 0; n < 600; ++n) {
    const auto v = b.velocity;
    const auto omega = b.angularVelocity;
    world.step();
    for (std::size_t i = 1; i < b.size(); ++i) {
      const Real a = (b.velocity[i] - v[i]).norm() / h;
      const Real alpha = (b.angularVelocity[i] - omega[i]).norm() / h;
      maxDelta = std::max(maxDelta, hs * hs * (a + (omega[i].squaredNorm() + alpha) * lever));
    }
    for (const Joint& joint : world.joints)
      worst = std::max(worst, jointError(joint, world.bodies).linear);
  }
  EXPECT_LE(worst, 10 * maxDelta);
  std::printf("  10-link ball chain: max joint error %.3e m (bound %.3e m)\n", double(worst),
              double(10 * maxDelta));
}

}  // namespace
}  // namespace pbd

namespace pbd {
namespace {

// Cosserat rods (constraints/cosserat_rod.h), PBD and XPBD variants, in both step methods: a
// clamped helix of 12 points allocates nothing in a step, two worlds stay bitwise identical,
// and the state hash sees the segment orientations.
TEST(CosseratRodWorld, StepAllocatesNothingAndHashesOrientations) {
  for (StepMethod stepMethod : {StepMethod::Seed, StepMethod::Xpbd})
    for (bool xpbd : {false, true}) {
      Scene scene;
      scene.simulation.stepMethod = stepMethod;
      LineModelDesc rod;
      rod.points = helixPoints(0.5, 0.3, 2, 11, Vector3::Zero());
      rod.staticParticles = {0};
      rod.staticSegments = {0};
      if (xpbd) {
        rod.radius = 0.01;
        rod.density = 1000;
        rod.youngsModulus = 1e6;
        rod.shearModulus = 4e5;
      }
      appendLineModel(scene, rod);
      World a = buildWorld(scene), b = buildWorld(scene);
      a.step();
      b.step();
      const long before = gAllocations.load();
      for (int n = 0; n < 200; ++n) {
        a.step();
        b.step();
      }
      EXPECT_EQ(gAllocations.load() - before, 0) << xpbd;
      EXPECT_EQ(a.stateHash(), b.stateHash()) << xpbd;
      // The rod moved (gravity sags its free end), and the hash sees a one-ulp change of an
      // orientation.
      EXPECT_GT((a.bodies.particles.position.back() - rod.points.back()).norm(), 1e-5) << xpbd;
      b.bodies.segments.rotation[3].x() =
          std::nextafter(b.bodies.segments.rotation[3].x(), Real(1e9));
      EXPECT_NE(a.stateHash(), b.stateHash()) << xpbd;
    }
}

// Stiff rods (joints/stiff_rod_tree_solver.h, joints/stretch_bending_twisting_joint.h): the
// direct tree solver preallocates every block, the per-joint constraint is fixed-size; neither
// step method allocates, for a chain and a Y-shaped tree.
TEST(StiffRodWorld, StepAllocatesNothing) {
  const test::RodMaterial material;
  for (StiffRodSolver solver : {StiffRodSolver::Direct, StiffRodSolver::Iterative})
    for (StepMethod method : {StepMethod::Seed, StepMethod::Xpbd}) {
      for (Scene scene : {test::cantileverScene(6, 1, material, solver, Real(1e-3), 3),
                          test::yTreeScene(3, Real(0.1), material, solver)}) {
        scene.simulation.stepMethod = method;
        World a = buildWorld(scene), b = buildWorld(scene);
        expectStepsAllocateNothingAndAgree(a, b, int(solver) * 10 + int(method));
        // It moved (sagged). Double-only for pbd.xpbd (allocations and determinism are checked
        // in float too; the test reports itself skipped there): with 20 substeps (h_s = 50 µs)
        // the bending rows' α̃ = 1/(E I L h_s²) = 5e7 stand against stretch rows of ~250, a
        // conditioning of ~2e5, which float's ε turns into a solve error of ~2 % per substep;
        // in float the XPBD Y tree flails (last segment at y = +0.29 m after 203 steps).
        // The sag is a property of the rod solver, so it is checked without contacts: the Y
        // tree's arms overlap at the branch and every segment touches its neighbours, ~2400
        // contacts that make the pbd.xpbd tree flail in double too (its last segment swings
        // between y = −0.26 and +0.34 m within 200 steps, before and after issue 24's
        // speculative-margin change: which sign step 201 lands on is chance).
        if (sizeof(Real) >= 8 || method == StepMethod::Seed) {
          Scene free = scene;
          for (RigidBodyDesc& body : free.rigidBodies)
            body.collision.type = CollisionObjectType::None;
          World sagging = buildWorld(free);
          for (int n = 0; n < 201; ++n)
            sagging.step();
          EXPECT_LT(sagging.bodies.rigid.position.back().y(), 0)
              << "solver " << int(solver) << ", method " << int(method) << ", "
              << scene.rigidBodies.size() << " segments";
        }
      }
    }
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision for the pbd.xpbd sag check (allocations and "
                    "hashes ran): kappa ~ 2e5 of the stiff-rod rows at h_s = 50 us times "
                    "float eps is ~2 % per substep and the Y tree flails";
}

}  // namespace
}  // namespace pbd
