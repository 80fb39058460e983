// Issue 25, "fail closed, round two", the library side of what its fuzz targets found and
// guard: measuring a trajectory given from outside (validation/measure/measure_trajectory.h),
// merging shards whose results.json points anywhere (validation/run/shard_files.h, mergeShards),
// and ending the processes an external engine started outside its process group
// (validation/external/process_reaper.h).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "adapters/built_in_engines.h"
#include "pbd/io/scene_loader.h"
#include "validation/external/process_reaper.h"
#include "validation/measure/measure_trajectory.h"
#include "validation/run/case_spec.h"
#include "validation/run/run_execution.h"
#include "validation/run/shard_files.h"
#include "validation/run/sharding.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- measureTrajectory -------------------------------------------------------------------------

class MeasureTrajectory : public ::testing::Test {
 protected:
  void SetUp() override {
    // Two bodies with collision shapes (the FCL oracle measures them) and an analytic
    // reference (bouncing_ball), as pbdval.measure gets them.
    scene_ =
        pbd::loadScene(std::string(PBDVAL_SOURCE_DIR) + "/cases/contact_sphere_drop.json").scene;
    spec_ = parseCaseSpec(scene_, engines_);
  }
  /// `count` samples of the initial state at t = k·h.
  std::vector<State> restingSamples(std::size_t count) const {
    std::vector<State> samples(count);
    for (std::size_t k = 0; k < count; ++k) {
      samples[k].time = double(k) * double(scene_.simulation.timeStepSize);
      for (const pbd::RigidBodyDesc& body : scene_.rigidBodies) {
        BodyState b;
        b.id = body.id;
        b.position = body.translation;
        samples[k].bodies.push_back(b);
      }
    }
    return samples;
  }
  MeasuredTrajectory measure(const std::vector<State>& samples, double margin = 0,
                             ReferenceChoice choice = ReferenceChoice::CaseDefault,
                             const ReferenceTrajectory* given = nullptr) const {
    return measureTrajectory(scene_, spec_, samples, choice, given, margin, 0);
  }

  EngineRegistry engines_ = builtInEngines();
  pbd::Scene scene_;
  CaseSpec spec_;
};

TEST_F(MeasureTrajectory, AFiniteTrajectoryIsMeasuredAgainstTheCasesAnalyticReference) {
  // The sphere held at its start for n = 4 steps of h while the reference falls freely: the
  // error is the reference's drop, between the continuous ½ g (n h)² and semi-implicit Euler's
  // g h² n (n + 1) / 2 (the reference may use either form).
  const MeasuredTrajectory measured = measure(restingSamples(5));
  EXPECT_FALSE(measured.referenceDescription.empty());
  const double g = 9.81, h = double(scene_.simulation.timeStepSize), n = 4;
  ASSERT_TRUE(measured.metrics.values.count("trajectory_error_max"));
  const double error = measured.metrics.values.at("trajectory_error_max");
  EXPECT_GE(error, 0.5 * g * (n * h) * (n * h) * (1 - 1e-9));
  EXPECT_LE(error, g * h * h * n * (n + 1) / 2 * (1 + 1e-9));
}

