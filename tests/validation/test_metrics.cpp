// computeMetrics on synthetic runs whose metrics are known by hand: an energy ramp, momentum
// kicks, joints with set gaps, injected penetration depths, and offset references.
#include <gtest/gtest.h>

#include <algorithm>

#include "tests/validation/fixtures.h"
#include "validation/measure/metrics.h"
#include "validation/measure/numerics.h"

namespace pbdval {
namespace {

using pbd::JointType;
using pbd::test::boxBody;
using test::turn;

bool hasNote(const MetricSet& m, const std::string& text) {
  return std::any_of(m.notes.begin(), m.notes.end(),
                     [&](const std::string& note) { return note.find(text) != std::string::npos; });
}

MetricSet run(const pbd::Scene& scene, const CaseSpec& spec, const std::vector<State>& samples,
              const ReferenceTrajectory* reference = nullptr, PenetrationQuery query = {}) {
  MetricInputs in;
  in.scene = &scene;
  in.spec = &spec;
  in.samples = &samples;
  in.reference = reference;
  in.penetration = std::move(query);
  return computeMetrics(in);
}

/// Samples at t = 0, 0.1, …, 1.0 s of a 48 kg box (g = 0) whose kinetic energy grows from
/// E_ref = ½ · 48 · 2² = 96 J by 9.6 J/s: ΔE/E_ref = 0.1 t exactly.
struct EnergyRamp {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  std::vector<State> samples;
  EnergyRamp() {
    scene.rigidBodies.push_back(boxBody(1, Vector3(0.2, 0.4, 0.6), Vector3::Zero(), 1000));
    scene.rigidBodies[0].velocity = Vector3(2, 0, 0);
    for (int k = 0; k <= 10; ++k) {
      State s = initialState(scene);
      s.time = 0.1 * k;
      s.bodies[0].velocity = Vector3(std::sqrt(2 * (96 + 9.6 * s.time) / 48), 0, 0);
      samples.push_back(s);
    }
  }
};

TEST(EnergyMetrics, OfALinearRampAreItsSlopeMaximumAndFinalValue) {
  const EnergyRamp ramp;
  CaseSpec spec;
  spec.energyConserved = true;
  const MetricSet m = run(ramp.scene, spec, ramp.samples);
  // Energies are ~100 J computed from √ and squares: relative round-off ~1e-15.
  EXPECT_NEAR(m.values.at("energy_scale"), 96, 1e-12);
  EXPECT_NEAR(m.values.at(metric::kEnergyDriftMax), 0.1, 1e-13);
  EXPECT_NEAR(m.values.at(metric::kEnergyDriftFinal), 0.1, 1e-13);
  EXPECT_NEAR(m.values.at(metric::kEnergyDriftRate), 0.1, 1e-12);
  EXPECT_FALSE(hasNote(m, "energy: not declared conserved"));
}

TEST(EnergyMetrics, FinalDriftIsSignedAndTheScaleCanBeDeclared) {
  EnergyRamp ramp;
  std::reverse(ramp.samples.begin(), ramp.samples.end());  // energy now falls by 0.1 E_ref/s …
  for (std::size_t k = 0; k < ramp.samples.size(); ++k)
    ramp.samples[k].time = 0.1 * double(k);
  CaseSpec spec;
  spec.energyScale = 192.0;  // … relative to a declared scale twice the default
  const MetricSet m = run(ramp.scene, spec, ramp.samples);
  EXPECT_NEAR(m.values.at(metric::kEnergyDriftFinal), -0.05, 1e-13);
  EXPECT_NEAR(m.values.at(metric::kEnergyDriftMax), 0.05, 1e-13);
  EXPECT_NEAR(m.values.at(metric::kEnergyDriftRate), -0.05, 1e-12);
  EXPECT_TRUE(hasNote(m, "energy: not declared conserved"));
  EXPECT_TRUE(hasNote(m, "Validation.energyScale"));
}

TEST(EnergyMetrics, RateNeedsTwoSamples) {
  const EnergyRamp ramp;
  const MetricSet m = run(ramp.scene, CaseSpec{}, {ramp.samples.front()});
  EXPECT_EQ(m.values.at(metric::kEnergyDriftMax), 0.0);
  EXPECT_EQ(m.values.count(metric::kEnergyDriftRate), 0u);
  EXPECT_TRUE(hasNote(m, "energy_drift_rate"));
}

/// Two 48 kg boxes at (±1, 0, 0) moving at (0, ±1, 0) in zero gravity: P₀ = 0, L₀ = 96 ẑ,
/// E_ref = 48 J, P_scale = √(2 · 96 · 48) = 96, L_scale = √(2 · 99.2 · 48) (I_sys = 99.2).
struct TwoBoxes {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  std::vector<State> samples;
  TwoBoxes() {
    scene.rigidBodies.push_back(boxBody(1, Vector3(0.2, 0.4, 0.6), Vector3(1, 0, 0), 1000));
    scene.rigidBodies.push_back(boxBody(2, Vector3(0.2, 0.4, 0.6), Vector3(-1, 0, 0), 1000));
    scene.rigidBodies[0].velocity = Vector3(0, 1, 0);
    scene.rigidBodies[1].velocity = Vector3(0, -1, 0);
    State s = initialState(scene);
    samples.push_back(s);
    s.time = 0.1;
    s.bodies[0].velocity = Vector3(0.5, 1, 0);  // ΔP = (24, 0, 0); L about c unchanged
    samples.push_back(s);
    s.time = 0.2;
    s.bodies[0].velocity = Vector3(0, 1, 0);
    s.bodies[0].angularVelocity = Vector3(0, 0, 2);  // ΔL = I_z · 2 = 1.6 ẑ
    samples.push_back(s);
  }
};

TEST(MomentumMetrics, AreTheLargestChangesOverTheirScales) {
  const TwoBoxes boxes;
  CaseSpec spec;
  spec.linearMomentumConserved = spec.angularMomentumConserved = true;
  const MetricSet m = run(boxes.scene, spec, boxes.samples);
  EXPECT_NEAR(m.values.at("momentum_linear_scale"), 96, 1e-12);
  EXPECT_NEAR(m.values.at(metric::kMomentumLinearDriftMax), 0.25, 1e-14);  // 24 / 96
  EXPECT_NEAR(m.values.at(metric::kMomentumAngularDriftMax), 1.6 / std::sqrt(2 * 99.2 * 48), 1e-14);
}

TEST(MomentumMetrics, AreAbsentUnlessDeclaredConserved) {
  const TwoBoxes boxes;
  const MetricSet m = run(boxes.scene, CaseSpec{}, boxes.samples);
  EXPECT_EQ(m.values.count(metric::kMomentumLinearDriftMax), 0u);
  EXPECT_EQ(m.values.count(metric::kMomentumAngularDriftMax), 0u);
  EXPECT_TRUE(hasNote(m, "linear momentum not declared conserved"));
  EXPECT_TRUE(hasNote(m, "angular momentum not declared conserved"));
}

/// A static box with a ball-jointed box (body 1) and a hinged box (body 2), plus a spring.
pbd::Scene jointScene() {
  pbd::Scene scene = test::emptyScene();
  scene.rigidBodies.push_back(boxBody(0, Vector3(0.2, 0.2, 0.2), Vector3(0, 2, 0), 100, false));
  scene.rigidBodies.push_back(boxBody(1, Vector3(0.1, 0.4, 0.1), Vector3(0.5, 1.7, 0), 100));
  scene.rigidBodies.push_back(boxBody(2, Vector3(0.1, 0.4, 0.1), Vector3(-0.5, 1.7, 0), 100));
  pbd::JointDesc ball = pbd::test::makeJointDesc(JointType::Ball, 0, 1);
  ball.position = Vector3(0.5, 1.9, 0);
  pbd::JointDesc hinge = pbd::test::makeJointDesc(JointType::Hinge, 0, 2);
  hinge.position = Vector3(-0.5, 1.9, 0);
  hinge.axis = Vector3(0, 0, 1);
  pbd::JointDesc spring = pbd::test::makeJointDesc(JointType::RigidBodySpring, 1, 2);
  spring.position1 = Vector3(0.5, 1.7, 0);
  spring.position2 = Vector3(-0.5, 1.7, 0);
  spring.stiffness = 10;
  scene.joints = {ball, hinge, spring};
  return scene;
}

TEST(JointMetrics, AggregatePerTypeAndOverall) {
  const pbd::Scene scene = jointScene();
  std::vector<State> samples(3, initialState(scene));
  samples[1].time = 0.1;
  samples[1].bodies[1].position.x() += 0.003;  // ball gap 0.003
  samples[1].bodies[2].position.y() += 0.004;  // hinge gap 0.004
  samples[2].time = 0.2;
  test::moveBody(samples[2], 2, turn(Vector3::UnitX(), 0.02), Vector3(-0.5, 1.9, 0),
                 Vector3::Zero());  // hinge axis tilted by 0.02 rad about its anchor
  const MetricSet m = run(scene, CaseSpec{}, samples);
  // Exact by construction up to round-off of O(1) coordinates (~1e-16).
  const double tol = 1e-13;
  const JointErrorSummary& ball = m.jointErrorByType.at("ball");
  EXPECT_EQ(ball.joints, 1);
  EXPECT_NEAR(ball.linearMax, 0.003, tol);
  EXPECT_NEAR(ball.linearRms, 0.003 / std::sqrt(3.0), tol);
  EXPECT_FALSE(ball.hasAngular);
  const JointErrorSummary& hinge = m.jointErrorByType.at("hinge");
  EXPECT_NEAR(hinge.linearMax, 0.004, tol);
  EXPECT_NEAR(hinge.angularMax, 0.02, tol);
  EXPECT_NEAR(hinge.angularRms, 0.02 / std::sqrt(3.0), tol);
  EXPECT_EQ(m.jointErrorByType.count("rigid_body_spring"), 0u);
  EXPECT_NEAR(m.values.at(metric::kJointErrorLinearMax), 0.004, tol);
  // RMS over the 6 (sample, joint) pairs: √((0.003² + 0.004²)/6).
  EXPECT_NEAR(m.values.at(metric::kJointErrorLinearRms), std::sqrt(25e-6 / 6), tol);
  EXPECT_NEAR(m.values.at(metric::kJointErrorAngularMax), 0.02, tol);
  EXPECT_NEAR(m.values.at(metric::kJointErrorAngularRms), 0.02 / std::sqrt(3.0), tol);
}

TEST(JointMetrics, AreAbsentWithANoteWithoutConstraints) {
  pbd::Scene scene = jointScene();
  scene.joints.erase(scene.joints.begin(), scene.joints.begin() + 2);  // only the spring left
  const MetricSet m = run(scene, CaseSpec{}, {initialState(scene)});
  EXPECT_EQ(m.values.count(metric::kJointErrorLinearMax), 0u);
  EXPECT_TRUE(hasNote(m, "no constrained joints"));
}

TEST(JointMetrics, AngularIsAbsentForPointJointsOnly) {
  pbd::Scene scene = jointScene();
  scene.joints.erase(scene.joints.begin() + 1);  // ball and spring
  const MetricSet m = run(scene, CaseSpec{}, {initialState(scene)});
  EXPECT_EQ(m.values.count(metric::kJointErrorLinearMax), 1u);
  EXPECT_EQ(m.values.count(metric::kJointErrorAngularMax), 0u);
  EXPECT_TRUE(hasNote(m, "no joint with an angular error"));
}

TEST(JointMetrics, MotorTrackingSkipsTheFirstSample) {
  pbd::Scene scene = jointScene();
  scene.joints[1].type = JointType::TargetAngleMotorHinge;
  scene.joints[1].target.constant = 0.5;
  std::vector<State> samples(2, initialState(scene));
  samples[1].time = 0.1;
  test::moveBody(samples[1], 2, turn(Vector3::UnitZ(), 0.3), Vector3(-0.5, 1.9, 0),
                 Vector3::Zero());
  const MetricSet m = run(scene, CaseSpec{}, samples);
  // At t = 0 the error is 0.5 (the motor has not acted yet); at t = 0.1 it is 0.3 − 0.5.
  EXPECT_NEAR(m.values.at(metric::motorTrackingMax("angle")), 0.2, 1e-13);
  const JointErrorSummary& motor = m.jointErrorByType.at("target_angle_motor_hinge");
  EXPECT_EQ(motor.trackingQuantity, "angle");
  EXPECT_NEAR(motor.trackingRms, 0.2, 1e-13);
  EXPECT_NEAR(motor.angularMax, 0, 1e-13);  // turning about the hinge axis is free
}

TEST(PenetrationMetrics, AreTheMaximumAndTheMeanOverActiveContacts) {
  const EnergyRamp ramp;
  const PenetrationQuery query = [](const State& s) -> std::vector<double> {
    if (s.time < 0.05) return {};
    if (s.time < 0.15) return {0.001, 0.003};
    if (s.time < 0.25) return {0.002, 0.0, -1.0};  // touching / separated: not active
    return {};
  };
  const MetricSet m = run(ramp.scene, CaseSpec{}, ramp.samples, nullptr, query);
  EXPECT_DOUBLE_EQ(m.values.at(metric::kPenetrationMax), 0.003);
  EXPECT_NEAR(m.values.at(metric::kPenetrationMean), 0.002, 1e-18);  // (1 + 3 + 2) mm / 3
}

TEST(PenetrationMetrics, AreAbsentWithoutAnOracle) {
  const EnergyRamp ramp;
  const MetricSet m = run(ramp.scene, CaseSpec{}, ramp.samples);
  EXPECT_EQ(m.values.count(metric::kPenetrationMax), 0u);
  EXPECT_TRUE(hasNote(m, "no distance oracle"));
}

/// The run of TwoBoxes, and a reference where body 1 is offset by (0.03, 0.04, 0) and turned
/// 0.1 rad at the last sample; body 0 of the reference is far off but masked out.
ReferenceTrajectory offsetReference(const std::vector<State>& samples) {
  ReferenceTrajectory r;
  r.description = "test";
  r.samples = samples;
  r.bodies = {false, true};
  for (State& s : r.samples) {
    s.bodies[0].position += Vector3(100, 0, 0);
    s.bodies[1].position += Vector3(0.03, 0.04, 0);
  }
  r.samples.back().bodies[1].rotation = turn(Vector3(1, 1, 1), 0.1);
  return r;
}

TEST(TrajectoryMetrics, CompareMaskedBodiesSampleBySample) {
  const TwoBoxes boxes;
  const ReferenceTrajectory reference = offsetReference(boxes.samples);
  const MetricSet m = run(boxes.scene, CaseSpec{}, boxes.samples, &reference);
  EXPECT_NEAR(m.values.at(metric::kTrajectoryErrorMax), 0.05, 1e-15);
  EXPECT_NEAR(m.values.at(metric::kTrajectoryErrorRms), 0.05, 1e-15);
  EXPECT_NEAR(m.values.at(metric::kRotationErrorMax), 0.1, 1e-14);
}

TEST(TrajectoryMetrics, RotationIsAbsentWhenTheReferenceHasNone) {
  const TwoBoxes boxes;
  ReferenceTrajectory reference = offsetReference(boxes.samples);
  reference.hasRotation = false;
  reference.samples.pop_back();  // covers 2 of 3 samples
  const MetricSet m = run(boxes.scene, CaseSpec{}, boxes.samples, &reference);
  EXPECT_EQ(m.values.count(metric::kRotationErrorMax), 0u);
  EXPECT_TRUE(hasNote(m, "gives no orientations"));
  EXPECT_TRUE(hasNote(m, "covers only the first 2 of 3 samples"));
}

TEST(TrajectoryMetrics, RejectMisalignedTimesAndAcceptResampledReferences) {
  const TwoBoxes boxes;
  ReferenceTrajectory reference = offsetReference(boxes.samples);
  reference.samples[1].time = 0.11;
  EXPECT_THROW(run(boxes.scene, CaseSpec{}, boxes.samples, &reference), std::invalid_argument);
  // A reference sampled twice as often (interpolated midpoints added) and resampled back.
  ReferenceTrajectory fine = offsetReference(boxes.samples);
  fine.samples.insert(fine.samples.begin() + 1,
                      interpolateState(fine.samples[0], fine.samples[1], 0.5, 0.05));
  const ReferenceTrajectory aligned = resampleReference(fine, {0.0, 0.1, 0.2});
  EXPECT_EQ(aligned.bodies, fine.bodies);
  const MetricSet m = run(boxes.scene, CaseSpec{}, boxes.samples, &aligned);
  EXPECT_NEAR(m.values.at(metric::kTrajectoryErrorMax), 0.05, 1e-15);
}

TEST(TrajectoryMetrics, EmptyMaskComparesEveryBody) {
  const TwoBoxes boxes;
  ReferenceTrajectory reference;
  reference.samples = boxes.samples;
  reference.samples[2].bodies[0].position += Vector3(0, 0, 0.2);
  const TrajectoryErrors e = trajectoryErrors(boxes.samples, reference);
  EXPECT_EQ(e.bodiesCompared, 2u);
  EXPECT_NEAR(e.positionMax, 0.2, 1e-15);
  EXPECT_NEAR(e.positionRms, 0.2 / std::sqrt(6.0), 1e-15);  // one of 6 (sample, body) pairs
}

TEST(ComputeMetrics, NotesMissingInputsAndRejectsForeignStates) {
  const EnergyRamp ramp;
  const MetricSet empty = run(ramp.scene, CaseSpec{}, {});
  EXPECT_TRUE(empty.values.empty());
  EXPECT_TRUE(hasNote(empty, "no samples"));
  const MetricSet m = run(ramp.scene, CaseSpec{}, ramp.samples);
  EXPECT_TRUE(hasNote(m, "no reference"));
  std::vector<State> foreign = ramp.samples;
  foreign[3].bodies[0].id = 99;
  EXPECT_THROW(run(ramp.scene, CaseSpec{}, foreign), std::invalid_argument);
  EXPECT_THROW(computeMetrics(MetricInputs{}), std::invalid_argument);
}

TEST(SummarizeDrift, GivesMaxAbsoluteSignedFinalAndSlope) {
  const DriftSummary d = summarizeDrift({0, 1, 2}, {0, -0.3, 0.1});
  EXPECT_EQ(d.max, 0.3);
  EXPECT_EQ(d.final, 0.1);
  EXPECT_NEAR(d.rate, 0.05, 1e-15);  // Σ(t−1)(y−ȳ) = (−1)(0.0667) + (1)(0.1667) = 0.1; / 2
}

}  // namespace
}  // namespace pbdval
