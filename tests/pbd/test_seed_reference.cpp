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
// δ = 10⁻⁸ m, each in its own direction (the single-precision rounding of a 0.1 m coordinate
// is 3.7·10⁻⁹ m, so δ bounds the input differences) and the distance between the two runs, D(t), is
// the growth of an input difference of δ up to time t: round-off growth in a regular scene,
// Lyapunov growth in a chaotic one. The tolerance at a sample is 10 D(t) (a margin for round-off
// injected at every step rather than once) plus 10⁻⁹ m (the round-off floor: ~10⁻¹⁶ relative per
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

#include "pbd/collision/seed_point_order.h"
#include "pbd/io/mesh_loader.h"
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

/// One row of a recording: its time, the body's scene id (or the particle's index) and the
/// recorded position.
struct RecordedRow {
  double t = 0;
  int id = 0;
  Vector3 position = Vector3::Zero();
};

/// A recording: the line `header`, then rows of `columns` numbers whose first five are t, the id
/// (or index), x, y, z.
std::vector<RecordedRow> readRows(const std::string& path, const std::string& header,
                                  std::size_t columns) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  std::getline(in, line);
  if (line != header) throw std::runtime_error(path + ": line 1: unexpected header");
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
    if (values.size() != columns)
      throw std::runtime_error(path + ": line " + std::to_string(lineNumber) + ": " +
                               std::to_string(columns) + " columns");
    rows.push_back(
        {values[0], int(values[1]), Vector3(Real(values[2]), Real(values[3]), Real(values[4]))});
  }
  return rows;
}

/// A body recording (NAME.csv, the CSV of `pbdval simulate`).
std::vector<RecordedRow> readRecording(const std::string& path) {
  return readRows(path, "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz", 15);
}

/// The distinct step counts of a recording's samples, up to time `until` (s).
std::vector<std::int64_t> recordedSteps(const std::vector<RecordedRow>& rows, double h,
                                        double until = HUGE_VAL) {
  std::vector<std::int64_t> steps;
  for (const RecordedRow& r : rows) {
    const std::int64_t s = std::llround(r.t / h);
    if (r.t <= until + 1e-9 && (steps.empty() || steps.back() != s)) steps.push_back(s);
  }
  return steps;
}

/// The twin's start offset of the k-th moved item (a body or a particle): δ in a direction of its
/// own, so that the twin also breaks the scene's symmetries (a stack of centred boxes, a vertical
/// drop), as round-off does in both programs.
Vector3 twinOffset(std::size_t k) {
  const double x = double(k) + 1;
  return Real(kPerturbation) *
         Vector3(Real(std::sin(2.4 * x)), Real(std::cos(1.7 * x)), Real(std::sin(0.9 * x + 1)))
             .normalized();
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
  double largestDeviation = 0;  ///< the largest deviation over the compared samples (m)
  double horizon = 0;           ///< last compared time (s)
  int comparedSamples = 0;
  double lastTime = 0;
};

/// Each recorded sample against `ours`, with the tolerance from the twin run's growth
/// (`perturbed`) up to the horizon.
Comparison compareWithTwin(const std::vector<RecordedRow>& rows, double h, const Positions& ours,
                           const Positions& perturbed) {
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
    c.largestDeviation = std::max(c.largestDeviation, deviation);
    if (deviation / tolerance > c.worstRatio) {
      c.worstRatio = deviation / tolerance;
      c.worstDeviation = deviation;
      c.worstTolerance = tolerance;
      c.worstTime = r.t;
    }
  }
  return c;
}

Comparison compare(const std::string& name) {
  const Scene scene = loadSeedScene(name);
  const std::vector<RecordedRow> rows = readRecording(kReferenceDir + "/" + name + ".csv");
  const double h = double(scene.simulation.timeStepSize);
  const std::vector<std::int64_t> steps = recordedSteps(rows, h);
  Scene twin = scene;
  for (std::size_t b = 0; b < twin.rigidBodies.size(); ++b)
    if (twin.rigidBodies[b].isDynamic) twin.rigidBodies[b].translation += twinOffset(b);
  return compareWithTwin(rows, h, run(scene, steps), run(twin, steps));
}

