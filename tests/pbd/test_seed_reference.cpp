// Differential test against PositionBasedDynamics 2.2.2 itself: every scene of
// tests/data/seed_reference/scenes was run by the original library (built beside the project,
// driven headless the way its SceneLoaderDemo builds a scene, single-threaded; the provenance of
// each recording is in tests/data/seed_reference/README.md) and its trajectory recorded in the
// CSV format of `pbdval simulate`. Here the `pbd` method with the `seed` contact model runs the
// same scene, and every recorded centre of mass must agree.
//
// Where the tolerance comes from. The two programs compute the same algorithm with different
// round-off (operation order; the seed reads OBJ coordinates in single precision, a relative
// change of 6·10⁻⁸). How much such a difference grows is a property of the scene, measured
// here: the scene is run a second time with every dynamic body's start moved by
// δ = 10⁻⁸ m (the single-precision rounding of a 0.1 m coordinate is 3.7·10⁻⁹ m, so δ bounds
// the input differences) and the distance between the two runs, D(t), is the growth of an
// input difference of δ up to time t: round-off growth in a regular scene, Lyapunov growth in a
// chaotic one. The tolerance at a sample is 10 D(t) (a margin for round-off injected at
// every step rather than once) plus 10⁻⁹ m (the round-off floor: ~10⁻¹⁶ relative per
// operation over ~10⁷ operations on a body in a run). Once D exceeds 1 mm the scene is past its
// predictability horizon — two starts 10 nm apart no longer share a trajectory — and later
// samples are not compared (printed with the horizon).
//
// A difference in the algorithm (a restitution, friction or ordering rule) does not shrink with
// δ: it shows as a deviation of millimetres within the horizon. The closing table
// (docs/contacts.md, "Fidelity to the seed") gives the scenes' numbers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "pbd/io/scene_loader.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const std::string kReferenceDir = std::string(PBDVAL_TEST_DATA_DIR) + "/seed_reference";

/// The start perturbation of the twin run (m); see the file comment.
constexpr double kPerturbation = 1e-8;
/// Margin on the measured growth: round-off enters at every step, not once.
constexpr double kGrowthMargin = 10;
/// Round-off floor (m).
constexpr double kRoundOffFloor = 1e-9;
/// Past this twin distance (m) the scene is past its predictability horizon.
constexpr double kHorizon = 1e-3;

struct RecordedRow {
  double t = 0;
  int id = 0;
  Vector3 position = Vector3::Zero();
};

std::vector<RecordedRow> readRecording(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  std::getline(in, line);
  if (line != "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz")
    throw std::runtime_error(path + ": line 1: unexpected header");
  std::vector<RecordedRow> rows;
  int lineNumber = 1;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.empty()) continue;
    std::vector<double> values;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      char* end = nullptr;
      values.push_back(std::strtod(field.c_str(), &end));
      if (end == field.c_str() || *end != '\0')
        throw std::runtime_error(path + ": line " + std::to_string(lineNumber) + ": bad number");
    }
    if (values.size() != 15)
      throw std::runtime_error(path + ": line " + std::to_string(lineNumber) + ": 15 columns");
    RecordedRow row;
    row.t = values[0];
    row.id = static_cast<int>(values[1]);
    row.position = Vector3(Real(values[2]), Real(values[3]), Real(values[4]));
    rows.push_back(row);
  }
  return rows;
}

Scene loadSeedScene(const std::string& name) {
  Scene scene = loadScene(kReferenceDir + "/scenes/" + name + ".json").scene;
  scene.simulation.contactModel = ContactModel::Seed;
  return scene;
}

/// Positions of every body (by scene id) at each of the given step counts.
using Positions = std::map<std::int64_t, std::map<int, Vector3>>;

Positions run(const Scene& scene, const std::vector<std::int64_t>& steps) {
  World world = buildWorld(scene);
  Positions out;
  std::int64_t done = 0;
  for (std::int64_t target : steps) {
    while (done < target) {
      world.step();
      ++done;
    }
    for (std::size_t b = 0; b < scene.rigidBodies.size(); ++b)
      out[target][scene.rigidBodies[b].id] = world.sceneFrameState(b).centerOfMass;
  }
  return out;
}

