// The Cosserat rods' energy as the metrics measure it (validation/measure/deformation.h,
// mechanics.h): the XPBD stretch–shear and bend–twist energies ½ Cᵀ α⁻¹ C of a rod deformed by
// hand against their closed forms (computed here from the constraints' definitions:
// ½ EA ℓ ε², ½ κGA ℓ γ², (2 EI/ℓ̄) sin²(θ/2), (2 GJ/ℓ̄) sin²(φ/2)), a spinning segment's kinetic
// energy ½ I |ω|² with I = 1/(4 w_q), and a run of an XPBD cantilever released at rest, whose
// energy is conserved up to XPBD's dissipation once the rod's terms are measured.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "engines/selftest_engine.h"
#include "tests/validation/fixtures.h"
#include "validation/io/trajectory.h"
#include "validation/measure/deformation.h"
#include "validation/measure/mechanics.h"
#include "validation/measure/metrics.h"
#include "validation/run/simulation.h"

namespace pbdval {
namespace {

using test::kPi;

// A straight rod of two segments of ℓ = 0.5 m along +x, r = 2 cm, E = 2 MPa, G = 0.8 MPa,
// κ = 0.9, no gravity; its first particle is static.
constexpr double kLength = 0.5, kRadius = 0.02, kYoung = 2e6, kShear = 8e5, kKappa = 0.9;

pbd::Scene twoSegmentRod() {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  pbd::LineModelDesc rod;
  rod.points = {Vector3(0, 0, 0), Vector3(kLength, 0, 0), Vector3(2 * kLength, 0, 0)};
  rod.staticParticles = {0};
  rod.radius = kRadius;
  rod.youngsModulus = kYoung;
  rod.shearModulus = kShear;
  rod.shearFactor = kKappa;
  pbd::appendLineModel(scene, rod);
  return scene;
}

// The section's moduli by hand: A = πr², I = πr⁴/4, J = πr⁴/2.
const double kArea = kPi * kRadius * kRadius;
const double kEA = kYoung * kArea, kKappaGA = kKappa * kShear * kArea;
const double kEI = kYoung * kPi * std::pow(kRadius, 4) / 4;
const double kGJ = kShear * kPi * std::pow(kRadius, 4) / 2;

// The second segment of `state` turned by `turn` in its own frame (q₁ ← q₁ turn), its end point
// p₂ moved to p₁ + ℓ d₃(q₁) so that it carries no stretch or shear.
void turnSecondSegment(State& state, const Quaternion& turn) {
  Quaternion& q = state.segments[1].rotation;
  q = (q * turn).normalized();
  state.particles[2].position = state.particles[1].position + kLength * (q * Vector3::UnitZ());
}

Vector3 director(const State& state, std::size_t segment, int axis) {
  return state.segments[segment].rotation * Vector3::Unit(axis);
}

// Every energy below is a few dozen roundings of O(1) numbers on values ≥ 10⁻⁶ J: 10⁻¹² relative.
constexpr double kRoundOff = 1e-12;

TEST(RodEnergy, RestRodStoresNothing) {
  const pbd::Scene scene = twoSegmentRod();
  const ElasticEnergy elastic(scene);
  EXPECT_TRUE(elastic.hasXpbdRods());
  EXPECT_FALSE(elastic.hasPbdConstraints());
  // At rest C_ss = (p₁ − p₀)/ℓ − d₃ and Im(q̄₀q₁ − Ω₀) vanish to round-off (ε ≈ 2·10⁻¹⁶ each):
  // the energy is ≲ EA ℓ ε² ≈ 10⁻²⁹ J.
  EXPECT_LT(elastic.of(initialState(scene)), 1e-25);
}

TEST(RodEnergy, StretchIsHalfEALengthStrainSquared) {
  const pbd::Scene scene = twoSegmentRod();
  State state = initialState(scene);
  const double strain = 0.01;
  state.particles[2].position = Vector3((2 + strain) * kLength, 0, 0);  // the second segment only
  const double expected = 0.5 * kEA * kLength * strain * strain;
  EXPECT_NEAR(ElasticEnergy(scene).of(state), expected, kRoundOff * expected);
}

TEST(RodEnergy, ShearIsHalfKappaGALengthShearSquared) {
  const pbd::Scene scene = twoSegmentRod();
  for (int axis : {0, 1}) {  // along d₁ and along d₂
    State state = initialState(scene);
    const double shear = 0.02;
    state.particles[2].position =
        state.particles[1].position +
        kLength * (director(state, 1, 2) + shear * director(state, 1, axis));
    const double expected = 0.5 * kKappaGA * kLength * shear * shear;
    EXPECT_NEAR(ElasticEnergy(scene).of(state), expected, kRoundOff * expected) << axis;
  }
}

TEST(RodEnergy, BendAndTwistAreTwoModulusOverLengthSineSquared) {
  const pbd::Scene scene = twoSegmentRod();
  const double angle = 0.1;
  // ℓ̄ = ℓ; a turn by θ about d_i of the second segment gives q̄₀q₁ = Ω₀ (cos θ/2, sin θ/2 e_i),
  // Ω₀ = 1 for a straight rod, so C = sin(θ/2) e_i and ½ C² / α = (2K/ℓ̄) sin²(θ/2).
  for (int axis : {0, 1, 2}) {
    State state = initialState(scene);
    turnSecondSegment(state, test::turn(Vector3::Unit(axis), angle));
    const double modulus = axis == 2 ? kGJ : kEI;
    const double expected = 2 * modulus / kLength * std::pow(std::sin(angle / 2), 2);
    EXPECT_NEAR(ElasticEnergy(scene).of(state), expected, kRoundOff * expected) << axis;
    // The continuum ½ K κ² ℓ̄ with κ = θ/ℓ̄ is the small-angle limit: relative gap
    // 1 − sin²(θ/2)/(θ/2)² ≈ θ²/12 ≈ 8.3·10⁻⁴ at θ = 0.1.
    const double continuum = 0.5 * modulus * angle * angle / kLength;
    EXPECT_NEAR(expected / continuum, 1 - angle * angle / 12, 1e-6);  // next term θ⁴/360 ≈ 3·10⁻⁷
  }
}

TEST(RodEnergy, TermsAddAndDoNotDependOnTheQuaternionSignOrARigidMotion) {
  const pbd::Scene scene = twoSegmentRod();
  State state = initialState(scene);
  const double strain = 0.01, twist = 0.2;
  turnSecondSegment(state, test::turn(Vector3::UnitZ(), twist));  // d₃ unchanged
  state.particles[2].position = Vector3((2 + strain) * kLength, 0, 0);
  const double expected =
      0.5 * kEA * kLength * strain * strain + 2 * kGJ / kLength * std::pow(std::sin(twist / 2), 2);
  const ElasticEnergy elastic(scene);
  const double energy = elastic.of(state);
  EXPECT_NEAR(energy, expected, kRoundOff * expected);
  // q and −q are the same frame: every term is a product of two coefficients, bit for bit the
  // same (the trajectory files write w ≥ 0, the engine may hold w < 0).
  State flipped = state;
  for (SegmentState& s : flipped.segments)
    s.rotation.coeffs() = -s.rotation.coeffs();
  EXPECT_EQ(elastic.of(flipped), energy);
  // A rigid motion of everything (the rest frames are the scene's, the constraints measure
  // relative quantities): the same energy to round-off.
  const Quaternion r = test::turn(Vector3(1, 2, 3), 0.7);
  State moved = state;
  for (ParticleState& p : moved.particles)
    p.position = r * p.position + Vector3(1, -2, 3);
  for (SegmentState& s : moved.segments)
    s.rotation = r * s.rotation;
  EXPECT_NEAR(elastic.of(moved), energy, kRoundOff * energy);
  // Without the segments the rods' energy is not measured (0 here: no other constraints).
  State noSegments = state;
  noSegments.segments.clear();
  EXPECT_EQ(elastic.of(noSegments), 0.0);
  // Some but not all segments: an error naming them.
  noSegments.segments.resize(1);
  EXPECT_NE(test::errorOf([&] { elastic.of(noSegments); }).find("rod segments"), std::string::npos);
}

TEST(RodEnergy, SpinningSegmentHasHalfIOmegaSquared) {
  // With a density the quaternion's inertia is I = ½ m r², m = ρπr²ℓ the segment's mass
  // (LineModels.density); without, the seed's w_q = 1, I = ¼. A static segment carries none.
  for (bool withDensity : {true, false}) {
    pbd::Scene scene = twoSegmentRod();
    pbd::LineModelDesc rod = scene.lineModels[0];
    scene = test::emptyScene(Vector3::Zero());
    if (withDensity) rod.density = 1000;
    rod.staticSegments = {1};
    pbd::appendLineModel(scene, rod);
    State state = initialState(scene);
    const EnergyTerms still = energyOf(scene, state);
    EXPECT_EQ(still.rotational, 0.0);
    state.segments[0].angularVelocity = Vector3(0, 3, 4);  // |ω|² = 25
    state.segments[1].angularVelocity = Vector3(7, 0, 0);  // static: not counted
    const double mass = 1000 * kArea * kLength;
    const double inertia = withDensity ? 0.5 * mass * kRadius * kRadius : 0.25;
    const double expected = 0.5 * inertia * 25;
    const EnergyTerms e = energyOf(scene, state);
    EXPECT_NEAR(e.rotational, expected, kRoundOff * expected) << withDensity;
    EXPECT_EQ(e.translational, still.translational);
    EXPECT_NEAR(e.total() - still.total(), expected, kRoundOff * expected);
  }
}

// An XPBD cantilever (L = 1 m, 10 segments, r = 1 cm, ρ = 1000 kg/m³, E = 1 GPa, ν = 0.3)
// clamped at its first particle and segment, released straight and at rest under gravity: it
// swings down and oscillates about its sag. Without the rod's elastic and rotational terms the
// measured energy (kinetic + gravitational) falls by the bending energy the swing stores; with
// them, E(t) − E(0) is what the step dissipates.
struct CantileverRun {
  pbd::Scene scene;
  std::vector<State> samples;
};

CantileverRun runCantilever(const std::string& method, int iterations,
                            const std::map<std::string, std::string>& parameters = {}) {
  CantileverRun run;
  run.scene = test::emptyScene(Vector3(0, -9.81, 0));
  run.scene.simulation.timeStepSize = 0.001;
  run.scene.simulation.subSteps = 1;
  run.scene.simulation.maxIterations = iterations;
  pbd::LineModelDesc rod;
  for (int i = 0; i <= 10; ++i)
    rod.points.push_back(Vector3(0.1 * i, 0, 0));
  rod.radius = 0.01;
  rod.density = 1000;
  rod.youngsModulus = 1e9;
  rod.shearModulus = 1e9 / 2.6;
  rod.staticParticles = {0};
  rod.staticSegments = {0};
  pbd::appendLineModel(run.scene, rod);
  const std::unique_ptr<Engine> engine = testRegistry().make("pbd");
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& s) { run.samples.push_back(s); };
  const RunOutcome outcome = runSimulation(
      *engine, run.scene, testRegistry().resolve(method, parameters), {1.0, 0.005}, callbacks);
  EXPECT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  return run;
}

struct EnergyChanges {
  double upAfter = 0, downAfter = 0, finalAfter = 0;  ///< E − E(0) with the rod's terms, J
  double downBefore = 0, finalBefore = 0;             ///< without them (no segments), J
};

EnergyChanges energyChanges(const CantileverRun& run) {
  const ElasticEnergy elastic(run.scene);
  const double start = energyOf(run.scene, run.samples.front(), elastic).total();
  EnergyChanges c;
  for (const State& s : run.samples) {
    const double after = energyOf(run.scene, s, elastic).total() - start;
    State withoutSegments = s;  // what the metrics measured before: no segments read back
    withoutSegments.segments.clear();
    const double before = energyOf(run.scene, withoutSegments, elastic).total() - start;
    c.upAfter = std::max(c.upAfter, after);
    c.downAfter = std::min(c.downAfter, after);
    c.downBefore = std::min(c.downBefore, before);
    c.finalAfter = after;
    c.finalBefore = before;
  }
  return c;
}

// The seed step with the Gauss–Seidel converged (1000 iterations of one substep h = 1 ms: the
// seed's red–black order of the rod's constraints, even segments then odd, moves a correction along
// the rod more slowly per sweep than segment order, and 200 sweeps left a transient gain of 2e-3 J)
// is XPBD's implicit (backward) Euler step, which only dissipates. Euler–Bernoulli with the clamp
// at the midpoint of the clamped segment (L_eff = 0.95 m, tests/pbd/test_cosserat_rod.cpp):
//   static sag energy  ½ k δ² = q² L⁵/(40 EI) = 0.0234 J  (q = ρπr²g, I = πr⁴/4);
//   released at rest, the rod swings to twice the sag, storing 4 × that (0.094 J): what the
//   measure without the rod's terms misses at the bottom of a swing;
//   backward Euler multiplies the first mode's oscillation energy (½ k δ², about the sag) by
//   (1 + h²ω₁²)⁻¹ per step, ω₁² = 3.516² EI/(ρA L⁴): after N = 1000 steps E(1 s) − E(0) =
//   −q² L⁵/(40 EI) (1 − (1 + h²ω₁²)^−N) = −0.0074 J.
TEST(RodEnergy, ConvergedXpbdCantileverOnlyDissipates) {
  const CantileverRun run = runCantilever("pbd", 1000);
  ASSERT_EQ(run.samples.size(), 201u);
  const EnergyChanges c = energyChanges(run);
  const double q = 1000 * kPi * 1e-4 * 9.81, ei = 1e9 * kPi * 1e-8 / 4, length = 0.95;
  const double sagEnergy = q * q * std::pow(length, 5) / (40 * ei);
  const double omega2 = 3.516 * 3.516 * ei / (1000 * kPi * 1e-4 * std::pow(length, 4));
  const double dissipated = sagEnergy * (1 - std::pow(1 + 1e-6 * omega2, -1000));
  std::printf(
      "converged XPBD cantilever: E - E(0) without the rod's terms min %.4g J, final "
      "%.4g J; with them max %+.3g J, min %.4g J, final %.4g J (predicted %.4g J)\n",
      c.downBefore, c.finalBefore, c.upAfter, c.downAfter, c.finalAfter, -dissipated);
  // Before: the swing's bending energy is missing: at least 3 of the 4 × ½ k δ² (the first
  // half-swing's dissipation takes ≈ 6 % of the oscillation energy; measured −0.091 J).
  EXPECT_LT(c.downBefore, -3 * sagEnergy);
  // After: never above the start (backward Euler is dissipative; measured exactly 0, the
  // 1000-iteration Gauss–Seidel residual and round-off included) — 10⁻³ of what was missed.
  EXPECT_LE(c.upAfter, 1e-3 * -c.downBefore);
  // And it loses what backward Euler's damping of the first mode predicts, within 10 % (the
  // higher modes the release excites carry a few % of the energy and are damped faster;
  // measured −0.007363 J against −0.007386 J).
  EXPECT_NEAR(c.finalAfter, -dissipated, 0.1 * dissipated);
  EXPECT_NEAR(c.downAfter, c.finalAfter, 0.1 * dissipated);  // monotone: the minimum is the end
}

// The XPBD method (one position iteration per substep, pbd.xpbd) is not converged per substep:
// its rod is softer than the moduli say, so the energy measured with the moduli rises above the
// start while it bends (by +0.022 J of the 0.09 J swing with the default 20 substeps of 1 ms).
// The excess vanishes as the substeps shrink (Macklin et al. 2019, "small steps"): measured
// +3.6·10⁻⁴ J with 100 and +8.2·10⁻⁵ J with 200 substeps.
TEST(RodEnergy, XpbdMethodApproachesConservationWithSubsteps) {
  const EnergyChanges fine = energyChanges(runCantilever("pbd.xpbd", 1, {{"substeps", "100"}}));
  const EnergyChanges finer = energyChanges(runCantilever("pbd.xpbd", 1, {{"substeps", "200"}}));
  std::printf(
      "pbd.xpbd cantilever: E - E(0) without the rod's terms min %.4g J; with them max "
      "%+.3g J (100 substeps), %+.3g J (200 substeps), final %.4g J, %.4g J\n",
      fine.downBefore, fine.upAfter, finer.upAfter, fine.finalAfter, finer.finalAfter);
  EXPECT_LT(fine.downBefore, -0.07);  // ≥ 3 × ½ k δ² missing, as above
  // The excess is at most 1 % of the swing's energy with 100 substeps, and falls by at least
  // 3× when the substep halves (second order would be 4×; measured 4.4×).
  EXPECT_LT(fine.upAfter, 0.01 * -fine.downBefore);
  EXPECT_LT(finer.upAfter, fine.upAfter / 3);
  // Both end below the start (the substeps' damping).
  EXPECT_LT(fine.finalAfter, 0);
  EXPECT_LT(finer.finalAfter, 0);
}

// The segment files of `pbdval simulate --segments` (docs/cli.md#segments): CSV and NPY read back
// to the same doubles, quaternions written with w ≥ 0 (the same rotation), rows checked.
TEST(RodEnergy, SegmentFilesRoundTripBitForBit) {
  std::vector<State> samples(2);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    samples[k].time = 0.1 * double(k) + 0.1;  // 0.1, 0.2 (not exactly representable)
    samples[k].segments = {
        {test::turn(Vector3(1, 2, 3), 0.3 + double(k)), Vector3(1.0 / 3, -2e-17, 7)},
        {Quaternion(-0.5, 0.5, -0.5, 0.5), Vector3(0, 1e300, -1.0 / 7)}};  // w < 0
  }
  std::ostringstream csv, npy;
  writeSegmentCsvHeader(csv);
  for (const State& s : samples)
    writeSegmentCsvRows(csv, s);
  writeSegmentTrajectoryNpy(npy, samples);
  EXPECT_EQ(csv.str().substr(0, csv.str().find('\n')), "t,index,qw,qx,qy,qz,wx,wy,wz");
  for (const Trajectory& read : {parseSegmentTrajectoryCsv(csv.str(), "s.csv"),
                                 parseSegmentTrajectoryNpy(npy.str(), "s.npy")}) {
    ASSERT_EQ(read.samples.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(read.samples[k].time, samples[k].time);
      EXPECT_TRUE(read.samples[k].bodies.empty() && read.samples[k].particles.empty());
      ASSERT_EQ(read.samples[k].segments.size(), 2u);
      for (std::size_t i = 0; i < 2; ++i) {
        const Quaternion& q = samples[k].segments[i].rotation;
        const Quaternion expected = q.w() < 0 ? Quaternion(-q.coeffs()) : q;
        EXPECT_EQ(read.samples[k].segments[i].rotation.coeffs(), expected.coeffs());
        EXPECT_EQ(read.samples[k].segments[i].angularVelocity,
                  samples[k].segments[i].angularVelocity);
      }
    }
  }
  // A sample must list its segments from 0, in order; the message names the file and line.
  const std::string skipped = "t,index,qw,qx,qy,qz,wx,wy,wz\n0,1,1,0,0,0,0,0,0\n";
  try {
    parseSegmentTrajectoryCsv(skipped, "s.csv");
    ADD_FAILURE() << "a sample starting at segment 1 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("s.csv: line 2: segment 1, expected 0"), std::string::npos)
        << e.what();
  }
}

// A non-finite segment state is a divergence, named.
TEST(RodEnergy, NonFiniteSegmentIsADivergence) {
  State state;
  state.time = 0.5;
  state.segments.resize(3);
  EXPECT_EQ(divergenceReason(state), "");
  state.segments[2].angularVelocity.y() = std::nan("");
  EXPECT_EQ(divergenceReason(state), "non-finite state of rod segment 2 at t = 0.5 s");
}

}  // namespace
}  // namespace pbdval