TEST_F(MeasureTrajectory, AnEmptyTrajectoryIsAnArgumentErrorNamingTheTimes) {
  for (const ReferenceChoice choice :
       {ReferenceChoice::None, ReferenceChoice::CaseDefault, ReferenceChoice::Given}) {
    const ReferenceTrajectory given;
    try {
      measure({}, 0, choice, &given);
      ADD_FAILURE() << "an empty trajectory was measured";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("times: expected at least one sample"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST_F(MeasureTrajectory, NonFiniteOrDecreasingTimesAreRefusedBeforeTheReferenceIntegratesToThem) {
  // Before: a NaN or decreasing time reached the analytic reference, which integrates from t = 0
  // to each sample time in turn.
  for (const double bad : {kNaN, std::numeric_limits<double>::infinity(), -1.0}) {
    std::vector<State> samples = restingSamples(4);
    samples[2].time = bad;
    EXPECT_THROW(measure(samples), std::invalid_argument) << bad;
  }
  std::vector<State> samples = restingSamples(4);
  samples[3].time = samples[1].time;
  try {
    measure(samples);
    ADD_FAILURE() << "a decreasing time was measured";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("times[3]"), std::string::npos) << e.what();
  }
}

TEST_F(MeasureTrajectory, AMarginThatIsNotAFewMetresAtMostIsAnArgumentError) {
  // -1.8e308 inflated every box of the FCL oracle's broad phase to an overflow: a segfault
  // (tests/fuzz/corpus/measure/margin_minus_max_double_segfaulted_fcl).
  for (const double margin : {kNaN, -std::numeric_limits<double>::infinity(),
                              -std::numeric_limits<double>::max(), -1.5, 2.0}) {
    try {
      measure(restingSamples(3), margin);
      ADD_FAILURE() << "margin " << margin << " was used";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("contact_margin"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(measure(restingSamples(3), -kMaxContactMargin));
  EXPECT_NO_THROW(measure(restingSamples(3), 0.004));  // Bullet's default collision margin
}

TEST_F(MeasureTrajectory, ANonFiniteOrZeroQuaternionIsADivergenceNamingTheSample) {
  std::vector<State> samples = restingSamples(4);
  samples[2].bodies[1].rotation.coeffs().setConstant(kNaN);
  try {
    measure(samples);
    ADD_FAILURE() << "a NaN quaternion was measured";
  } catch (const EngineDivergence& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
  }
}

TEST_F(MeasureTrajectory, AQuaternionThatIsNoRotationIsADivergenceNamingTheSampleAndBody) {
  // A zero quaternion (what an overflowed angular velocity normalises to) was measured as a
  // rotation before; 1e-3 is the tolerance, far above any engine's round-off.
  for (const double scale : {0.0, 2.0, 1.0 + 2e-3}) {
    std::vector<State> samples = restingSamples(4);
    samples[3].bodies[1].rotation.coeffs() *= scale;
    try {
      measure(samples);
      ADD_FAILURE() << "a quaternion of norm " << scale << " was measured";
    } catch (const EngineDivergence& e) {
      EXPECT_NE(
          std::string(e.what()).find("sample 3: the rotation of body 1 is not a unit quaternion"),
          std::string::npos)
          << e.what();
    }
  }
  std::vector<State> samples = restingSamples(4);
  samples[3].bodies[1].rotation.coeffs() *= 1.0 + 1e-9;  // round-off is fine
  EXPECT_NO_THROW(measure(samples));
}

TEST_F(MeasureTrajectory, ASampleWithoutTheScenesBodiesIsAnArgumentError) {
  std::vector<State> samples = restingSamples(3);
  samples[1].bodies.pop_back();
  EXPECT_THROW(measure(samples, 0, ReferenceChoice::None), std::invalid_argument);
  samples = restingSamples(3);
  samples[1].bodies[0].id += 7;
  EXPECT_THROW(measure(samples, 0, ReferenceChoice::None), std::invalid_argument);
}

TEST_F(MeasureTrajectory, AGivenReferenceWithNaNTimesIsAnArgumentErrorNamingIt) {
  ReferenceTrajectory given;
  given.samples = restingSamples(3);
  given.samples[1].time = kNaN;
  try {
    measure(restingSamples(3), 0, ReferenceChoice::Given, &given);
    ADD_FAILURE() << "a reference with a NaN time was used";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("reference.times[1]"), std::string::npos) << e.what();
  }
  given.samples = restingSamples(3);
  EXPECT_NO_THROW(measure(restingSamples(3), 0, ReferenceChoice::Given, &given));
}

// ---- case specs --------------------------------------------------------------------------------

TEST(CaseSpecFields, ARequiredKeyThatIsMissingIsALocatedErrorNotAJsonException) {
  // A check without "metric" escaped as nlohmann's out_of_range and ended the process (the
  // case_spec fuzz target; tests/fuzz/corpus/case_spec/check_without_metric_...).
  const EngineRegistry engines = builtInEngines();
  const std::string head =
      R"({"Name": "c", "RigidBodies": [{"id": 1, "density": 1000, "collisionObjectType": 1,
          "collisionObjectScale": [0.1, 0.1, 0.1]}], "Validation": {"schema": 1, )";
  for (const auto& [validation, where] : std::vector<std::pair<std::string, std::string>>{
           {R"("checks": [{"max": 1}]})", "Validation.checks[0].metric: missing (required)"},
           {R"("reference": {"type": "analytic"}})",
            "Validation.reference.model: missing (required)"},
           {R"("reference": {"type": "engine"}})",
            "Validation.reference.method: missing (required)"}}) {
    const pbd::Scene scene = pbd::parseScene(head + validation + "}", "c.json").scene;
    try {
      (void)parseCaseSpec(scene, engines);
      ADD_FAILURE() << validation << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("c.json: " + where), std::string::npos) << e.what();
    }
  }
}

// ---- shards ------------------------------------------------------------------------------------

class ShardFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/pbdval-shard-files-XXXXXX";
    ASSERT_NE(::mkdtemp(pattern), nullptr);
    root_ = pattern;
    shard_.folder = (root_ / "shard").string();
    fs::create_directories(root_ / "shard/trajectories/c");
    fs::create_directories(root_ / "outside/trajectories/c");
    write(root_ / "shard/trajectories/c/pbd-pbd.csv", "inside\n");
    write(root_ / "outside/secret.csv", "secret\n");
    write(root_ / "outside/trajectories/c/ode-ode.quickstep.csv", "secret\n");
  }
  void TearDown() override { fs::remove_all(root_); }
  static void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }
  void addRun(const std::string& engine, const std::string& method, const std::string& path,
              RunStatus status = RunStatus::Ok) {
    RunRecord r;
    r.request.caseName = "c";
    r.request.engine = engine;
    r.request.method = method;
    r.request.trajectoryPath = path;
    r.status = status;
    shard_.results.runs.push_back(r);
  }
  std::string refusal() const {
    try {
      (void)verifiedShardFiles(shard_);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  }

  fs::path root_;
  ShardResults shard_;
};