struct Comparison {
  double worstRatio = 0;      ///< max deviation / tolerance over compared samples
  double worstDeviation = 0;  ///< at that sample (m)
  double worstTolerance = 0;
  double worstTime = 0;
  double horizon = 0;         ///< last compared time (s)
  int comparedSamples = 0;
  double lastTime = 0;
};

Comparison compare(const std::string& name) {
  const Scene scene = loadSeedScene(name);
  const std::vector<RecordedRow> rows = readRecording(kReferenceDir + "/" + name + ".csv");
  const double h = double(scene.simulation.timeStepSize);
  std::vector<std::int64_t> steps;
  for (const RecordedRow& r : rows) {
    const std::int64_t s = std::llround(r.t / h);
    if (steps.empty() || steps.back() != s) steps.push_back(s);
  }
  Scene twin = scene;
  for (RigidBodyDesc& b : twin.rigidBodies)
    if (b.isDynamic) b.translation += Vector3::Constant(Real(kPerturbation / std::sqrt(3.0)));
  const Positions ours = run(scene, steps);
  const Positions perturbed = run(twin, steps);

  Comparison c;
  double growth = 0;  // max twin distance so far
  std::int64_t lastStep = -1;
  bool pastHorizon = false;
  for (const RecordedRow& r : rows) {
    const std::int64_t s = std::llround(r.t / h);
    c.lastTime = r.t;
    if (s != lastStep) {
      lastStep = s;
      for (const auto& [id, p] : ours.at(s))
        growth = std::max(growth, double((perturbed.at(s).at(id) - p).norm()));
      if (growth > kHorizon) pastHorizon = true;
      if (!pastHorizon) {
        c.horizon = r.t;
        ++c.comparedSamples;
      }
    }
    if (pastHorizon) continue;
    const double tolerance = kGrowthMargin * growth + kRoundOffFloor;
    const double deviation = double((ours.at(s).at(r.id) - r.position).norm());
    if (deviation / tolerance > c.worstRatio) {
      c.worstRatio = deviation / tolerance;
      c.worstDeviation = deviation;
      c.worstTolerance = tolerance;
      c.worstTime = r.t;
    }
  }
  return c;
}

class SeedReference : public ::testing::TestWithParam<const char*> {};

TEST_P(SeedReference, PbdMethodFollowsTheOriginalsTrajectory) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::string name = GetParam();
  const Comparison c = compare(name);
  std::printf("  %-42s worst %.3e m (tolerance %.3e m) at t = %.3f s; compared to t = %.3f of %.3f s\n",
              name.c_str(), c.worstDeviation, c.worstTolerance, c.worstTime, c.horizon, c.lastTime);
  EXPECT_GT(c.comparedSamples, 1) << "the scene is past its horizon from the start";
  EXPECT_LE(c.worstRatio, 1.0) << name << ": deviation " << c.worstDeviation << " m at t = "
                               << c.worstTime << " s exceeds " << c.worstTolerance << " m";
}

// The scenes the `pbd` method reproduces (tests/data/seed_reference/README.md).
INSTANTIATE_TEST_SUITE_P(
    Recorded, SeedReference,
    ::testing::Values("chain_10", "chain_100", "chain_mass_ratio", "chain_10_second_order",
                      "chain_10_1substep_4iterations", "double_pendulum", "joint_hinge",
                      "joint_hinge_h10ms_2substeps_3iterations", "joint_ball", "joint_ball_on_line",
                      "joint_universal", "joint_slider", "joint_distance", "joint_damper",
                      "joint_rigid_body_spring", "free_tumbling_box", "contact_resting_box",
                      "resting_box_stiff", "bounce", "bounce_second_order_10substeps",
                      "incline_stick_30deg", "incline_slide_30deg", "grid_torus_on_ground"),
    [](const ::testing::TestParamInfo<const char*>& param) { return std::string(param.param); });