// --- Particle recordings (NAME.particles.csv: t,index,x,y,z,vx,vy,vz) --------------------------

/// A particle recording (NAME.particles.csv).
std::vector<RecordedRow> readParticleRecording(const std::string& path) {
  return readRows(path, "t,index,x,y,z,vx,vy,vz", 8);
}

/// Every particle's position (by index) at each of the given step counts.
Positions runParticles(const Scene& scene, const std::vector<std::int64_t>& steps) {
  World world = buildWorld(scene);
  Positions out;
  std::int64_t done = 0;
  for (std::int64_t target : steps) {
    while (done < target) {
      world.step();
      ++done;
    }
    const std::vector<Vector3>& positions = world.bodies.particles.position;
    for (std::size_t i = 0; i < positions.size(); ++i)
      out[target][int(i)] = positions[i];
  }
  return out;
}

/// The particle version of compare(): the twin moves every dynamic particle's start (and so its
/// rest shape, as the single-precision reading of a mesh does) by δ in its own direction.
Comparison compareParticles(const std::string& name) {
  const Scene scene = loadSeedScene(name);
  const std::vector<RecordedRow> rows =
      readParticleRecording(kReferenceDir + "/" + name + ".particles.csv");
  const double h = double(scene.simulation.timeStepSize);
  const std::vector<std::int64_t> steps = recordedSteps(rows, h);
  Scene twin = scene;
  for (std::size_t i = 0; i < twin.particles.size(); ++i)
    if (twin.particles[i].mass > 0) twin.particles[i].position += twinOffset(i);
  return compareWithTwin(rows, h, runParticles(scene, steps), runParticles(twin, steps));
}

class SeedReferenceParticles : public ::testing::TestWithParam<const char*> {};

TEST_P(SeedReferenceParticles, PbdMethodFollowsTheOriginalsParticles) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::string name = GetParam();
  const Comparison c = compareParticles(name);
  std::printf(
      "  %-42s worst %.3e m (tolerance %.3e m) at t = %.3f s; compared to t = %.3f of %.3f s\n",
      name.c_str(), c.worstDeviation, c.worstTolerance, c.worstTime, c.horizon, c.lastTime);
  EXPECT_GT(c.comparedSamples, 1) << "the scene is past its horizon from the start";
  EXPECT_LE(c.worstRatio, 1.0) << name << ": deviation " << c.worstDeviation
                               << " m at t = " << c.worstTime << " s exceeds " << c.worstTolerance
                               << " m";
}

/// The largest particle deviation from the recording over every sample of its first second, past
/// the twin horizon too (PBDVAL_SEED_TRACE prints every sample's).
double largestParticleDeviationOverFirstSecond(const std::string& name) {
  const Scene scene = loadSeedScene(name);
  const std::vector<RecordedRow> rows =
      readParticleRecording(kReferenceDir + "/" + name + ".particles.csv");
  const double h = double(scene.simulation.timeStepSize);
  const Positions ours = runParticles(scene, recordedSteps(rows, h, 1.0));
  const auto deviation = [&](const RecordedRow& r) {
    return double((ours.at(std::llround(r.t / h)).at(r.id) - r.position).norm());
  };
  double worst = 0;
  for (const RecordedRow& r : rows)
    if (r.t <= 1 + 1e-9) worst = std::max(worst, deviation(r));
  if (std::getenv("PBDVAL_SEED_TRACE"))
    for (const RecordedRow& r : rows)
      if (r.t <= 1 + 1e-9) std::printf("    t %.3f p %d dev %.3e\n", r.t, r.id, deviation(r));
  return worst;
}

// The target (issue 28): the FEM cloth and FEM tet scenes agree with the original to
// 1 µm over their first second. Their twin horizon is short (the seed's absolute FEM cut-off
// makes the step discontinuous: a 10⁻⁸ m nudge flips an element's skip decision), but the
// `pbd` method evaluates the same operations in the same order, so no decision flips between
// the two programs: every sample of the first second is compared, past the horizon too. The
// same holds for the dihedral bending scene (twin horizon 0.14 s: its seed's form, acos and a
// sign flip by orientation, is evaluated in the seed's operations; measured bit for bit).
TEST(SeedReferenceFem, ClothAndTetScenesAgreeWithTheOriginalToAMicrometreOverTheFirstSecond) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  for (const char* name : {"fem_cloth_10x10", "fem_tet_bar", "fem_tet_bar_xpbd",
                           "cloth_xpbd_isometric_10x10", "cloth_dihedral_10x10"}) {
    const double worst = largestParticleDeviationOverFirstSecond(name);
    std::printf("  %-20s largest difference over the first second %.3e m\n", name, worst);
    EXPECT_LE(worst, 1e-6) << name;
  }
}