TEST_F(ShardFiles, TheRunsTrajectoryIsTakenFromInsideTheShardWhateverFolderTheRunWroteTo) {
  // Written by `pbdval run --out /scratch/job-7/out` on another machine, copied here.
  addRun("pbd", "pbd", "/scratch/job-7/out/trajectories/c/pbd-pbd.csv");
  const std::vector<ShardFile> files = verifiedShardFiles(shard_);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].path, shard_.folder + "/trajectories/c/pbd-pbd.csv");
  EXPECT_EQ(files[0].relative, "trajectories/c/pbd-pbd.csv");
}

TEST_F(ShardFiles, PathsOfAnotherFormAreRefusedNeverFollowed) {
  for (const std::string& path :
       {(root_ / "outside/secret.csv").string(),
        shard_.folder + "/trajectories/c/../../../outside/secret.csv", std::string("/etc/passwd"),
        shard_.folder + "/trajectories/c/pbd-pbd.csv/..",
        shard_.folder + "/trajectories/other/pbd-pbd.csv",
        shard_.folder + "/trajectories/c/ode-ode.csv"}) {
    shard_.results.runs.clear();
    addRun("pbd", "pbd", path);
    EXPECT_NE(refusal().find("expected OUT/trajectories/c/pbd-pbd.csv or .npy"), std::string::npos)
        << path << ": " << refusal();
  }
}

