// The metrics path end to end on a real run: cases/projectile.json in the PBD engine, compared
// with the semi-implicit Euler closed form of the projectile reference. PBD integrates with
// substeps h_s = timeStepSize / subSteps, so the reference built with integrationStep = h_s
// must agree to round-off, and the translational + gravitational energy must drift by exactly
// −½ m ‖g‖² h_s t (from x_k = x₀ + v₀ t + ½ g t (t + h_s), v_k = v₀ + g t).
#include <gtest/gtest.h>

#include "engines/selftest_engine.h"
#include "pbd/io/scene_loader.h"
#include "tests/validation/fixtures.h"
#include "validation/measure/metrics.h"
#include "validation/measure/references/reference.h"
#include "validation/run/case_spec.h"
#include "validation/run/simulation.h"

namespace pbdval {
namespace {

struct ProjectileRun {
  pbd::Scene scene;
  CaseSpec spec;
  std::vector<State> samples;
  double substep = 0;
};

ProjectileRun runProjectile() {
  ProjectileRun r;
  r.scene = pbd::loadScene(std::string(PBDVAL_SOURCE_DIR) + "/cases/projectile.json").scene;
  r.spec = parseCaseSpec(r.scene, testRegistry());
  r.substep = double(r.scene.simulation.timeStepSize) / r.scene.simulation.subSteps;
  const std::unique_ptr<Engine> engine = testRegistry().make("pbd");
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& s) { r.samples.push_back(s); };
  const RunOutcome outcome = runSimulation(
      *engine, r.scene, testRegistry().resolve("pbd"),
      {defaultDuration(r.scene, r.spec), r.spec.sampleInterval.value_or(0)}, callbacks);
  EXPECT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  return r;
}

TEST(EndToEnd, PbdProjectileMatchesTheDiscreteReferenceToRoundOff) {
  const ProjectileRun run = runProjectile();
  ASSERT_GT(run.samples.size(), 100u);
  std::vector<double> times;
  for (const State& s : run.samples)
    times.push_back(s.time);
  ReferenceSpec reference;
  reference.kind = ReferenceSpec::Kind::Analytic;
  reference.model = "projectile";
  reference.parametersJson = R"({"form": "semi_implicit_euler"})";
  const ReferenceTrajectory ref = buildAnalyticReference(run.scene, reference, times, run.substep);
  MetricInputs in;
  in.scene = &run.scene;
  in.spec = &run.spec;
  in.samples = &run.samples;
  in.reference = &ref;
  const MetricSet m = computeMetrics(in);
  // Round-off of k ≤ 1500 substeps on |x| ≤ 10 m: k² · 4ε · |x| ≈ 2e-8 m (the parity suite's
  // bound, tests/adapters/test_parity.cpp).
  EXPECT_LE(m.values.at(metric::kTrajectoryErrorMax), 1500.0 * 1500 * 4 * 2.2e-16 * 10);
  EXPECT_EQ(m.values.count(metric::kRotationErrorMax), 0u);  // the box spins: no orientation

  const double mass = double(run.scene.rigidBodies[0].massProperties.mass);
  const double g2 = double(run.scene.simulation.gravitation.squaredNorm());
  const EnergyTerms start = energyOf(run.scene, run.samples.front());
  for (const State& s : run.samples) {
    const EnergyTerms e = energyOf(run.scene, s);
    const double drift =
        (e.translational + e.gravitational) - (start.translational + start.gravitational);
    // Energies ~100 J after up to 1500 substeps: round-off ≲ 1e-9 J.
    EXPECT_NEAR(drift, -0.5 * mass * g2 * run.substep * s.time, 1e-8) << "t = " << s.time;
  }
}

}  // namespace
}  // namespace pbdval
