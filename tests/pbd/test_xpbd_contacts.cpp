// The XPBD step (pbd.xpbd) with contacts, against closed forms: a resting box, a box on an
// incline below and above its friction angle (Coulomb), a bouncing sphere (apex ratio e²), a
// stack of 10 and a pyramid of 15 boxes. Numbers are printed for docs/methods.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/scene_fixtures.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

constexpr Real kGravity = Real(9.81);
constexpr Real kPi = Real(3.14159265358979323846);
const Vector3 kCube = Vector3::Constant(Real(0.2));

void useXpbd(Scene& s, int substeps) {
  s.simulation.stepMethod = StepMethod::Xpbd;
  s.simulation.xpbd.substeps = substeps;
}

/// A static ground box 4 × 1 × 4 m whose top face is y = 0, and the seed's defaults (h = 5 ms).
Scene groundScene() {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  s.rigidBodies.push_back(test::boxBody(0, Vector3(4, 1, 4), Vector3(0, Real(-0.5), 0), 1, false));
  useXpbd(s, 20);
  return s;
}

/// The lowest point of box `body` with full extents `extents` (its centre is its centre of mass).
Real lowestCorner(const World& world, std::size_t body, const Vector3& extents) {
  const SceneFrameState s = world.sceneFrameState(body);
  Real lowest = 1e30;
  for (int k = 0; k < 8; ++k) {
    const Vector3 corner(Real(k & 1) - Real(0.5), Real((k >> 1) & 1) - Real(0.5),
                         Real((k >> 2) & 1) - Real(0.5));
    lowest = std::min(lowest, (s.centerOfMass + s.rotation * corner.cwiseProduct(extents)).y());
  }
  return lowest;
}

// A 0.2 m box released at rest on the ground (e = 0.5, μ = 0.5). The targets: after 1 s
// penetration ≤ 0.1 mm and vertical speed ≤ 1 mm/s, and no lateral drift; we hold them from
// 1 s to 5 s, at every step. Lateral drift: the scene is symmetric about the box's vertical
// axis, so a sideways motion can only come from the order of the corners in the Gauss–Seidel
// sweep; it must stay at round-off level, far below the 1 µm asserted.
TEST(XpbdContacts, RestingBoxSettlesWithoutSinking) {
  Scene s = groundScene();
  s.rigidBodies.push_back(test::boxBody(1, kCube, Vector3(0, Real(0.1), 0), 1000));
  s.contactPairs.push_back(test::contactPair(0, 1, Real(0.5), Real(0.5)));
  World world = buildWorld(s);
  const auto& b = world.bodies.rigid;
  Real worstPenetration = 0, worstSpeed = 0, worstDrift = 0;
  for (int n = 1; n <= 1000; ++n) {
    world.step();
    if (n < 200) continue;  // settle for 1 s
    worstPenetration = std::max(worstPenetration, -lowestCorner(world, 1, kCube));
    worstSpeed = std::max(worstSpeed, std::abs(b.velocity[1].y()));
    worstDrift = std::max(worstDrift, std::hypot(b.position[1].x(), b.position[1].z()));
  }
  std::printf("  resting box 1..5 s: penetration %.3e m, |v_y| %.3e m/s, drift %.3e m\n",
              double(worstPenetration), double(worstSpeed), double(worstDrift));
  EXPECT_LE(worstPenetration, 1e-4);
  EXPECT_LE(worstSpeed, 1e-3);
  // Round-off: each of the 20 000 substeps may move the box by ε |x|, |x| ≤ 0.1 m.
  const Real roundOff = 20000 * kEpsilon * Real(0.1);
  EXPECT_LE(worstDrift, 1e-6 + roundOff);
  // It rests on the ground, not above it (the contact holds it, not a gap).
  EXPECT_GE(lowestCorner(world, 1, kCube), -1e-4);
  EXPECT_LE(lowestCorner(world, 1, kCube), 1e-4);
}

/// A static slab 4 × 0.2 × 4 tilted by `angle` about z, and a 0.2 m cube lying on it, at rest.
Scene inclineScene(Real angle, Real friction) {
  Scene s;
  s.simulation.timeStepSize = Real(0.005);
  const Quaternion tilt(AngleAxis(angle, Vector3::UnitZ()));
  s.rigidBodies.push_back(
      test::boxBody(0, Vector3(4, Real(0.2), 4), Vector3::Zero(), 1, false, tilt));
  const Vector3 normal = tilt * Vector3::UnitY();
  s.rigidBodies.push_back(test::boxBody(1, kCube, Real(0.2) * normal, 1000, true, tilt));
  s.contactPairs.push_back(test::contactPair(0, 1, friction, 0));
  useXpbd(s, 20);
  return s;
}