// The fluid: the seed's FluidDemo breaking dam (240 particles, `formulation` "seed"; README.md).
// Its chaos horizon, measured in the original itself: its driver nudging every particle's start
// by 10⁻¹⁵ m (each in the direction of twinOffset), the twins stay within 6.4·10⁻⁷ m up to
// 0.09 s and part by 1.1·10⁻⁵ m at 0.10 s (a neighbour entering a list at one search and not at
// the other's is a discontinuity). Up to 0.09 s a change of the input at the level of round-off
// moves the original by less than 1 µm, so a program computing the same operations with other
// round-off stays within 1 µm of it there; the test asks that of every recorded particle at every
// sample up to 0.09 s. Past it, as for the FEM scenes (SeedReferenceFem), the `pbd` method
// evaluates the same operations in the same order (formulation "seed"), so no neighbour-list or
// clamp decision flips between the two programs: the whole second is compared to the same 1 µm
// (measured: 0, bit for bit).
TEST(SeedReferenceFluid, TheDamBreakFollowsTheOriginalToAMicrometreOverTheWholeSecond) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::string name = "fluid_dam_break_seed";
  constexpr double kOriginalTwinWindow = 0.09;  // s, see above
  Scene scene = loadSeedScene(name);
  ASSERT_EQ(scene.fluidModels.size(), 1u);
  ASSERT_EQ(scene.fluidModels[0].formulation, FluidFormulation::Seed);
  // The run leaves the key out: the seed's formulation is the `pbd` method's default.
  scene.fluidModels[0].formulation.reset();
  ASSERT_EQ(fluidFormulationFor(scene.fluidModels[0], scene.simulation), FluidFormulation::Seed);
  const std::vector<RecordedRow> rows =
      readParticleRecording(kReferenceDir + "/" + name + ".particles.csv");
  const double h = double(scene.simulation.timeStepSize);
  const Positions ours = runParticles(scene, recordedSteps(rows, h));
  double worstInWindow = 0, worstOverall = 0, firstAbove = -1;
  int compared = 0;
  for (const RecordedRow& r : rows) {
    const double deviation = double((ours.at(std::llround(r.t / h)).at(r.id) - r.position).norm());
    worstOverall = std::max(worstOverall, deviation);
    if (firstAbove < 0 && deviation > 1e-6) firstAbove = r.t;
    if (r.t <= kOriginalTwinWindow + 1e-9) {
      worstInWindow = std::max(worstInWindow, deviation);
      ++compared;
    }
  }
  std::printf(
      "  %s: largest difference %.3e m up to %.2f s (%d rows), %.3e m over %.2f s; "
      "first above 1 um at t = %.3f s\n",
      name.c_str(), worstInWindow, kOriginalTwinWindow, compared, worstOverall, rows.back().t,
      firstAbove);
  EXPECT_GT(compared, 50);
  EXPECT_LE(worstInWindow, 1e-6);
  EXPECT_LE(worstOverall, 1e-6);
}

// The particle scenes the `pbd` method reproduces (tests/data/seed_reference/README.md).
INSTANTIATE_TEST_SUITE_P(
    Recorded, SeedReferenceParticles,
    ::testing::Values("fem_cloth_10x10", "fem_tet_bar", "fem_tet_bar_xpbd", "cloth_on_sphere",
                      "cloth_collision_scene", "cloth_scene", "deformable_solid_collision_scene",
                      "armadillo_collision_scene", "cosserat_helix", "cloth_on_bunny",
                      "fluid_dam_break_seed", "cloth_dihedral_10x10", "tet_bar_shape_matching",
                      "cloth_distance_10x10", "cloth_xpbd_distance_10x10",
                      "cloth_xpbd_isometric_10x10", "tet_bar_distance_volume",
                      "tet_bar_xpbd_distance_volume", "tet_bar_strain", "cloth_strain_10x10"),
    [](const ::testing::TestParamInfo<const char*>& param) { return std::string(param.param); });

