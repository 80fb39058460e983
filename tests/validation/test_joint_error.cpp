// Joint error per type: known gaps and misalignments built by hand, and invariance under rigid
// motions of the whole pair. Both bodies start turned, so the capture in the scene frames is
// exercised.
#include <gtest/gtest.h>

#include "tests/validation/fixtures.h"
#include "validation/measure/joint_error.h"
#include "validation/measure/numerics.h"

namespace pbdval {
namespace {

using pbd::JointType;
using pbd::test::boxBody;
using test::kPi;
using test::moveBody;
using test::turn;

// Errors of a few rotations and translations of O(1) numbers: round-off ~1e-16 per operation.
constexpr double kExact = 1e-13;

const Vector3 kPoint(0.1, 1.8, 0.05);
const Vector3 kAxis = Vector3(1, 0.5, 0.2).normalized();
// Perpendicular to kAxis, and a third direction completing the frame.
const Vector3 kAcross = kAxis.cross(Vector3::UnitZ()).normalized();
const Vector3 kThird = kAxis.cross(kAcross);

/// Two dynamic boxes, both turned, joined by a joint of `type` at kPoint / along kAxis.
pbd::Scene pairScene(JointType type) {
  pbd::Scene scene = test::emptyScene();
  scene.rigidBodies.push_back(
      boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 100, true, turn(Vector3(1, 1, 0), 0.3)));
  scene.rigidBodies.push_back(boxBody(1, Vector3(0.1, 0.4, 0.1), Vector3(0.3, 1.5, 0.2), 100, true,
                                      turn(Vector3(0, 1, 1), -0.7)));
  pbd::JointDesc j = pbd::test::makeJointDesc(type, 0, 1);
  j.position = kPoint;
  j.position1 = Vector3(0.05, 1.95, 0);
  j.position2 = Vector3(0.3, 1.6, 0.2);
  j.axis = kAxis;
  j.axis1 = kAxis;
  j.axis2 = kAcross;
  j.stiffness = 300;
  scene.joints.push_back(j);
  return scene;
}

pbd::Scene particleScene() {
  pbd::Scene scene = test::emptyScene();
  scene.rigidBodies.push_back(boxBody(1, Vector3(0.1, 0.6, 0.1), Vector3(0.2, 1.7, 0), 100, true,
                                      turn(Vector3::UnitZ(), 0.5)));
  scene.particles.push_back({Vector3(0, 2, 0), Vector3::Zero(), 0});
  pbd::JointDesc j = pbd::test::makeJointDesc(JointType::RigidBodyParticleBall, 0, -1);
  j.particle = 0;
  scene.joints.push_back(j);
  return scene;
}

JointMeasurement measure(const pbd::Scene& scene, const State& state) {
  return measureJoint(captureJointGeometry(scene, scene.joints.front()), state);
}

const JointType kAllConstraints[] = {JointType::Ball,
                                     JointType::BallOnLine,
                                     JointType::Hinge,
                                     JointType::Universal,
                                     JointType::Slider,
                                     JointType::Distance,
                                     JointType::Damper,
                                     JointType::TargetAngleMotorHinge,
                                     JointType::TargetVelocityMotorHinge,
                                     JointType::TargetPositionMotorSlider,
                                     JointType::TargetVelocityMotorSlider};

TEST(JointError, IsZeroAtTheStartAndUnderRigidMotionsOfThePair) {
  for (const JointType type : kAllConstraints) {
    SCOPED_TRACE(pbd::jointTypeName(type));
    const pbd::Scene scene = pairScene(type);
    State s = initialState(scene);
    const JointMeasurement start = measure(scene, s);
    EXPECT_NEAR(start.linear, 0, kExact);
    EXPECT_NEAR(start.angular.value_or(0), 0, kExact);
    const Quaternion r = turn(Vector3(0.3, -1, 0.4), 1.2);
    for (std::size_t i = 0; i < 2; ++i)
      moveBody(s, i, r, Vector3(1, 2, 3), Vector3(-0.5, 0.1, 2));
    const JointMeasurement moved = measure(scene, s);
    EXPECT_NEAR(moved.linear, 0, kExact);
    EXPECT_NEAR(moved.angular.value_or(0), 0, kExact);
    EXPECT_EQ(moved.angular.has_value(), hasAngularError(type));
  }
}

TEST(JointError, PointJointsReportTheAnchorGap) {
  for (const JointType type : {JointType::Ball, JointType::Hinge, JointType::Universal,
                               JointType::TargetAngleMotorHinge}) {
    SCOPED_TRACE(pbd::jointTypeName(type));
    const pbd::Scene scene = pairScene(type);
    State s = initialState(scene);
    s.bodies[1].position += Vector3(0.003, -0.004, 0);  // gap 0.005 m
    EXPECT_NEAR(measure(scene, s).linear, 0.005, kExact);
  }
}

TEST(JointError, HingeMeasuresTheAngleBetweenTheTwoAxisCopies) {
  const pbd::Scene scene = pairScene(JointType::Hinge);
  State s = initialState(scene);
  moveBody(s, 1, turn(kAxis, 0.9), kPoint, Vector3::Zero());  // the free rotation
  EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
  EXPECT_NEAR(*measure(scene, s).angular, 0, kExact);
  moveBody(s, 1, turn(kAcross, 0.02), kPoint, Vector3::Zero());  // tilt the axis by 0.02 rad
  EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
  EXPECT_NEAR(*measure(scene, s).angular, 0.02, kExact);
}

TEST(JointError, UniversalMeasuresTheDeviationFromPerpendicular) {
  const pbd::Scene scene = pairScene(JointType::Universal);
  State s = initialState(scene);
  // axis1 = kAxis in body 0, axis2 = kAcross in body 1. Turning body 1 about axis1 or about
  // axis2 keeps them perpendicular (the two free rotations).
  moveBody(s, 1, turn(kAxis, 0.8), kPoint, Vector3::Zero());
  EXPECT_NEAR(*measure(scene, s).angular, 0, kExact);
  s = initialState(scene);
  moveBody(s, 1, turn(kAcross, 0.8), kPoint, Vector3::Zero());
  EXPECT_NEAR(*measure(scene, s).angular, 0, kExact);
  // Turning about the third direction tilts axis2 towards axis1 by 0.03 rad.
  s = initialState(scene);
  moveBody(s, 1, turn(kThird, 0.03), kPoint, Vector3::Zero());
  EXPECT_NEAR(*measure(scene, s).angular, 0.03, kExact);
}

TEST(JointError, SliderMeasuresTheOffsetAcrossTheAxisAndTheRotationChange) {
  for (const JointType type :
       {JointType::Slider, JointType::Damper, JointType::TargetPositionMotorSlider,
        JointType::TargetVelocityMotorSlider}) {
    SCOPED_TRACE(pbd::jointTypeName(type));
    const pbd::Scene scene = pairScene(type);
    State s = initialState(scene);
    s.bodies[1].position += 0.1 * kAxis;  // the free translation
    EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
    EXPECT_NEAR(measure(scene, s).springExtension, 0.1, kExact);
    s.bodies[1].position += 0.02 * kAcross;
    EXPECT_NEAR(measure(scene, s).linear, 0.02, kExact);
    // A turn of body 1 about its own centre of mass: only the rotation change.
    s = initialState(scene);
    s.bodies[1].rotation = (turn(Vector3(1, -2, 0.5), 0.04) * s.bodies[1].rotation).normalized();
    EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
    EXPECT_NEAR(*measure(scene, s).angular, 0.04, kExact);
  }
}

TEST(JointError, SliderAxisFollowsBodyZero) {
  const pbd::Scene scene = pairScene(JointType::Slider);
  State s = initialState(scene);
  // Turn body 0 by 90° about kAcross around body 1's centre: the line now points along
  // ±kThird, so moving body 1 by 0.1 along the old axis is 0.1 across the new one. Body 1 is
  // also turned so that the relative rotation is unchanged.
  const Quaternion r = turn(kAcross, kPi / 2);
  const Vector3 centre = s.bodies[1].position;
  moveBody(s, 0, r, centre, Vector3::Zero());
  moveBody(s, 1, r, centre, Vector3::Zero());
  s.bodies[1].position += 0.1 * kAxis;
  EXPECT_NEAR(measure(scene, s).linear, 0.1, kExact);
  EXPECT_NEAR(*measure(scene, s).angular, 0, kExact);
}

TEST(JointError, BallOnLineMeasuresTheDistanceFromTheLine) {
  const pbd::Scene scene = pairScene(JointType::BallOnLine);
  State s = initialState(scene);
  moveBody(s, 1, turn(Vector3(1, 2, 3), 1.0), kPoint, 0.3 * kAxis);  // free: slide and turn
  EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
  s.bodies[1].position += 0.01 * kThird;
  EXPECT_NEAR(measure(scene, s).linear, 0.01, kExact);
}

TEST(JointError, DistanceJointMeasuresTheLengthChange) {
  const pbd::Scene scene = pairScene(JointType::Distance);
  const Vector3 along = (scene.joints[0].position2 - scene.joints[0].position1).normalized();
  const double length = (scene.joints[0].position2 - scene.joints[0].position1).norm();
  State s = initialState(scene);
  s.bodies[1].position += 0.01 * along;
  EXPECT_NEAR(measure(scene, s).linear, 0.01, kExact);
  s = initialState(scene);
  const Vector3 across = along.cross(Vector3::UnitZ()).normalized();
  s.bodies[1].position += 0.05 * across;  // ‖c₁ − c₀‖ = √(L² + 0.05²)
  EXPECT_NEAR(measure(scene, s).linear, std::sqrt(length * length + 0.0025) - length, kExact);
}

TEST(JointError, ParticleBallMeasuresTheAnchorToParticleGap) {
  const pbd::Scene scene = particleScene();
  State s = initialState(scene);
  EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
  moveBody(s, 0, turn(Vector3(0, 0, 1), 0.6), Vector3(0, 2, 0), Vector3::Zero());  // swing
  EXPECT_NEAR(measure(scene, s).linear, 0, kExact);
  s.particles[0].position += Vector3(0, 0, 0.007);
  EXPECT_NEAR(measure(scene, s).linear, 0.007, kExact);
  s.particles.clear();
  EXPECT_THROW(measure(scene, s), std::invalid_argument);
}

TEST(JointError, SpringsAreNotConstraints) {
  const pbd::Scene scene = pairScene(JointType::RigidBodySpring);
  EXPECT_FALSE(isConstraint(JointType::RigidBodySpring));
  State s = initialState(scene);
  s.bodies[1].position += Vector3(0.3, 0, 0);
  const JointGeometry g = captureJointGeometry(scene, scene.joints[0]);
  const JointMeasurement m = measureJoint(g, s);
  EXPECT_EQ(m.linear, 0.0);
  const double length = (scene.joints[0].position2 - scene.joints[0].position1).norm();
  const double stretched =
      (scene.joints[0].position2 + Vector3(0.3, 0, 0) - scene.joints[0].position1).norm();
  EXPECT_NEAR(m.springExtension, stretched - length, kExact);
  EXPECT_NEAR(springPotential(g, s), 150 * (stretched - length) * (stretched - length), 1e-12);
}

TEST(MotorTracking, TargetAngleHingeComparesTheTwistWithTheClampedSetPoint) {
  pbd::Scene scene = pairScene(JointType::TargetAngleMotorHinge);
  scene.joints[0].target.constant = 0.5;
  State s = initialState(scene);
  moveBody(s, 1, turn(kAxis, 0.3), kPoint, Vector3::Zero());
  const JointMeasurement m = measure(scene, s);
  EXPECT_NEAR(*m.tracking, 0.3 - 0.5, kExact);
  EXPECT_NEAR(*m.angular, 0, kExact);
  // A set point of 4 rad is clamped to π; at 3 rad the error is 3 − π.
  scene.joints[0].target.constant = 4.0;
  s = initialState(scene);
  moveBody(s, 1, turn(kAxis, 3.0), kPoint, Vector3::Zero());
  EXPECT_NEAR(*measure(scene, s).tracking, 3.0 - kPi, kExact);
  // Body 0 turning with body 1 is no motor motion.
  scene.joints[0].target.constant = 0;
  s = initialState(scene);
  for (std::size_t i = 0; i < 2; ++i)
    moveBody(s, i, turn(kAxis, 1.0), kPoint, Vector3::Zero());
  EXPECT_NEAR(*measure(scene, s).tracking, 0, kExact);
}

TEST(MotorTracking, FollowsATargetSequenceAtTheSampleTime) {
  pbd::Scene scene = pairScene(JointType::TargetAngleMotorHinge);
  scene.joints[0].target.times = {0, 1};
  scene.joints[0].target.values = {0, 0.8};
  State s = initialState(scene);
  s.time = 0.25;  // f(0.25) = 0.2
  EXPECT_NEAR(*measure(scene, s).tracking, -0.2, kExact);
}

TEST(MotorTracking, TargetVelocityHingeComparesTheAxialRelativeSpin) {
  pbd::Scene scene = pairScene(JointType::TargetVelocityMotorHinge);
  scene.joints[0].target.constant = 1.5;
  State s = initialState(scene);
  s.bodies[0].angularVelocity = 0.5 * kAxis + 0.3 * kAcross;
  s.bodies[1].angularVelocity = 2.5 * kAxis + 0.3 * kAcross;  // relative 2 rad/s about the axis
  EXPECT_NEAR(*measure(scene, s).tracking, 0.5, kExact);
}

TEST(MotorTracking, TargetPositionSliderComparesTheAxialOffset) {
  pbd::Scene scene = pairScene(JointType::TargetPositionMotorSlider);
  scene.joints[0].target.constant = 0.25;
  State s = initialState(scene);
  s.bodies[1].position += 0.1 * kAxis + 0.2 * kThird;
  EXPECT_NEAR(*measure(scene, s).tracking, -0.15, kExact);
}

/// Advances every body of `s` by dt with its own velocities (exact rigid motion).
State advanced(State s, double dt) {
  for (BodyState& b : s.bodies) {
    b.position += dt * b.velocity;
    if (b.angularVelocity.norm() > 0)
      b.rotation =
          (turn(b.angularVelocity, b.angularVelocity.norm() * dt) * b.rotation).normalized();
  }
  s.time += dt;
  return s;
}

TEST(MotorTracking, TargetVelocitySliderIsTheTimeDerivativeOfTheAxialOffset) {
  // Independent check: a central difference of the position motor's axial offset a₀·d while
  // both bodies translate and body 0 spins (the axis and the anchor move with it).
  pbd::Scene positionScene = pairScene(JointType::TargetPositionMotorSlider);
  pbd::Scene velocityScene = pairScene(JointType::TargetVelocityMotorSlider);
  State s = initialState(velocityScene);
  s.bodies[0].velocity = Vector3(0.2, -0.1, 0.3);
  s.bodies[0].angularVelocity = Vector3(0.4, 0.9, -0.5);
  s.bodies[1].velocity = Vector3(-0.3, 0.6, 0.1);
  s.bodies[1].position += 0.2 * kAxis + 0.05 * kThird;  // off the axis too
  const double h = 1e-5;
  const double offsetAfter = *measure(positionScene, advanced(s, h)).tracking;
  const double offsetBefore = *measure(positionScene, advanced(s, -h)).tracking;
  // Central difference: truncation ~h² |s‴| ~ 1e-10, cancellation ~1e-16/h ~ 1e-11.
  EXPECT_NEAR(*measure(velocityScene, s).tracking, (offsetAfter - offsetBefore) / (2 * h), 1e-9);
}

TEST(MotorTracking, OnlyMotorsHaveIt) {
  for (const JointType type : kAllConstraints) {
    const pbd::Scene scene = pairScene(type);
    EXPECT_EQ(measure(scene, initialState(scene)).tracking.has_value(),
              motorQuantity(type) != MotorQuantity::None)
        << pbd::jointTypeName(type);
  }
}

TEST(JointGeometry, RejectsJointsOnUnknownBodies) {
  pbd::Scene scene = pairScene(JointType::Ball);
  scene.joints[0].body2 = 5;
  EXPECT_THROW(captureJointGeometry(scene, scene.joints[0]), std::invalid_argument);
}

}  // namespace
}  // namespace pbdval