TEST_F(ShardFiles, ASymbolicLinkOnTheWayIsRefused) {
  fs::create_symlink(root_ / "outside/secret.csv",
                     root_ / "shard/trajectories/c/ode-ode.quickstep.csv");
  addRun("ode", "ode.quickstep", "out/trajectories/c/ode-ode.quickstep.csv");
  EXPECT_NE(refusal().find("is a symbolic link"), std::string::npos) << refusal();
  // A linked case folder leads outside as well.
  shard_.results.runs.clear();
  fs::create_directory_symlink(root_ / "outside/trajectories/c",
                               root_ / "shard/trajectories/linked");
  addRun("ode", "ode.quickstep", "out/trajectories/linked/ode-ode.quickstep.csv");
  shard_.results.runs.back().request.caseName = "linked";
  EXPECT_NE(refusal().find("is a symbolic link"), std::string::npos) << refusal();
}

TEST_F(ShardFiles, AMissingTrajectoryOfAMeasuredRunIsRefusedOfAFailedRunAccepted) {
  addRun("bullet", "bullet.si", "out/trajectories/c/bullet-bullet.si.csv", RunStatus::Ok);
  EXPECT_NE(refusal().find("does not exist"), std::string::npos) << refusal();
  shard_.results.runs.back().status = RunStatus::Timeout;  // killed before it wrote one
  EXPECT_EQ(refusal(), "");
  EXPECT_TRUE(verifiedShardFiles(shard_).empty());
}

TEST_F(ShardFiles, NamesThatAreNotPlainFileNamesAreRefused) {
  addRun("..", "pbd", "out/trajectories/c/..-pbd.csv");
  EXPECT_NE(refusal().find("plain names"), std::string::npos) << refusal();
}

TEST_F(ShardFiles, OnlyVerifiedFilesAreCarriedAndACompanionLinkIsRefused) {
  addRun("pbd", "pbd", "out/trajectories/c/pbd-pbd.csv");
  write(root_ / "shard/trajectories/c/pbd-pbd.particles.csv", "particles\n");
  std::vector<ShardFile> files = verifiedShardFiles(shard_);
  ASSERT_EQ(files.size(), 2u);
  carryShardFiles(files, (root_ / "merged").string(), /*move=*/true);
  EXPECT_TRUE(fs::is_regular_file(root_ / "merged/trajectories/c/pbd-pbd.csv"));
  EXPECT_TRUE(fs::is_regular_file(root_ / "merged/trajectories/c/pbd-pbd.particles.csv"));
  EXPECT_FALSE(fs::exists(root_ / "shard/trajectories/c/pbd-pbd.csv"));  // moved
  EXPECT_TRUE(fs::exists(root_ / "outside/secret.csv"));
  write(root_ / "shard/trajectories/c/pbd-pbd.csv", "inside\n");
  fs::remove(root_ / "shard/trajectories/c/pbd-pbd.particles.csv");
  fs::create_symlink(root_ / "outside/secret.csv",
                     root_ / "shard/trajectories/c/pbd-pbd.particles.csv");
  EXPECT_NE(refusal().find("a symbolic link"), std::string::npos) << refusal();
}

/// A plan of three runs, its one shard (1/1) as `pbdval run --shard 1/1` records it.
ShardResults wholePlanShard() {
  RunPlan plan;
  for (const auto& [engine, method] : std::vector<std::pair<std::string, std::string>>{
           {"pbd", "pbd"}, {"ode", "ode.quickstep"}, {"bullet", "bullet.si"}}) {
    RunRequest r;
    r.caseName = "c";
    r.caseFile = "cases/c.json";
    r.engine = engine;
    r.method = method;
    plan.requests.push_back(r);
  }
  ShardResults shard;
  shard.folder = "shard-1";
  ShardInfo info;
  info.index = 1;
  info.count = 1;
  info.planSize = plan.requests.size();
  info.planDigest = planDigest(plan);
  shard.results.metadata.shard = info;
  shard.results.metadata.planDigest = runsDigest(plan);
  for (const RunRequest& request : plan.requests) {
    RunRecord record;
    record.request = request;
    record.status = RunStatus::Ok;
    shard.results.runs.push_back(record);
  }
  return shard;
}