class SeedReference : public ::testing::TestWithParam<const char*> {};

TEST_P(SeedReference, PbdMethodFollowsTheOriginalsTrajectory) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::string name = GetParam();
  const Comparison c = compare(name);
  std::printf(
      "  %-42s worst %.3e m (tolerance %.3e m) at t = %.3f s; compared to t = %.3f of %.3f s\n",
      name.c_str(), c.worstDeviation, c.worstTolerance, c.worstTime, c.horizon, c.lastTime);
  EXPECT_GT(c.comparedSamples, 1) << "the scene is past its horizon from the start";
  EXPECT_LE(c.worstRatio, 1.0) << name << ": deviation " << c.worstDeviation
                               << " m at t = " << c.worstTime << " s exceeds " << c.worstTolerance
                               << " m";
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
                      "incline_stick_30deg", "incline_slide_30deg", "grid_torus_on_ground",
                      "spheres_in_hollow_box", "sphere_on_grid_torus",
                      "sphere_on_grid_torus_off_cell", "contact_stack_5", "stack_5_in_shell",
                      "damper_on_pendulum", "joint_target_velocity_motor_hinge",
                      "joint_target_angle_motor_hinge", "joint_target_position_motor_slider",
                      "joint_target_velocity_motor_slider", "position_motor_slider_on_pendulum",
                      "velocity_motor_slider_on_pendulum", "car_scene", "cloth_collision_scene",
                      "pile_scene", "stiff_rod_cantilever", "deformable_solid_collision_scene",
                      "wilberforce_spring", "cloth_on_bunny"),
    [](const ::testing::TestParamInfo<const char*>& param) { return std::string(param.param); });

// The motors' schedule: the seed's motors act on the set point f(t − 2h) during the step that
// ends at t (it sets the target after the step, from the time before the step), and repeat a
// sequence whose scene does not say `repeatSequence`; the `pbd` method does the same by default
// (jointModel seed) and acts on f(t), holding the last value, with jointModel corrected
// (docs/methods.md, "Joints"). The velocity motor hinge shows it in closed form: the motor is a
// hard velocity constraint, so the relative angular velocity at the end of a step equals the
// set point the step used. Its sequence is [t, ω] = (0, 0), (1, 2), (3, 2), (4, −1), linear in
// between.
double velocityMotorSetPoint(double t) {
  if (t <= 1) return 2 * t;
  if (t <= 3) return 2;
  if (t <= 4) return 2 - 3 * (t - 3);
  return -1;
}

TEST(SeedReferenceMotors, TheOriginalAndThePbdMethodLagTwoStepsAndTheCorrectedModelDoesNot) {
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
    while (std::getline(fields, field, ','))
      v.push_back(std::strtod(field.c_str(), nullptr));
    ASSERT_EQ(v.size(), 15u);
    recorded.emplace_back(v[0], v[14]);
  }
  std::vector<std::int64_t> steps;
  for (const auto& r : recorded)
    steps.push_back(std::llround(r.first / h));
  World world = buildWorld(scene);
  Scene correctedScene = scene;
  correctedScene.simulation.jointModel = JointModel::Corrected;
  World corrected = buildWorld(correctedScene);
  std::int64_t done = 0;
  for (std::size_t k = 1; k < recorded.size(); ++k) {
    while (done < steps[k]) {
      world.step();
      corrected.step();
      ++done;
    }
    const double t = recorded[k].first;
    // 10⁻⁹ rad/s: the hard velocity row closes to round-off (ω ~ 1 rad/s, five iterations).
    // After the sequence's end (t = 4) the original starts it again: the scene gives no
    // `repeatSequence`, and the seed's loader leaves that flag uninitialised
    // (docs/seed.md#motor-target-sequences), here true; the seed model does the same, the corrected
    // one holds the last value.
    if (t - 2 * h <= 4)
      EXPECT_NEAR(recorded[k].second, velocityMotorSetPoint(t - 2 * h), 1e-9)
          << "original, t = " << t;
    else
      EXPECT_NEAR(recorded[k].second, velocityMotorSetPoint(t - 4 - 2 * h), 1e-9)
          << "original, t = " << t;
    // The seed model: the original's value, to the same 10⁻⁹ rad/s.
    EXPECT_NEAR(double(world.sceneFrameState(1).angularVelocity.z()), recorded[k].second, 1e-9)
        << "pbd (jointModel seed), t = " << t;
    EXPECT_NEAR(double(corrected.sceneFrameState(1).angularVelocity.z()), velocityMotorSetPoint(t),
                1e-9)
        << "pbd (jointModel corrected), t = " << t;
  }
}