Vector3 downhill(Real angle) {
  return -(Quaternion(AngleAxis(angle, Vector3::UnitZ())) * Vector3::UnitX());
}

// 5° below the friction angle atan μ the box must stick: the target, ≤ 0.5 mm in 5 s.
TEST(XpbdContacts, BoxBelowFrictionAngleSticks) {
  const Real friction = Real(0.5);
  const Real angle = std::atan(friction) - Real(5) * kPi / 180;
  World world = buildWorld(inclineScene(angle, friction));
  const Vector3 start = world.bodies.rigid.position[1];
  for (int n = 0; n < 1000; ++n)
    world.step();
  const Real moved = (world.bodies.rigid.position[1] - start).norm();
  std::printf("  incline %.3f deg (5 deg below atan mu): moved %.3e m in 5 s\n",
              double(angle * 180 / kPi), double(moved));
  EXPECT_LE(moved, 5e-4);
}

// 5° above the friction angle the box slides with a = g (sin θ − μ cos θ). With XPBD the
// friction impulse per substep is μ λ_n / h_s, and λ_n sums to m g cos θ h_s² per substep over
// the contacts, so the discrete acceleration is the Coulomb one up to the rotational coupling
// of the corner contacts; the target is 1 %. Measured from the downhill velocity at
// 0.5 s and 1.5 s (a velocity difference: the start-up transient of the first substeps, when
// the corners settle into contact, does not enter).
TEST(XpbdContacts, BoxAboveFrictionAngleSlidesWithCoulombAcceleration) {
  // Double-only: XPBD takes velocities from positions, v = Δx / h_s, and the acceleration
  // enters each substep as a h_s² = 0.96 × (2.5e-4 s)² = 6e-8 m, half of float's ulp at the
  // box's ~1 m position (1.2e-7 m): float measures 1.215 m/s² against 0.956 (27 %).
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision: a h_s^2 = 6e-8 m per substep is half of float's "
                    "ulp 1.2e-7 m at the box's 1 m position";
  const Real friction = Real(0.5);
  const Real angle = std::atan(friction) + Real(5) * kPi / 180;
  World world = buildWorld(inclineScene(angle, friction));
  const Vector3 d = downhill(angle);
  Real v1 = 0;
  for (int n = 1; n <= 300; ++n) {
    world.step();
    if (n == 100) v1 = world.bodies.rigid.velocity[1].dot(d);
  }
  const Real v2 = world.bodies.rigid.velocity[1].dot(d);
  const Real measured = (v2 - v1) / Real(1.0);
  const Real coulomb = kGravity * (std::sin(angle) - friction * std::cos(angle));
  std::printf("  incline %.3f deg (5 deg above): a = %.6f m/s^2, Coulomb %.6f (%.3f %%)\n",
              double(angle * 180 / kPi), double(measured), double(coulomb),
              double(100 * (measured / coulomb - 1)));
  EXPECT_NEAR(measured, coulomb, Real(0.01) * coulomb);
  // It slides flat: a tumbling box would turn by order 1 rad; we allow 0.01 rad.
  const Real turned = world.bodies.rigid.rotation[1].angularDistance(
      Quaternion(AngleAxis(angle, Vector3::UnitZ())));
  std::printf("  turned by %.3e rad while sliding\n", double(turned));
  EXPECT_LE(turned, 0.01);
}

// A sphere (r = 0.1 m) dropped from 1 m onto the ground with e = 0.5, μ = 0: the apex heights
// (of the lowest point) fall by e² per bounce. Error budget for 1 %: free flight of the
// semi-implicit Euler substeps loses v h_s/2 of height per flight (0.1 % of the first apex
// at h_s = 0.25 ms), the apex sampled once per step is low by at most g (h/2)²/2 = 31 µm
// (0.2 % of the third apex, 1.6 cm).
TEST(XpbdContacts, BouncingSphereApexRatioIsRestitutionSquared) {
  // Double-only: in free flight each substep adds g h_s² = 6.1e-7 m to positions of up to 1 m,
  // where float's ulp is 1.2e-7 m, so each substep's gravity is rounded by up to 10 %; float
  // measures the first ratio 1.85 % low against the 1 % budget above.
  if (sizeof(Real) < 8)
    GTEST_SKIP() << "needs double precision: g h_s^2 = 6.1e-7 m per substep against float's ulp "
                    "1.2e-7 m at 1 m height rounds each substep's gravity by up to 10 %";
  const Real e = Real(0.5), radius = Real(0.1);
  Scene s = groundScene();
  s.rigidBodies.push_back(test::sphereBody(1, radius, Vector3(0, 1 + radius, 0), 1000));
  s.contactPairs.push_back(test::contactPair(0, 1, 0, e));
  World world = buildWorld(s);
  std::vector<Real> apex{1};
  Real previous = 1, before = 1;
  for (int n = 0; n < 800 && apex.size() < 4; ++n) {  // 4 s
    world.step();
    const Real height = world.bodies.rigid.position[1].y() - radius;
    if (previous > before && previous >= height && n > 1 && previous < apex.back() * 0.9)
      apex.push_back(previous);
    before = previous;
    previous = height;
  }
  ASSERT_EQ(apex.size(), 4u);
  for (std::size_t k = 1; k < apex.size(); ++k) {
    const Real ratio = apex[k] / apex[k - 1];
    std::printf("  bounce %zu: apex %.5f m, ratio %.5f (e^2 = %.5f, %.3f %%)\n", k, double(apex[k]),
                double(ratio), double(e * e), double(100 * (ratio / (e * e) - 1)));
    EXPECT_NEAR(ratio, e * e, Real(0.01) * e * e) << "bounce " << k;
  }
}

