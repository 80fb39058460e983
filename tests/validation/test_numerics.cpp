// Rotation angles, the least-squares slope and resampling, against hand-computed values.
#include <gtest/gtest.h>

#include "tests/validation/fixtures.h"
#include "validation/measure/numerics.h"

namespace pbdval {
namespace {

using test::kPi;
using test::turn;

// Angles built from exact rotations come back to a few ulps of π; 1e-14 rad is ~50 ulps of 0.3.
constexpr double kAngleTolerance = 1e-14;

TEST(GeodesicAngle, IsTheAngleOfTheRelativeRotation) {
  const Quaternion a = turn(Vector3(1, 2, 3), 0.4);
  const Quaternion b = turn(Vector3(1, 2, 3), 0.4) * turn(Vector3(0, 1, 0), 0.3);
  EXPECT_NEAR(geodesicAngle(a, b), 0.3, kAngleTolerance);
  EXPECT_NEAR(geodesicAngle(b, a), 0.3, kAngleTolerance);
}

TEST(GeodesicAngle, TreatsQAndMinusQAlike) {
  const Quaternion q = turn(Vector3(0, 0, 1), 1.1);
  const Quaternion minusQ(-q.coeffs());
  EXPECT_NEAR(geodesicAngle(q, minusQ), 0.0, kAngleTolerance);
  EXPECT_NEAR(geodesicAngle(Quaternion::Identity(), minusQ), 1.1, kAngleTolerance);
}

TEST(GeodesicAngle, ReachesPiForAHalfTurnAndIsAccurateForTinyAngles) {
  EXPECT_NEAR(rotationAngle(turn(Vector3(1, 0, 0), kPi)), kPi, kAngleTolerance);
  // 2 acos(1 − ε) loses half the digits; the atan2 form keeps them: 1e-9 rad to 1e-22.
  EXPECT_NEAR(rotationAngle(turn(Vector3(0, 1, 0), 1e-9)), 1e-9, 1e-22);
}

TEST(GeodesicAngle, NormalisesItsInputs) {
  const Quaternion q = turn(Vector3(0, 0, 1), 0.5);
  const Quaternion scaled(Eigen::Vector4d(3 * q.coeffs()));
  EXPECT_NEAR(geodesicAngle(Quaternion::Identity(), scaled), 0.5, kAngleTolerance);
}

TEST(TwistAngle, IsTheSignedAngleAboutTheAxis) {
  const Vector3 axis(0, 0, 1);
  EXPECT_NEAR(twistAngle(turn(axis, 0.7), axis), 0.7, kAngleTolerance);
  EXPECT_NEAR(twistAngle(turn(axis, -0.7), axis), -0.7, kAngleTolerance);
  EXPECT_NEAR(twistAngle(Quaternion(-turn(axis, 0.7).coeffs()), axis), 0.7, kAngleTolerance);
  // 3 rad about −axis is −3 rad about +axis.
  EXPECT_NEAR(twistAngle(turn(-axis, 3.0), axis), -3.0, kAngleTolerance);
}

TEST(WrapAngle, MapsIntoMinusPiToPi) {
  EXPECT_NEAR(wrapAngle(3 * kPi / 2), -kPi / 2, kAngleTolerance);
  EXPECT_NEAR(wrapAngle(-3 * kPi / 2), kPi / 2, kAngleTolerance);
  EXPECT_NEAR(wrapAngle(0.25), 0.25, 0.0);
  EXPECT_NEAR(wrapAngle(-kPi), kPi, kAngleTolerance);  // (−π, π]
}

TEST(AngleBetween, IsTheAngleOfTwoDirections) {
  EXPECT_NEAR(angleBetween(Vector3(1, 0, 0), Vector3(1, 1, 0)), kPi / 4, kAngleTolerance);
  EXPECT_NEAR(angleBetween(Vector3(2, 0, 0), Vector3(-1, 0, 0)), kPi, kAngleTolerance);
}

TEST(LeastSquaresSlope, RecoversAnExactLine) {
  const std::vector<double> t{0, 0.5, 1.0, 1.5, 2.0};
  std::vector<double> y;
  for (const double ti : t)
    y.push_back(-0.25 + 3.5 * ti);
  // Sums of a handful of exact binary fractions: exact up to rounding of the final division.
  EXPECT_NEAR(leastSquaresSlope(t, y), 3.5, 1e-15);
}

TEST(LeastSquaresSlope, AveragesSymmetricNoise) {
  // y = 2t ± 1 alternating symmetric about the centre: Σ(t − t̄)·noise = 0 for these samples.
  const std::vector<double> t{0, 1, 2, 3};
  const std::vector<double> y{0 + 1, 2 - 1, 4 - 1, 6 + 1};
  // By hand: t̄ = 1.5, ȳ = 3.5; Σ(t−t̄)(y−ȳ) = (−1.5)(−2.5)+(−0.5)(−2.5)+(0.5)(−0.5)+(1.5)(3.5)
  // = 3.75 + 1.25 − 0.25 + 5.25 = 10; Σ(t−t̄)² = 5; slope 2.
  EXPECT_DOUBLE_EQ(leastSquaresSlope(t, y), 2.0);
}

TEST(LeastSquaresSlope, IsZeroWithoutTwoDistinctTimesAndRejectsMismatchedSizes) {
  EXPECT_EQ(leastSquaresSlope({1.0}, {5.0}), 0.0);
  EXPECT_EQ(leastSquaresSlope({1.0, 1.0}, {5.0, 7.0}), 0.0);
  EXPECT_EQ(leastSquaresSlope({}, {}), 0.0);
  EXPECT_THROW(leastSquaresSlope({1.0, 2.0}, {5.0}), std::invalid_argument);
}

State oneBodyState(double time, const Vector3& x, const Quaternion& q, const Vector3& v) {
  State s;
  s.time = time;
  BodyState b;
  b.id = 7;
  b.position = x;
  b.rotation = q;
  b.velocity = v;
  s.bodies.push_back(b);
  s.particles.push_back({x, v});
  return s;
}

// A cubic motion x(t) = c0 + c1 t + c2 t² + c3 t³ sampled with its exact velocities is
// reproduced exactly by the Hermite interpolation (round-off only: 1e-14 on O(1) values).
TEST(ResampleStates, PositionsAreExactForCubicMotion) {
  const Vector3 c0(1, -2, 0.5), c1(0.3, 2, -1), c2(-4, 1, 2), c3(7, -3, 1);
  auto x = [&](double t) { return Vector3(c0 + c1 * t + c2 * t * t + c3 * t * t * t); };
  auto v = [&](double t) { return Vector3(c1 + 2 * c2 * t + 3 * c3 * t * t); };
  const Vector3 axis(0, 0, 1);
  const std::vector<State> source{oneBodyState(0.0, x(0.0), turn(axis, 0.0), v(0.0)),
                                  oneBodyState(0.1, x(0.1), turn(axis, 1.0), v(0.1)),
                                  oneBodyState(0.3, x(0.3), turn(axis, 1.5), v(0.3))};
  const std::vector<State> out = resampleStates(source, {0.025, 0.1, 0.17, 0.29});
  ASSERT_EQ(out.size(), 4u);
  for (const State& s : out) {
    EXPECT_NEAR((s.bodies[0].position - x(s.time)).norm(), 0, 1e-14) << s.time;
    EXPECT_NEAR((s.bodies[0].velocity - v(s.time)).norm(), 0, 1e-13) << s.time;
    EXPECT_NEAR((s.particles[0].position - x(s.time)).norm(), 0, 1e-14) << s.time;
    EXPECT_EQ(s.bodies[0].id, 7);
  }
  EXPECT_EQ(out[0].time, 0.025);
  // An exact sample time returns the sample itself.
  EXPECT_EQ(out[1].bodies[0].position, source[1].bodies[0].position);
  EXPECT_EQ(out[1].bodies[0].rotation.coeffs(), source[1].bodies[0].rotation.coeffs());
}

/// A body spinning about z at 3 rad/s while its axis precesses: q(t) = R_x(0.7 sin t) R_z(3t).
Quaternion wobble(double t) {
  return turn(Vector3(1, 0, 0), 0.7 * std::sin(t)) * turn(Vector3(0, 0, 1), 3 * t);
}
/// Its world angular velocity, from q̇ q⁻¹ = ½ ω by a central difference of step 1e-6 (error
/// O(1e-12), far below what the test resolves).
Vector3 wobbleRate(double t) {
  const double e = 1e-6;
  const Quaternion dq = wobble(t + e) * wobble(t - e).conjugate();
  return 2 * std::atan2(dq.vec().norm(), dq.w()) / (2 * e) * dq.vec().normalized();
}

// Rotations: exact for a constant angular velocity; for a smooth rotation the error falls with
// the fourth power of the sample interval (halving it divides the error by 16; slerp would
// give 4).
TEST(ResampleStates, RotationsFollowTheAngularVelocityToFourthOrder) {
  const Vector3 w(0.3, -1.2, 2.0);
  auto spin = [&](double t) { return Quaternion(pbd::AngleAxis(w.norm() * t, w.normalized())); };
  State a = oneBodyState(0.0, Vector3::Zero(), spin(0.0), Vector3::Zero());
  State b = oneBodyState(0.4, Vector3::Zero(), spin(0.4), Vector3::Zero());
  a.bodies[0].angularVelocity = b.bodies[0].angularVelocity = w;
  for (double s : {0.1, 0.5, 0.9})
    EXPECT_LT(geodesicAngle(interpolateState(a, b, s, 0.4 * s).bodies[0].rotation, spin(0.4 * s)),
              1e-14);

  auto midpointError = [&](double dt) {
    State p = oneBodyState(1.0, Vector3::Zero(), wobble(1.0), Vector3::Zero());
    State q = oneBodyState(1.0 + dt, Vector3::Zero(), wobble(1.0 + dt), Vector3::Zero());
    p.bodies[0].angularVelocity = wobbleRate(1.0);
    q.bodies[0].angularVelocity = wobbleRate(1.0 + dt);
    return geodesicAngle(interpolateState(p, q, 0.5, 1.0 + dt / 2).bodies[0].rotation,
                         wobble(1.0 + dt / 2));
  };
  const double coarse = midpointError(0.1), fine = midpointError(0.05);
  // Ratio 16 for O(dt⁴); [12, 20] leaves room for the next term of the expansion at these steps.
  EXPECT_GT(coarse / fine, 12) << coarse << " " << fine;
  EXPECT_LT(coarse / fine, 20) << coarse << " " << fine;
}

TEST(ResampleStates, SlerpTakesTheShorterArc) {
  const Vector3 axis(1, 0, 0);
  const Quaternion end(-turn(axis, 0.4).coeffs());  // same orientation, other hemisphere
  const std::vector<State> source{
      oneBodyState(0.0, Vector3::Zero(), Quaternion::Identity(), Vector3::Zero()),
      oneBodyState(1.0, Vector3::Zero(), end, Vector3::Zero())};
  EXPECT_NEAR(rotationAngle(resampleStates(source, {0.5})[0].bodies[0].rotation), 0.2, 1e-14);
}

TEST(ResampleStates, RejectsTimesOutsideTheSourceButToleratesRounding) {
  const std::vector<State> source{
      oneBodyState(0.0, Vector3::Zero(), Quaternion::Identity(), Vector3::Zero()),
      oneBodyState(1.0, Vector3(1, 0, 0), Quaternion::Identity(), Vector3::Zero())};
  EXPECT_THROW(resampleStates(source, {1.1}), std::invalid_argument);
  EXPECT_THROW(resampleStates(source, {-0.1}), std::invalid_argument);
  EXPECT_THROW(resampleStates({}, {0.0}), std::invalid_argument);
  // 1 + 1e-12 is a rounding of 1 (slack 1e-9 relative): clamped to the last sample.
  EXPECT_EQ(resampleStates(source, {1.0 + 1e-12})[0].bodies[0].position.x(), 1.0);
}

}  // namespace
}  // namespace pbdval