// --- The table of docs/methods.md -------------------------------------------------------------

/// A row of the table in docs/methods.md ("Fidelity to the seed: particle models, damper,
/// motors"): the recording's name (the first cell's first `name`), the window and the largest
/// difference as written.
struct DocumentedRow {
  std::string name, window, largest;
};

std::vector<DocumentedRow> documentedRows() {
  const std::string path = std::string(PBDVAL_SOURCE_DIR) + "/docs/methods.md";
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  const std::string section = "### Fidelity to the seed: particle models, damper, motors";
  while (std::getline(in, line) && line != section) {
  }
  std::vector<DocumentedRow> rows;
  bool inTable = false;
  while (std::getline(in, line)) {
    if (line.rfind("|", 0) != 0) {
      if (inTable) break;
      continue;
    }
    inTable = true;
    std::vector<std::string> cells;
    std::stringstream fields(line.substr(1));
    std::string cell;
    while (std::getline(fields, cell, '|')) {
      const std::size_t first = cell.find_first_not_of(' ');
      cells.push_back(first == std::string::npos ? std::string() : cell.substr(first));
    }
    if (cells.size() != 3 || cells[0].rfind("`", 0) != 0) continue;  // header, rule, prose rows
    rows.push_back({cells[0].substr(1, cells[0].find('`', 1) - 1), cells[1], cells[2]});
  }
  return rows;
}

/// "0 (bit for bit)", or "m·10⁻ⁿ m" (superscript digits) as a number.
double documentedNumber(const std::string& text) {
  if (text.rfind("0 ", 0) == 0) return 0;
  const std::size_t dot = text.find("\u00b710");
  if (dot == std::string::npos) throw std::runtime_error("not a documented number: " + text);
  const double mantissa = std::stod(text.substr(0, dot));
  static const char* const digits[] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                       "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
  std::size_t at = dot + std::string("\u00b710").size();
  int sign = 1, exponent = 0;
  if (text.compare(at, std::string("\u207b").size(), "\u207b") == 0) {
    sign = -1;
    at += std::string("\u207b").size();
  }
  for (bool more = true; more;) {
    more = false;
    for (int d = 0; d < 10; ++d)
      if (text.compare(at, std::string(digits[d]).size(), digits[d]) == 0) {
        exponent = 10 * exponent + d;
        at += std::string(digits[d]).size();
        more = true;
      }
  }
  return mantissa * std::pow(10.0, sign * exponent);
}

// The table's numbers are measurements of these recordings: each row's largest difference (over
// the first second, or up to the twin horizon / the whole recording, as its window says) is
// recomputed here and must be the documented number to its two significant digits (half a unit
// in the last digit), and the documented horizon the compared one.
TEST(SeedReferenceTable, TheDocumentedLargestDifferencesAreTheMeasuredOnes) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  const std::vector<DocumentedRow> rows = documentedRows();
  ASSERT_GE(rows.size(), 10u) << "the table in docs/methods.md";
  for (const DocumentedRow& row : rows) {
    const bool particles = std::ifstream(kReferenceDir + "/" + row.name + ".particles.csv").good();
    double measured = 0;
    if (row.window.rfind("first second", 0) == 0) {
      measured = largestParticleDeviationOverFirstSecond(row.name);
    } else {
      const Comparison c = particles ? compareParticles(row.name) : compare(row.name);
      measured = c.largestDeviation;
      const double window = std::stod(row.window);
      if (row.window.find("(twin horizon)") != std::string::npos) {
        EXPECT_NEAR(window, c.horizon, 1e-9) << row.name << ": the documented horizon";
      } else if (row.window.find("(whole") != std::string::npos) {
        EXPECT_NEAR(window, c.lastTime, 1e-9) << row.name << ": the whole recording";
        EXPECT_NEAR(c.horizon, c.lastTime, 1e-9) << row.name << ": compared to its end";
      } else {
        ADD_FAILURE() << row.name << ": the window \"" << row.window
                      << "\" says neither \"(twin horizon)\", \"(whole\" nor \"first second\"";
      }
    }
    const double documented = documentedNumber(row.largest);
    const double halfUnit =
        documented == 0 ? 0 : 0.05 * std::pow(10.0, std::floor(std::log10(documented)));
    std::printf("  %-38s measured %.2e m, documented %s\n", row.name.c_str(), measured,
                row.largest.c_str());
    EXPECT_LE(std::abs(measured - documented), halfUnit) << row.name << ": " << row.largest;
  }
}