/// A column of `count` boxes 0.2 m high, 0.30 m wide at the bottom and 1 cm narrower per
/// level, each resting on the one below. Every bottom corner lies 5 mm inside the face beneath:
/// with equal aligned boxes the corners would sit exactly on the edges below, where the nearest
/// face of a box's SDF (and so the contact normal) is ambiguous between top and side.
Scene stackScene(int count) {
  Scene s = groundScene();
  for (int k = 0; k < count; ++k) {
    const Real width = Real(0.30) - Real(0.01) * Real(k);
    s.rigidBodies.push_back(test::boxBody(k + 1, Vector3(width, Real(0.2), width),
                                          Vector3(0, Real(0.1 + 0.2 * k), 0), 500));
  }
  return s;
}

/// `levels` rows of boxes 0.2 m wide and high on the ground, row k holding levels − k boxes
/// 0.22 m apart (a 2 cm gap), each row resting on the gaps of the one below (corners 9 cm
/// inside the faces beneath). Their depth (z) is 0.30 m in the bottom row and 2 cm less per
/// row, for the reason given at stackScene: no corner on an edge of the box above or below.
Scene pyramidScene(int levels) {
  Scene s = groundScene();
  int id = 1;
  for (int row = 0; row < levels; ++row) {
    const int count = levels - row;
    for (int i = 0; i < count; ++i) {
      const Real x = Real(0.22) * (Real(i) - Real(count - 1) / 2);
      s.rigidBodies.push_back(test::boxBody(id++, Vector3(0.2, 0.2, Real(0.30 - 0.02 * row)),
                                            Vector3(x, Real(0.1 + 0.2 * row), 0), 500));
    }
  }
  return s;
}

/// The largest displacement of any dynamic body from its start over `steps` steps.
Real largestDisplacement(World& world, int steps) {
  const std::vector<Vector3> start = world.bodies.rigid.position;
  Real worst = 0;
  for (int n = 0; n < steps; ++n) {
    world.step();
    for (std::size_t i = 1; i < start.size(); ++i)
      worst = std::max(worst, (world.bodies.rigid.position[i] - start[i]).norm());
  }
  return worst;
}

// Ten boxes stacked exactly in contact (stackScene; μ = 0.4, e = 0.36, the seed's combination
// of its defaults) for 10 s: the target, the top box moves ≤ 1 mm — which bounds the
// sinking of all ten contacts together and any sliding.
TEST(XpbdContacts, StackOfTenStands) {
  World world = buildWorld(stackScene(10));
  const Vector3 top = world.bodies.rigid.position[10];
  const Real worst = largestDisplacement(world, 2000);
  const Real topMoved = (world.bodies.rigid.position[10] - top).norm();
  std::printf("  stack of 10, 10 s: top box moved %.3e m (any box at any time: %.3e m)\n",
              double(topMoved), double(worst));
  EXPECT_LE(topMoved, 1e-3);
  EXPECT_LE(worst, 1e-3);
}

// A pyramid of 15 (rows of 5, 4, 3, 2, 1) stands for 10 s: no box moves more than 1 cm (5 % of
// its size; a collapsing pyramid moves boxes by their size). The issue sets no number; the
// measured creep is reported in docs/methods.md.
TEST(XpbdContacts, PyramidOfFifteenStands) {
  World world = buildWorld(pyramidScene(5));
  ASSERT_EQ(world.bodies.rigid.size(), 16u);
  const Real worst = largestDisplacement(world, 2000);
  std::printf("  pyramid of 15, 10 s: largest displacement %.3e m\n", double(worst));
  EXPECT_LE(worst, 1e-2);
}