TEST(MergeShards, RunsRelabelledOrReorderedInAShardAreRefused) {
  EXPECT_EQ(mergeShards({wholePlanShard()}, "merge").runs.size(), 3u);
  ShardResults relabelled = wholePlanShard();
  relabelled.results.runs[1].request.engine = "mujoco";  // an engine the plan does not have
  relabelled.results.runs[1].request.method = "mujoco";
  EXPECT_THROW(mergeShards({relabelled}, "merge"), std::invalid_argument);
  ShardResults reordered = wholePlanShard();
  std::swap(reordered.results.runs[0], reordered.results.runs[2]);
  try {
    mergeShards({reordered}, "merge");
    ADD_FAILURE() << "runs out of plan order were merged";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not the plan they were run from"), std::string::npos)
        << e.what();
  }
}

// ---- ProcessReaper -----------------------------------------------------------------------------

/// Whether `pid` runs now (a zombie does not).
bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  const std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const std::size_t close = text.rfind(')');
  return !text.empty() && close != std::string::npos && text.compare(close + 2, 1, "Z") != 0;
}

/// Whether `pid` still runs after up to 2 s of waiting for it to end.
bool stillRunning(pid_t pid) {
  for (int k = 0; k < 200 && running(pid); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return running(pid);
}

TEST(ProcessReaper, AProcessThatLeftTheEnginesSessionIsKilledAndReaped) {
  int pipeEnds[2];
  ASSERT_EQ(::pipe(pipeEnds), 0);
  pid_t escaped = -1;
  int killed = 0;
  {
    const ProcessReaper reaper;
    const pid_t engine = ::fork();
    ASSERT_GE(engine, 0);
    if (engine == 0) {  // the "engine": starts a daemon-like grandchild, then ends
      reaper.mark();
      const pid_t child = ::fork();
      if (child == 0) {
        ::setsid();  // out of the engine's process group and session
        const pid_t self = ::getpid();
        (void)!::write(pipeEnds[1], &self, sizeof self);
        // /proc/PID/environ shows the environment a program was started with: the "engine"
        // here is forked without exec (its environ is this test's), so the grandchild execs a
        // program, as a real engine (exec'd with the mark) and what it starts are.
        ::execl("/bin/sleep", "sleep", "300", static_cast<char*>(nullptr));
        ::_exit(127);
      }
      ::_exit(0);
    }
    ASSERT_EQ(::read(pipeEnds[0], &escaped, sizeof escaped), ssize_t(sizeof escaped));
    int status = 0;
    ASSERT_EQ(::waitpid(engine, &status, 0), engine);
    ASSERT_TRUE(running(escaped))
        << "the grandchild must outlive the engine for the test to mean anything";
    for (int k = 0; k < 500; ++k) {  // until it has exec'd sleep (5 s at most)
      std::ifstream comm("/proc/" + std::to_string(escaped) + "/comm");
      std::string name;
      if (std::getline(comm, name) && name == "sleep") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    killed = reaper.killRemaining(engine);
  }
  EXPECT_EQ(killed, 1);
  EXPECT_FALSE(stillRunning(escaped));
  // Re-parented to this process (a subreaper while the reaper lived) and reaped by it: no
  // zombie child is left.
  EXPECT_EQ(::waitpid(-1, nullptr, WNOHANG), -1);
  ::close(pipeEnds[0]);
  ::close(pipeEnds[1]);
  if (running(escaped)) ::kill(escaped, SIGKILL);
}

TEST(ProcessReaper, ProcessesWithoutItsMarkAreLeftAlone) {
  const pid_t bystander = ::fork();
  ASSERT_GE(bystander, 0);
  if (bystander == 0) {
    ::pause();
    ::_exit(0);
  }
  {
    const ProcessReaper reaper;
    EXPECT_EQ(reaper.killRemaining(-1), 0);
  }
  EXPECT_TRUE(running(bystander));
  ::kill(bystander, SIGKILL);
  ::waitpid(bystander, nullptr, 0);
}

}  // namespace
}  // namespace pbdval