// --- The seed's contact report order -----------------------------------------------------------

/// The seed's kd-tree index list dumped from the original (kd_order_*.txt: a comment line, then
/// the vertex indices in report order).
std::vector<int> recordedKdOrder(const std::string& file) {
  std::ifstream in(kReferenceDir + "/" + file);
  if (!in) throw std::runtime_error(file + ": cannot open");
  std::string line;
  std::getline(in, line);
  std::vector<int> order;
  int v = 0;
  while (in >> v)
    order.push_back(v);
  return order;
}

void expectSeedOrder(const std::string& model, Real scale, const Vector3& translation,
                     const Quaternion& rotation, const std::string& recorded) {
  TriangleMesh mesh = loadObj(std::string(PBDVAL_SOURCE_DIR) + "/cases/models/" + model);
  for (Vector3& v : mesh.vertices)
    v *= scale;
  const std::vector<int> rank =
      seedVertexReportRank(mesh, Vector3::Constant(scale), translation, rotation, Real(1000));
  const std::vector<int> seed = recordedKdOrder(recorded);
  ASSERT_EQ(seed.size(), rank.size());
  int mismatches = 0;
  for (std::size_t k = 0; k < seed.size(); ++k)
    if (rank[std::size_t(seed[k])] != int(k)) ++mismatches;
  EXPECT_EQ(mismatches, 0) << model << ": ranks differing from the original's list";
}

// Exact: the order is a permutation decided by comparisons of coordinates and by the
// round-off-determined principal frame; one differing bit reorders (sphere.obj's frame is
// arbitrary: its inertia is isotropic).
TEST(SeedReportOrder, ReproducesTheOriginalsKdTreeListForASphere) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the seed's order is computed in double";
  expectSeedOrder("sphere.obj", Real(0.1), Vector3(0, Real(1.1), 0), Quaternion::Identity(),
                  "kd_order_sphere.txt");
}

TEST(SeedReportOrder, ReproducesTheOriginalsKdTreeListForARotatedTorus) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the seed's order is computed in double";
  expectSeedOrder("torus.obj", Real(0.2), Vector3(0, Real(0.4), 0),
                  Quaternion(AngleAxis(Real(0.3), Vector3::UnitX())), "kd_order_torus.txt");
}

// The particles of a tet model report in the order of the seed's kd-tree over their starting
// world positions (the model's PointCloudBSH, built once when its collision object is added).
// Exact, as above: a permutation decided by comparisons of coordinates (the tet cube's grid has
// many equal ones, which std::sort's tie handling orders as it does in the seed).
TEST(SeedReportOrder, ReproducesTheOriginalsKdTreeListForATetModelsParticles) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the seed's order is computed in double";
  const Scene scene = loadSeedScene("deformable_solid_collision_scene");
  ASSERT_EQ(scene.tetModels.size(), 1u);
  const TetModelDesc& model = scene.tetModels[0];
  std::vector<Vector3> start;
  for (std::size_t i = 0; i < model.mesh.vertices.size(); ++i)
    start.push_back(scene.particles[std::size_t(model.firstParticle) + i].position);
  const std::vector<int> rank = seedPointReportRank(start);
  const std::vector<int> seed = recordedKdOrder("kd_order_tet_cube.txt");
  ASSERT_EQ(seed.size(), rank.size());
  int mismatches = 0;
  for (std::size_t k = 0; k < seed.size(); ++k)
    if (rank[std::size_t(seed[k])] != int(k)) ++mismatches;
  EXPECT_EQ(mismatches, 0) << "ranks differing from the original's list";
}