// A sphere (r = 0.1 m) rolling without slipping at v = 2 m/s on the ground, with closed-form
// contacts. Its one contact is its support point (xpbd_contact.h, "Spheres"), so:
// - the normal velocity is the centre's, and the height holds: every substep the prediction
//   lowers the centre by g h_s² and the projection puts it back at y = r, so (y − y_old)/h_s is
//   round-off: a few ulps of coordinates below L = 2 m, divided by h_s; 64 ε L/h_s allows 64
//   (5e-10 m/s in double). A point fixed on the ball instead turns by ω h = 0.1 rad per step,
//   leaves the ground and lets the ball fall through the rest of the step (cm/s).
// - it rolls: the contact point's tangential velocity v + ω × r₀ stays at round-off;
// - the rolling energy E = ½ m v² + ½ I ω² falls only by the first-order angular velocity
//   update: ω ← 2 vec(Δq)/h_s with Δq = normalize(1, ½ h_s ω) returns ω/√(1 + θ²/4), θ = |ω| h_s,
//   so each substep takes θ²/4 of the rotational energy; friction then restores rolling keeping
//   the angular momentum about the contact point, m r v + I ω, which leaves the rolling ball
//   (I = 2/5 m r²) the fraction 1 − (2/7)(θ²/4) = 1 − θ²/14 of E per substep: after N substeps
//   ΔE/E = N θ²/14 (3.6e-3 here) to first order in it. The friction point's own slip, r (θ − sin θ)
//   per substep, and the rolling error of the rotation, r (θ − 2 atan(θ/2)), are O(θ³): 10 % of
//   the loss holds them and the second-order terms.
TEST(XpbdContacts, SphereRollingOnClosedFormContactKeepsHeightAndRollingEnergy) {
  const Real radius = Real(0.1), speed = 2, friction = Real(0.5);
  Scene s = groundScene();
  s.simulation.contactGeometry = ContactGeometry::Primitives;
  RigidBodyDesc ball = test::sphereBody(1, radius, Vector3(-1, radius, 0), 1000);
  ball.velocity = Vector3(speed, 0, 0);
  ball.angularVelocity = Vector3(0, 0, -speed / radius);  // v + ω × (−r e_y) = 0
  s.rigidBodies.push_back(ball);
  s.contactPairs.push_back(test::contactPair(0, 1, friction, 0));
  World world = buildWorld(s);
  const auto& b = world.bodies.rigid;
  const Real mass = 1 / b.inverseMass[1];
  const Real inertia = Real(0.4) * mass * radius * radius;
  const auto energy = [&] {
    return Real(0.5) * mass * b.velocity[1].squaredNorm() +
           Real(0.5) * inertia * b.angularVelocity[1].squaredNorm();
  };
  const Real initialEnergy = energy();
  const Real substep = s.simulation.timeStepSize / Real(s.simulation.xpbd.substeps);
  const Real roundOff = 64 * kEpsilon * 2 / substep;  // m/s; see above
  Real worstNormalSpeed = 0, worstHeight = 0, worstSlip = 0, expectedLoss = 0;
  const int steps = 100;  // 0.5 s, 1 m
  for (int n = 0; n < steps; ++n) {
    const Real theta = b.angularVelocity[1].norm() * substep;
    expectedLoss += s.simulation.xpbd.substeps * theta * theta / 14;
    world.step();
    worstNormalSpeed = std::max(worstNormalSpeed, std::abs(b.velocity[1].y()));
    worstHeight = std::max(worstHeight, std::abs(b.position[1].y() - radius));
    worstSlip = std::max(
        worstSlip, std::abs(b.velocity[1].x() + b.angularVelocity[1].z() * radius));  // v − ω r
  }
  const Real loss = 1 - energy() / initialEnergy;
  std::printf(
      "  rolling ball, 0.5 s: |v_n| %.3e m/s, |y - r| %.3e m, slip %.3e m/s, energy loss "
      "%.4e (N theta^2/14 = %.4e)\n",
      double(worstNormalSpeed), double(worstHeight), double(worstSlip), double(loss),
      double(expectedLoss));
  EXPECT_LE(worstNormalSpeed, roundOff);
  EXPECT_LE(worstHeight, roundOff * substep);
  // It rolls: the velocity pass's dynamic friction cancels the slip v θ²/8 the angular update
  // leaves each substep (6e-6 m/s) whole, its Coulomb budget μ g h_s (1.2e-3 m/s) being larger.
  EXPECT_LE(worstSlip, roundOff);
  EXPECT_NEAR(loss, expectedLoss, Real(0.1) * expectedLoss);
}

}  // namespace
}  // namespace pbd