// Recorded scenes the `pbd` method does not reproduce yet (docs/contacts.md, "Fidelity to the
// seed"): they run, print their deviation, and are skipped, so that the gap stays visible.
//   contact_stack_5: the stack drifts sideways differently from 0.05 s (4 mm at 0.2 s; the
//     scene's horizon is 0.6 s) — cause not found;
//   spheres_in_hollow_box: 1.3 µm after 1.5 s against a 0.17 µm tolerance;
//   sphere_on_grid_torus: the seed samples a Discregrid cubic-Lagrange grid over the mesh box
//     padded by 0.1, pbdval its own Catmull-Rom grid (docs/contacts.md, "Grid SDFs"): a
//     different SDF, not a different contact model.
class SeedReferenceNotReproduced : public ::testing::TestWithParam<const char*> {};

TEST_P(SeedReferenceNotReproduced, DeviationIsReported) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::string name = GetParam();
  const Comparison c = compare(name);
  std::printf("  %-42s worst %.3e m (tolerance %.3e m) at t = %.3f s; compared to t = %.3f of %.3f s\n",
              name.c_str(), c.worstDeviation, c.worstTolerance, c.worstTime, c.horizon, c.lastTime);
  GTEST_SKIP() << name << " is not reproduced yet (docs/contacts.md)";
}

INSTANTIATE_TEST_SUITE_P(
    Recorded, SeedReferenceNotReproduced,
    ::testing::Values("contact_stack_5", "spheres_in_hollow_box", "sphere_on_grid_torus"),
    [](const ::testing::TestParamInfo<const char*>& param) { return std::string(param.param); });

// The motor scenes differ by design (docs/methods.md, "Deliberate differences from the seed"):
// the seed's motors act on the set point f(t − 2h) during the step that ends at t (it sets the
// target after the step, from the time before the step), pbdval's on f(t). The velocity motor
// hinge shows it in closed form: the motor is a hard velocity constraint, so the relative
// angular velocity at the end of a step equals the set point the step used. Its sequence is
// [t, ω] = (0, 0), (1, 2), (3, 2), (4, −1), linear in between.
double velocityMotorSetPoint(double t) {
  if (t <= 1) return 2 * t;
  if (t <= 3) return 2;
  if (t <= 4) return 2 - 3 * (t - 3);
  return -1;
}

TEST(SeedReferenceMotors, TheOriginalLagsTwoStepsBehindTheSetPointAndPbdValDoesNot) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::string name = "joint_target_velocity_motor_hinge";
  const Scene scene = loadSeedScene(name);
  const double h = double(scene.simulation.timeStepSize);
  std::string path = kReferenceDir + "/" + name + ".csv";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::string line;
  std::getline(in, line);
  std::vector<std::pair<double, double>> recorded;  // t, ω_z of the swinging body
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) v.push_back(std::strtod(field.c_str(), nullptr));
    ASSERT_EQ(v.size(), 15u);
    recorded.emplace_back(v[0], v[14]);
  }
  std::vector<std::int64_t> steps;
  for (const auto& r : recorded) steps.push_back(std::llround(r.first / h));
  World world = buildWorld(scene);
  std::int64_t done = 0;
  for (std::size_t k = 1; k < recorded.size(); ++k) {
    while (done < steps[k]) {
      world.step();
      ++done;
    }
    const double t = recorded[k].first;
    // 10⁻⁹ rad/s: the hard velocity row closes to round-off (ω ~ 1 rad/s, five iterations).
    // After the sequence's end (t = 4) the original starts it again: the scene gives no
    // `repeatSequence`, and the seed's loader leaves that flag uninitialised (research/pbd.md
    // §4.2.5), here true. pbdval holds the last value.
    if (t - 2 * h <= 4)
      EXPECT_NEAR(recorded[k].second, velocityMotorSetPoint(t - 2 * h), 1e-9) << "original, t = " << t;
    else
      EXPECT_NEAR(recorded[k].second, velocityMotorSetPoint(t - 4 - 2 * h), 1e-9) << "original, t = " << t;
    EXPECT_NEAR(double(world.sceneFrameState(1).angularVelocity.z()), velocityMotorSetPoint(t), 1e-9)
        << "pbdval, t = " << t;
  }
}

}  // namespace
}  // namespace pbd