// --- The seed's characteristic failures, in the original and in the `pbd` method -------------

/// Centre of mass of body `id` at time t, from a recording.
Vector3 recordedPosition(const std::string& name, int id, double t) {
  for (const RecordedRow& r : readRecording(kReferenceDir + "/" + name + ".csv"))
    if (r.id == id && std::abs(r.t - t) < 1e-9) return r.position;
  throw std::runtime_error(name + ": no sample of body " + std::to_string(id) + " at " +
                           std::to_string(t));
}

Vector3 ourPosition(const std::string& name, int id, double t) {
  const Scene scene = loadSeedScene(name);
  const Positions p = run(scene, {std::llround(t / double(scene.simulation.timeStepSize))});
  return p.begin()->second.at(id);
}

TEST(SeedFailures, TheRestingBoxSinksBelowTheSurface) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  // A 0.2 m box (centre 0.1 above its bottom) on a ground whose top is y = 0, k_c = 1/s,
  // h = 5 ms: velocity-level contacts once per step hold it only where the penalty k_c |d|
  // balances gravity's g h (n+1)/(2n) per step, up to D = 29.4 mm inside the 10 mm shell —
  // below the surface. Exact contact would keep the bottom at or above 0; the seed's sink is
  // asserted as more than 5 mm below it, in the original and here.
  for (const Vector3& x : {recordedPosition("contact_resting_box", 1, 5.0),
                           ourPosition("contact_resting_box", 1, 5.0)})
    EXPECT_LT(double(x.y()) - 0.1, -5e-3);
}

TEST(SeedFailures, TheSphereReboundsHigherThanNewtonsLaw) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  // Newton's restitution with e = 0.8 rebounds to e² = 0.64 of the drop (1 m above the contact
  // height 0.1 m); the penalty kick and the Euler terms add < 0.001 (docs/contacts.md). The
  // seed's contact order adds energy: asserted as more than 0.05 above e², in both programs.
  const Scene scene = loadSeedScene("bounce");
  const double h = double(scene.simulation.timeStepSize);
  std::vector<std::int64_t> steps;
  for (std::int64_t k = 0; k <= std::llround(1.5 / h); ++k)
    steps.push_back(k);
  const Positions ours = run(scene, steps);
  double ourApex = -1, recordedApex = -1;
  bool ourBounced = false, recordedBounced = false;
  double previous = 2;
  for (std::int64_t k : steps) {
    const double y = double(ours.at(k).at(1).y());
    if (y > previous && y < 0.2) ourBounced = true;
    if (ourBounced) ourApex = std::max(ourApex, y);
    previous = y;
  }
  previous = 2;
  for (const RecordedRow& r : readRecording(kReferenceDir + "/bounce.csv")) {
    const double y = double(r.position.y());
    if (y > previous && y < 0.2) recordedBounced = true;
    if (recordedBounced) recordedApex = std::max(recordedApex, y);
    previous = y;
  }
  ASSERT_TRUE(ourBounced && recordedBounced);
  EXPECT_GT(ourApex - 0.1, 0.64 + 0.05);
  EXPECT_GT(recordedApex - 0.1, 0.64 + 0.05);
}

TEST(SeedFailures, TheBoxBelowItsFrictionAngleCreeps) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the recordings are double precision";
  // 30° incline, μ = 0.35 + 0.35 (friction angle 35°): Coulomb friction holds the box. The
  // seed's friction acts on velocities after the substeps moved the box, so it creeps; asserted
  // as more than 10 mm in 5 s, in both programs.
  const Vector3 start = recordedPosition("incline_stick_30deg", 1, 0.0);
  for (const Vector3& x : {recordedPosition("incline_stick_30deg", 1, 5.0),
                           ourPosition("incline_stick_30deg", 1, 5.0)})
    EXPECT_GT(double((x - start).norm()), 10e-3);
}

}  // namespace
}  // namespace pbd
