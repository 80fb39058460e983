// The external-engine protocol from the runner's side: every way an engine can misbehave is a
// run status with a reason, never a failure of the runner. The "engines" here are shell
// one-liners that misbehave on purpose; the well-behaved one copies a trajectory the test
// computes itself (the bodies at rest at the planned sample times).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "common/text_assertions.h"
#include "pbd/io/scene_loader.h"
#include "pbdval/build_info.h"
#include "validation/external/engine_catalogue.h"
#include "validation/external/external_engine.h"
#include "validation/external/standard_engines.h"
#include "validation/io/json_schema.h"
#include "validation/io/trajectory.h"
#include "validation/run/interrupts.h"
#include "validation/run/simulation.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;
using pbd::test::containsAll;

const char* kScene = R"({
  "Simulation": {"timeStepSize": 0.01, "gravitation": [0, 0, 0]},
  "RigidBodies": [
    {"id": 3, "collisionObjectType": 1, "collisionObjectScale": [0.5, 0.5, 0.5], "density": 1000},
    {"id": 7, "collisionObjectType": 1, "collisionObjectScale": [0.5, 0.5, 0.5], "density": 1000,
     "translation": [2, 0, 0]}]
})";

class ExternalEngineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("pbdval-external-" + std::to_string(::getpid()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
    scene_ = pbd::parseScene(kScene, (folder_ / "scene.json").string()).scene;
    length_ = {0.1, 0.05};  // 10 steps, samples at steps 0, 5, 10
  }
  void TearDown() override { fs::remove_all(folder_); }

  /// The trajectory a correct engine writes for the bodies at rest, with `edit` applied to it.
  std::string restingTrajectory(const std::function<void(std::vector<State>&)>& edit = {}) {
    std::vector<State> samples;
    for (int step : {0, 5, 10}) {
      State s;
      s.time = step * 0.01;
      for (const pbd::RigidBodyDesc& b : scene_.rigidBodies)
        s.bodies.push_back(
            {b.id, b.initialCenterOfMass(), b.rotation, Vector3::Zero(), Vector3::Zero()});
      samples.push_back(s);
    }
    if (edit) edit(samples);
    const fs::path file = folder_ / ("trajectory-" + std::to_string(counter_++) + ".csv");
    std::ofstream out(file);
    writeCsvHeader(out);
    for (const State& s : samples)
      writeCsvRows(out, s);
    return file.string();
  }

  /// The same trajectory as NPY (version 1.0, float64 rows of 15 columns), written here by hand
  /// from the format's definition (numpy.lib.format), with `header` replacing the dictionary when
  /// given and the data cut to `dataBytes` when non-negative.
  std::string restingNpy(const std::string& header = "", long dataBytes = -1) {
    std::vector<double> rows;
    for (int step : {0, 5, 10})
      for (const pbd::RigidBodyDesc& b : scene_.rigidBodies) {
        const Vector3 x = b.initialCenterOfMass();
        const pbd::Quaternion q = b.rotation;
        for (double v :
             {step * 0.01, double(b.id), double(x.x()), double(x.y()), double(x.z()), double(q.w()),
              double(q.x()), double(q.y()), double(q.z()), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0})
          rows.push_back(v);
      }
    std::string dict = header.empty() ? "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                                            std::to_string(rows.size() / 15) + ", 15), }"
                                      : header;
    while ((10 + dict.size() + 1) % 64 != 0)
      dict += ' ';
    dict += '\n';
    std::string bytes = "\x93NUMPY";
    bytes += char(1);
    bytes += char(0);
    bytes += char(dict.size() & 0xff);
    bytes += char(dict.size() >> 8);
    bytes += dict;
    std::string data(reinterpret_cast<const char*>(rows.data()), rows.size() * sizeof(double));
    if (dataBytes >= 0) data.resize(std::size_t(dataBytes));
    bytes += data;
    const fs::path file = folder_ / ("trajectory-" + std::to_string(counter_++) + ".npy");
    std::ofstream(file, std::ios::binary) << bytes;
    return file.string();
  }

  /// Runs the shell `script` as an engine ($4 is the output folder).
  RunOutcome run(const std::string& script, double limit = 10) {
    ExternalEngine engine("shell",
                          ExternalCommand{{"sh", "-c", script, "engine"}, folder_.string(), ""});
    Method method;
    method.name = "shell.test";
    std::vector<State> seen;
    RunCallbacks callbacks;
    callbacks.onSample = [&](const State& s) { seen.push_back(s); };
    RunOutcome outcome = runSimulation(engine, scene_, method, length_, callbacks, limit);
    samples_ = seen;
    return outcome;
  }

  static std::string okStatus() {
    return R"(printf '{"protocol": 1, "status": "ok", "reason": "", "engineVersion": "shell 1", )"
           R"("unsupported": [], "divergedAt": null, )"
           R"("integratorStepsPerSceneStep": 2, "contactMargin": 0.001, )"
           R"("effectiveSettings": {"solver": "none", "iterations": 3}}' > "$4/status.json")";
  }

  fs::path folder_;
  pbd::Scene scene_;
  RunLength length_;
  std::vector<State> samples_;
  int counter_ = 0;
};

TEST_F(ExternalEngineTest, AWellBehavedEngineRunsWithItsFactsAndSettings) {
  const RunOutcome outcome =
      run("cp " + restingTrajectory() + " \"$4/trajectory.csv\"; " + okStatus());
  ASSERT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  EXPECT_EQ(samples_.size(), 3u);
  EXPECT_EQ(outcome.facts.engineVersion, "shell 1");
  EXPECT_EQ(outcome.facts.integratorStepsPerSceneStep, 2);
  EXPECT_EQ(outcome.facts.contactMargin, 0.001);
  EXPECT_EQ(outcome.settings.at("iterations"), "3");
  EXPECT_EQ(outcome.steps, 10);
}

TEST_F(ExternalEngineTest, ABinaryTrajectoryReadsAsTheCsv) {
  const RunOutcome csv = run("cp " + restingTrajectory() + " \"$4/trajectory.csv\"; " + okStatus());
  const std::vector<State> fromCsv = samples_;
  const RunOutcome npy = run("cp " + restingNpy() + " \"$4/trajectory.npy\"; " + okStatus());
  ASSERT_EQ(npy.status, RunStatus::Ok) << npy.reason;
  ASSERT_EQ(samples_.size(), fromCsv.size());
  for (std::size_t k = 0; k < samples_.size(); ++k) {
    EXPECT_EQ(samples_[k].time, fromCsv[k].time);
    ASSERT_EQ(samples_[k].bodies.size(), fromCsv[k].bodies.size());
    for (std::size_t b = 0; b < samples_[k].bodies.size(); ++b) {
      EXPECT_EQ(samples_[k].bodies[b].id, fromCsv[k].bodies[b].id);
      EXPECT_EQ(samples_[k].bodies[b].position, fromCsv[k].bodies[b].position);
    }
  }
  EXPECT_EQ(csv.status, RunStatus::Ok);
}

TEST_F(ExternalEngineTest, BadBinaryTrajectoriesAreErrorsNamingWhatWasExpected) {
  const RunOutcome truncated =
      run("cp " + restingNpy("", 100) + " \"$4/trajectory.npy\"; " + okStatus());
  EXPECT_EQ(truncated.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(truncated.reason, {"trajectory.npy", "6 rows", "found 100 bytes"}))
      << truncated.reason;
  const RunOutcome floats =
      run("cp " + restingNpy("{'descr': '<f4', 'fortran_order': False, 'shape': (6, 15), }") +
          " \"$4/trajectory.npy\"; " + okStatus());
  EXPECT_TRUE(containsAll(floats.reason, {"trajectory.npy", "'<f8'"})) << floats.reason;
  const RunOutcome columns =
      run("cp " + restingNpy("{'descr': '<f8', 'fortran_order': False, 'shape': (6, 14), }") +
          " \"$4/trajectory.npy\"; " + okStatus());
  EXPECT_TRUE(containsAll(columns.reason, {"shape (rows, 15)"})) << columns.reason;
  const RunOutcome fortran =
      run("cp " + restingNpy("{'descr': '<f8', 'fortran_order': True, 'shape': (6, 15), }") +
          " \"$4/trajectory.npy\"; " + okStatus());
  EXPECT_TRUE(containsAll(fortran.reason, {"'fortran_order': False"})) << fortran.reason;
  const RunOutcome both = run("cp " + restingNpy() + " \"$4/trajectory.npy\"; cp " +
                              restingTrajectory() + " \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(both.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(both.reason, {"both", "trajectory.csv", "trajectory.npy"}))
      << both.reason;
  const RunOutcome text = run("echo hello > \"$4/trajectory.npy\"; " + okStatus());
  EXPECT_TRUE(containsAll(text.reason, {"NPY magic"})) << text.reason;
}

TEST_F(ExternalEngineTest, AMissingCommandIsAnError) {
  ExternalEngine engine("missing", ExternalCommand{{"/no/such/engine"}, folder_.string(), ""});
  Method method;
  method.name = "missing.x";
  const RunOutcome outcome = runSimulation(engine, scene_, method, length_, {});
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason, {"could not be started", "/no/such/engine"}))
      << outcome.reason;
}

TEST_F(ExternalEngineTest, ANonZeroExitIsAnErrorWithItsStandardError) {
  const RunOutcome outcome = run("echo 'Traceback: boom' >&2; exit 3");
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason, {"exited with status 3", "status.json", "boom"}))
      << outcome.reason;
}

TEST_F(ExternalEngineTest, AnErrorMessageAboveALongStackIsKept) {
  // Node.js prints the error's message above its stack: the tail alone would show frames only.
  const RunOutcome outcome = run(
      "{ echo '/e/engine.js:3'; echo '  throw new TypeError(message)'; echo;"
      " echo 'TypeError: the resolved scene has no bodies'; i=0;"
      " while [ $i -lt 40 ]; do echo \"    at step (/e/engine.js:$i:7)\"; i=$((i+1)); done; } >&2;"
      " exit 1");
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason, {"TypeError: the resolved scene has no bodies",
                                           "at step (/e/engine.js:39:7)"}))
      << outcome.reason;
}

TEST_F(ExternalEngineTest, AHangIsATimeout) {
  const RunOutcome outcome = run("sleep 30", /*limit=*/0.3);
  EXPECT_EQ(outcome.status, RunStatus::Timeout) << outcome.reason;
  EXPECT_LT(outcome.wallTime, 5.0);
}

// --- Issue 25: nothing is left behind ------------------------------------------------------

/// Whether process `pid` still runs (a zombie waiting to be reaped does not), after waiting up
/// to 5 s for it to go (a SIGKILLed process goes within milliseconds).
bool stillRunsAfterWaiting(pid_t pid) {
  for (int attempt = 0; attempt < 500; ++attempt) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    if (!std::getline(stat, text)) return false;
    const std::size_t close = text.rfind(')');
    if (close != std::string::npos && text.compare(close, 3, ") Z") == 0) return false;
    ::usleep(10000);
  }
  return true;
}

/// The pid an engine script wrote to `file`, waiting up to 10 s for it.
pid_t recordedPid(const fs::path& file) {
  for (int attempt = 0; attempt < 1000; ++attempt) {
    std::ifstream in(file);
    long pid = 0;
    if (in >> pid && pid > 0) return pid_t(pid);
    ::usleep(10000);
  }
  return -1;
}

/// The scratch folders of the runs of process `owner` still in the temporary folder.
std::vector<fs::path> scratchFoldersOf(pid_t owner) {
  std::vector<fs::path> found;
  const std::string prefix = "pbdval-engine-" + std::to_string(owner) + "-";
  for (const auto& item : fs::directory_iterator(fs::temp_directory_path()))
    if (item.path().filename().string().rfind(prefix, 0) == 0) found.push_back(item.path());
  return found;
}

/// Ends `pid` if the test failed before it could: no test leaves a process behind either.
struct KillAtExit {
  pid_t pid;
  ~KillAtExit() {
    if (pid > 0) ::kill(pid, SIGKILL);
  }
};

/// After a run: the child the engine recorded in `childFile` is gone (killed here if not, so
/// that a failing test leaves nothing), and so is every scratch folder of this process.
void expectNothingLeftBehind(const fs::path& childFile) {
  const pid_t child = recordedPid(childFile);
  const KillAtExit guard{child};
  ASSERT_GT(child, 0);
  EXPECT_FALSE(stillRunsAfterWaiting(child))
      << "the engine's child " << child << " outlived the run";
  EXPECT_TRUE(scratchFoldersOf(::getpid()).empty());
}

TEST_F(ExternalEngineTest, AProcessTheEngineLeftRunningEndsWithTheRun) {
  const fs::path childFile = folder_ / "child.pid";
  const RunOutcome outcome = run("sleep 300 & echo $! > " + childFile.string() + "; cp " +
                                 restingTrajectory() + " \"$4/trajectory.csv\"; " + okStatus());
  ASSERT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  expectNothingLeftBehind(childFile);
}

TEST_F(ExternalEngineTest, ATimedOutEngineLeavesNoProcessAndNoScratchFolder) {
  const fs::path childFile = folder_ / "child.pid";
  const RunOutcome outcome =
      run("sleep 300 & echo $! > " + childFile.string() + "; sleep 300", /*limit=*/0.5);
  EXPECT_EQ(outcome.status, RunStatus::Timeout) << outcome.reason;
  expectNothingLeftBehind(childFile);
}

/// Forks a process that runs a hanging engine (which starts a child of its own, recorded in
/// `childFile`) with no wall-time limit; in the fork, a SignalInterrupt ends it with status 10 +
/// the signal, anything else with 99. Returns the fork's pid once the engine's child exists.
pid_t forkHangingRun(const fs::path& folder, const pbd::Scene& scene, const RunLength& length,
                     const fs::path& childFile) {
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ExternalEngine engine(
        "shell",
        ExternalCommand{
            {"sh", "-c", "sleep 300 & echo $! > " + childFile.string() + "; sleep 300", "engine"},
            folder.string(),
            ""});
    Method method;
    method.name = "shell.hang";
    try {
      runSimulation(engine, scene, method, length, {}, 0);
    } catch (const SignalInterrupt& e) {
      ::_exit(10 + e.signal());
    } catch (...) {
    }
    ::_exit(99);
  }
  return pid;
}

/// waitpid, killing `pid` if it has not ended within 20 s (a hang must fail the test, not stall
/// it). Returns the wait status.
int waitBounded(pid_t pid) {
  int status = 0;
  for (int attempt = 0; attempt < 2000; ++attempt) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return status;
    ::usleep(10000);
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return status;
}

TEST_F(ExternalEngineTest, SIGTERMStopsTheEngineRemovesItsScratchAndIsThrown) {
  const fs::path childFile = folder_ / "child.pid";
  const pid_t runner = forkHangingRun(folder_, scene_, length_, childFile);
  ASSERT_GT(runner, 0);
  const pid_t child = recordedPid(childFile);
  const KillAtExit guard{child};
  ASSERT_GT(child, 0);
  ::kill(runner, SIGTERM);
  const int status = waitBounded(runner);
  ASSERT_TRUE(WIFEXITED(status)) << "the runner died of the signal instead of taking it";
  EXPECT_EQ(WEXITSTATUS(status), 10 + SIGTERM);
  EXPECT_FALSE(stillRunsAfterWaiting(child));
  EXPECT_TRUE(scratchFoldersOf(runner).empty());
}

TEST_F(ExternalEngineTest, WhatARunKilledOutrightLeftIsRemovedByItsParent) {
  const fs::path childFile = folder_ / "child.pid";
  const pid_t runner = forkHangingRun(folder_, scene_, length_, childFile);
  ASSERT_GT(runner, 0);
  const pid_t child = recordedPid(childFile);
  const KillAtExit guard{child};
  ASSERT_GT(child, 0);
  ::kill(runner, SIGKILL);  // as the scheduler stops a run over its limit
  waitBounded(runner);
  EXPECT_EQ(scratchFoldersOf(runner).size(), 1u);  // the killed runner could not remove it
  removeEngineLeftovers(runner);
  EXPECT_TRUE(scratchFoldersOf(runner).empty());
  EXPECT_FALSE(stillRunsAfterWaiting(child));
}

TEST_F(ExternalEngineTest, AMalformedStatusIsAnError) {
  EXPECT_EQ(run("printf '{' > \"$4/status.json\"").status, RunStatus::Error);
  const RunOutcome wrongProtocol =
      run(R"(printf '{"protocol": 2, "status": "ok"}' > "$4/status.json")");
  EXPECT_EQ(wrongProtocol.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(wrongProtocol.reason, {"protocol"})) << wrongProtocol.reason;
}

TEST_F(ExternalEngineTest, ATruncatedTrajectoryIsAnError) {
  const RunOutcome outcome =
      run("head -c 200 " + restingTrajectory() + " > \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason, {"trajectory.csv", "line"})) << outcome.reason;
}

TEST_F(ExternalEngineTest, WrongRowCountsTimesOrBodiesAreErrors) {
  const RunOutcome few =
      run("cp " + restingTrajectory([](std::vector<State>& s) { s.pop_back(); }) +
          " \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(few.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(few.reason, {"2 samples, expected 3"})) << few.reason;

  const RunOutcome time =
      run("cp " + restingTrajectory([](std::vector<State>& s) { s[1].time = 0.06; }) +
          " \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(time.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(time.reason, {"t = 0.06", "expected 0.05"})) << time.reason;

  const RunOutcome bodies = run("cp " + restingTrajectory([](std::vector<State>& s) {
                                  std::swap(s[2].bodies[0], s[2].bodies[1]);
                                }) +
                                " \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(bodies.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(bodies.reason, {"is body 7, expected body 3"})) << bodies.reason;
}

TEST_F(ExternalEngineTest, ProtocolMistakesAreErrorsNamingTheCheckAndTheBody) {
  // The boundary checks (validation/measure/sanity.h) hold an external engine's samples like a
  // built-in engine's: each of these mistakes leaves the first sample off the scene's state.
  const auto mistake = [&](const std::function<void(BodyState&)>& edit) {
    return run("cp " + restingTrajectory([&](std::vector<State>& samples) {
                 for (State& s : samples)
                   edit(s.bodies[1]);
               }) +
               " \"$4/trajectory.csv\"; " + okStatus());
  };
  const RunOutcome xyzw = mistake([](BodyState& b) {
    b.rotation = Quaternion(b.rotation.x(), b.rotation.y(), b.rotation.z(), b.rotation.w());
  });
  EXPECT_EQ(xyzw.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(xyzw.reason, {"initial_state", "orientation", "body 7"})) << xyzw.reason;
  const RunOutcome millimetres = mistake([](BodyState& b) { b.position *= 1000; });
  EXPECT_EQ(millimetres.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(millimetres.reason, {"initial_state", "position", "body 7"}))
      << millimetres.reason;
  const RunOutcome origin = mistake([](BodyState& b) { b.position.x() -= 0.05; });
  EXPECT_EQ(origin.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(origin.reason, {"initial_state", "position", "body 7"})) << origin.reason;
}

TEST_F(ExternalEngineTest, NaNsInTheTrajectoryAreADivergence) {
  const RunOutcome outcome = run("cp " + restingTrajectory([](std::vector<State>& s) {
                                   s[1].bodies[1].position.x() = std::nan("");
                                 }) +
                                 " \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(outcome.status, RunStatus::Diverged);
  EXPECT_TRUE(containsAll(outcome.reason, {"non-finite", "body 7"})) << outcome.reason;
}

TEST_F(ExternalEngineTest, UnsupportedFeaturesAreReportedByName) {
  const RunOutcome outcome = run(
      R"(printf '{"protocol": 1, "status": "unsupported", "reason": "x", "divergedAt": null, )"
      R"("engineVersion": "shell 1", "effectiveSettings": {}, "integratorStepsPerSceneStep": 1, )"
      R"("contactMargin": null, "unsupported": ["SliderJoints[0]: joint slider", "particles"]}' )"
      R"(> "$4/status.json")");
  EXPECT_EQ(outcome.status, RunStatus::Unsupported);
  EXPECT_EQ(outcome.reason, "SliderJoints[0]: joint slider; particles");
}

// --- Particles (cloth and solids) ------------------------------------------------------------

/// The fixture's two bodies plus a cloth of one triangle (three particles, the first static).
class ExternalEngineParticleTest : public ExternalEngineTest {
 protected:
  void SetUp() override {
    ExternalEngineTest::SetUp();
    std::ofstream(folder_ / "triangle.obj") << "v 0 1 0\nv 1 1 0\nv 0 1 1\nf 1 2 3\n";
    const std::string text = R"({
      "Simulation": {"timeStepSize": 0.01, "gravitation": [0, 0, 0], "clothSimulationMethod": 4},
      "RigidBodies": [
        {"id": 3, "collisionObjectType": 1, "collisionObjectScale": [0.5, 0.5, 0.5], "density": 1000}],
      "TriangleModels": [{"id": 0, "geometryFile": "triangle.obj", "staticParticles": [0]}]
    })";
    scene_ = pbd::parseScene(text, (folder_ / "scene.json").string()).scene;
    ASSERT_EQ(scene_.particles.size(), 3u);
  }

  /// The particles at rest at the planned sample times, `edit` applied, as CSV or NPY (the
  /// library's writers: their format is tested in test_trajectory).
  std::string restingParticles(bool npy,
                               const std::function<void(std::vector<State>&)>& edit = {}) {
    std::vector<State> samples;
    for (int step : {0, 5, 10}) {
      State s;
      s.time = step * 0.01;
      for (const pbd::ParticleDesc& p : scene_.particles)
        s.particles.push_back({p.position, Vector3::Zero()});
      samples.push_back(s);
    }
    if (edit) edit(samples);
    const fs::path file =
        folder_ / ("particles-" + std::to_string(counter_++) + (npy ? ".npy" : ".csv"));
    std::ofstream out(file, std::ios::binary);
    if (npy) {
      writeParticleTrajectoryNpy(out, samples);
    } else {
      writeParticleCsvHeader(out);
      for (const State& s : samples)
        writeParticleCsvRows(out, s);
    }
    return file.string();
  }

  std::string copies(const std::string& particles, const std::string& name) {
    return "cp " + restingTrajectory() + " \"$4/trajectory.csv\"; cp " + particles + " \"$4/" +
           name + "\"; " + okStatus();
  }
};

TEST_F(ExternalEngineParticleTest, ParticlesAreReadBackWithTheirSamples) {
  for (bool npy : {false, true}) {
    const RunOutcome outcome =
        run(copies(restingParticles(npy), npy ? "particles.npy" : "particles.csv"));
    ASSERT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
    ASSERT_EQ(samples_.size(), 3u);
    for (const State& s : samples_) {
      ASSERT_EQ(s.particles.size(), 3u);
      for (std::size_t i = 0; i < 3;
           ++i)  // the files hold the doubles exactly (shortest text or binary)
        EXPECT_EQ(s.particles[i].position, scene_.particles[i].position) << "npy " << npy;
    }
  }
}

TEST_F(ExternalEngineParticleTest, MissingOrMisplacedParticlesAreErrors) {
  const RunOutcome none =
      run("cp " + restingTrajectory() + " \"$4/trajectory.csv\"; " + okStatus());
  EXPECT_EQ(none.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(none.reason, {"3 particles", "neither particles.npy nor particles.csv"}))
      << none.reason;

  const RunOutcome both = run("cp " + restingParticles(true) + " \"$4/particles.npy\"; " +
                              copies(restingParticles(false), "particles.csv"));
  EXPECT_TRUE(containsAll(both.reason, {"both", "particles.csv", "particles.npy"})) << both.reason;

  const RunOutcome few =
      run(copies(restingParticles(false, [](std::vector<State>& s) { s[1].particles.pop_back(); }),
                 "particles.csv"));
  EXPECT_EQ(few.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(few.reason, {"particles.csv", "sample 1", "2 particles, expected 3"}))
      << few.reason;

  const RunOutcome late = run(copies(
      restingParticles(true, [](std::vector<State>& s) { s[2].time = 0.11; }), "particles.npy"));
  EXPECT_TRUE(containsAll(late.reason, {"particles.npy", "sample 2", "t = 0.11"})) << late.reason;

  const RunOutcome missingSample = run(copies(
      restingParticles(false, [](std::vector<State>& s) { s.pop_back(); }), "particles.csv"));
  EXPECT_TRUE(containsAll(missingSample.reason, {"2 samples", "the trajectory 3"}))
      << missingSample.reason;
}

TEST_F(ExternalEngineParticleTest, ParticlesOutOfOrderAreAnErrorNamingTheRow) {
  // Rows of the CSV reordered by hand: sample 0 lists particle 1 first.
  const std::string file = (folder_ / "swapped.csv").string();
  std::ofstream(file) << "t,index,x,y,z,vx,vy,vz\n0,1,1,1,0,0,0,0\n0,0,0,1,0,0,0,0\n";
  const RunOutcome outcome = run(copies(file, "particles.csv"));
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason, {"particles.csv", "line 2", "particle 1, expected 0"}))
      << outcome.reason;
}

TEST_F(ExternalEngineParticleTest, ABlownUpParticleIsADivergence) {
  const RunOutcome nan = run(copies(
      restingParticles(
          true, [](std::vector<State>& s) { s[1].particles[2].velocity.y() = std::nan(""); }),
      "particles.npy"));
  EXPECT_EQ(nan.status, RunStatus::Diverged);
  EXPECT_TRUE(containsAll(nan.reason, {"non-finite", "particle 2", "t = 0.05"})) << nan.reason;
  // 2e6 m: beyond the runner's limit of 1e6 m (kDivergenceLimit).
  const RunOutcome far = run(copies(
      restingParticles(false, [](std::vector<State>& s) { s[2].particles[1].position.x() = 2e6; }),
      "particles.csv"));
  EXPECT_EQ(far.status, RunStatus::Diverged);
  EXPECT_TRUE(containsAll(far.reason, {"particle 1 blew up"})) << far.reason;
}

TEST_F(ExternalEngineParticleTest, ASceneWithoutBodiesTakesItsSamplesFromTheParticles) {
  // Only the cloth: the trajectory has zero rows per sample (a header only), so the sample
  // times are the particles' and are checked against the plan as a trajectory's would be.
  const std::string text = R"({
    "Simulation": {"timeStepSize": 0.01, "gravitation": [0, 0, 0], "clothSimulationMethod": 4},
    "TriangleModels": [{"id": 0, "geometryFile": "triangle.obj", "staticParticles": [0]}]
  })";
  scene_ = pbd::parseScene(text, (folder_ / "scene.json").string()).scene;
  ASSERT_TRUE(scene_.rigidBodies.empty());
  const std::string empty = (folder_ / "empty.csv").string();
  std::ofstream(empty) << "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  const auto engine = [&](const std::string& particles) {
    return "cp " + empty + " \"$4/trajectory.csv\"; cp " + particles + " \"$4/particles.csv\"; " +
           okStatus();
  };
  const RunOutcome ok = run(engine(restingParticles(false)));
  ASSERT_EQ(ok.status, RunStatus::Ok) << ok.reason;
  ASSERT_EQ(samples_.size(), 3u);
  for (const State& s : samples_) {
    EXPECT_TRUE(s.bodies.empty());
    EXPECT_EQ(s.particles.size(), 3u);
  }
  EXPECT_EQ(samples_[2].time, 0.1);

  const RunOutcome late =
      run(engine(restingParticles(false, [](std::vector<State>& s) { s[2].time = 0.11; })));
  EXPECT_EQ(late.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(late.reason, {"particles.csv", "sample 2", "t = 0.11"})) << late.reason;
}

TEST_F(ExternalEngineTest, ParticlesForASceneWithoutParticlesAreAnError) {
  const std::string file = (folder_ / "stray.csv").string();
  std::ofstream(file) << "t,index,x,y,z,vx,vy,vz\n";
  const RunOutcome outcome = run("cp " + restingTrajectory() + " \"$4/trajectory.csv\"; cp " +
                                 file + " \"$4/particles.csv\"; " + okStatus());
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason, {"particles.csv", "without particles"}))
      << outcome.reason;
}

TEST_F(ExternalEngineTest, APythonCommandGetsThePackageFolderFirstOnItsPythonPath) {
  // The engine fails unless PYTHONPATH starts with the package folder: the run's status says which.
  const std::string script =
      "case \"$PYTHONPATH\" in /src/python|/src/python:*) ;; *) exit 3;; esac; " +
      std::string("cp ") + restingTrajectory() + " \"$4/trajectory.csv\"; " + okStatus();
  const ExternalCommand command{{"sh", "-c", script, "engine"}, folder_.string(), "/src/python"};
  ExternalEngine engine("shell", command);
  Method method;
  method.name = "shell.test";
  const RunOutcome outcome = runSimulation(engine, scene_, method, length_, {}, 10);
  EXPECT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
}

TEST(EngineCatalogue, EntriesAreTypedAndBadFilesNameTheirPath) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-catalogue-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder / "good.json") << R"({"protocol": 1, "name": "good",
    "command": ["{python}", "engine.py"], "defaultMethod": "good.a",
    "methods": [{"name": "good.a", "description": "d", "parameters": [
      {"name": "iterations", "kind": "integer", "default": 10, "min": 1, "max": 100,
       "description": "sweeps"}]}]})";
  const std::vector<EngineEntry> entries =
      readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].methods[0].parameters[0].kind, ParameterKind::Integer);
  EXPECT_THROW(parseParameter(entries[0].methods[0].parameters[0], "0", "good.a"),
               std::invalid_argument);

  std::ofstream(folder / "zbad.json") << R"({"protocol": 1, "name": "bad", "command": ["x"],
    "defaultMethod": "bad.a", "methods": [{"name": "bad.a", "parameters": [
      {"name": "p", "kind": "float", "default": 1}]}]})";
  try {
    readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
    FAIL() << "a bad kind was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(containsAll(e.what(),
                            {"zbad.json", "methods[0].parameters[0].kind",
                             R"("real", "integer", "bool" or "choice")", "catalogue.schema.json"}))
        << e.what();
  }
  fs::remove_all(folder);
}

TEST(EngineCatalogue, AFeatureTableIsCheckedAndDecidesUnsupportedRunsBeforeTheEngineStarts) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-catalogue-features-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  const auto write = [&](const std::string& features) {
    std::ofstream(folder / "probe.json") << R"({"protocol": 1, "name": "probe",
      "command": ["/bin/false"], "defaultMethod": "probe.a",
      "methods": [{"name": "probe.a"}, {"name": "probe.b"}], "features": [)"
                                         << features << "]}";
  };
  const std::string everything =
      R"({"feature": "shape", "support": "native"}, {"feature": "body", "support": "native"},
         {"feature": "contact", "support": "native"}, {"feature": "particle", "support": "native"},
         {"feature": "cloth", "support": "native"}, {"feature": "solid", "support": "native"},
         {"feature": "rod", "support": "native"}, {"feature": "fluid", "support": "native"})";
  write(everything + R"(, {"feature": "joint", "support": "native"},
    {"feature": "joint.distance", "support": "unsupported", "text": "no rods", "methods": ["probe.b"]})");
  const std::vector<EngineEntry> entries =
      readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
  ASSERT_EQ(entries.size(), 1u);
  const EngineEntry& entry = entries[0];
  ASSERT_EQ(entry.features.entries.size(), 10u);
  EXPECT_EQ(entry.features.resolve("joint.distance", "probe.b")->support, Support::Unsupported);
  // The engine (its command would fail) is never started for a run its table refuses.
  pbd::Scene scene;
  scene.rigidBodies = {pbd::RigidBodyDesc{}, pbd::RigidBodyDesc{}};
  scene.rigidBodies[1].id = 1;
  pbd::JointDesc joint;
  joint.type = pbd::JointType::Distance;
  joint.jsonPath = "DistanceJoints[0]";
  joint.body1 = 0;
  joint.body2 = 1;
  scene.joints = {joint};
  const std::unique_ptr<Engine> engine = entry.make({});
  const std::vector<std::string> refused =
      engine->unsupported(scene, resolveMethod(entry.methods[1]));
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_TRUE(containsAll(refused[0], {"DistanceJoints[0]", "no rods"})) << refused[0];
  EXPECT_TRUE(engine->unsupported(scene, resolveMethod(entry.methods[0])).empty());
  const RunOutcome outcome =
      runSimulation(*engine, scene, resolveMethod(entry.methods[1]), {0.1, 0}, {});
  EXPECT_EQ(outcome.status, RunStatus::Unsupported);
  EXPECT_TRUE(containsAll(outcome.reason, {"DistanceJoints[0]", "no rods"})) << outcome.reason;

  // Each fault of a table is refused with the file and the JSON path.
  const std::vector<std::pair<std::string, std::vector<std::string>>> faults = {
      {everything +
           R"(, {"feature": "joint", "support": "native"}, {"feature": "joints.x", "support": "native"})",
       {"probe.json", "features[9].feature", "joints.x"}},
      {everything, {"probe.json", "no entry covers \"joint.ball\""}},
      {everything + R"(, {"feature": "joint", "support": "approximated"})", {"features[8].text"}},
      {everything + R"(, {"feature": "joint", "support": "partly", "text": "t"})",
       {"features[8].support", R"("native", "approximated" or "unsupported")"}},
      {everything + R"(, {"feature": "joint", "support": "native", "method": ["probe.a"]})",
       {"features[8].method", "not a known key"}},
      {everything + R"(, {"feature": "joint", "support": "native", "methods": ["probe.c"]})",
       {"features[8].methods", "probe.c"}},
  };
  for (const auto& [features, expected] : faults) {
    write(features);
    try {
      readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
      ADD_FAILURE() << "accepted: " << features;
    } catch (const std::invalid_argument& e) {
      for (const std::string& part : expected)
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
            << part << " in " << e.what();
    }
  }
  fs::remove_all(folder);
}

TEST(EngineCatalogue, EveryRuleOfAnEntryIsRefusedNamingTheFileAndTheJsonPath) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-catalogue-rules-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  // A sound entry, its top-level keys extended by `extra` and its first method given `parameter`.
  const auto entry = [](const std::string& name, const std::string& extra,
                        const std::string& parameter) {
    return R"({"protocol": 1, "name": ")" + name + R"(", "command": ["x"], "defaultMethod": "e.a",
      "methods": [{"name": "e.a", "parameters": [)" +
           parameter + R"(]}, {"name": "e.b"}])" + extra + "}";
  };
  const std::string integer = R"({"name": "n", "kind": "integer", "default": 3, "min": 1})";
  std::ofstream(folder / "e.json") << entry("e", R"(, "runMethods": ["e.b", "e.a"])", integer);
  ASSERT_EQ(readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"}).size(), 1u);
  // Rules of docs/schemas/catalogue.schema.json, then the ones only the reader can check.
  const std::vector<std::pair<std::string, std::vector<std::string>>> faults = {
      {entry("My Engine", "", integer), {"name: expected a string matching"}},
      {entry("e", R"(, "colour": "red")", integer), {"colour: not a known key"}},
      {entry("e", R"(, "runMethods": ["e.a", "e.a"])", integer),
       {"runMethods[1]: expected a value not already in runMethods[0]"}},
      {entry("e", "", R"({"name": "c", "kind": "choice", "default": "x"})"),
       {"methods[0].parameters[0].choices: missing (required)"}},
      {entry("e", "", R"({"name": "n", "kind": "integer", "default": 1.5})"),
       {"methods[0].parameters[0].default: expected an integer, got 1.5"}},
      {entry("e", "", R"({"name": "n", "kind": "integer", "default": 0, "min": 1})"),
       {"methods[0].parameters[0].default: expected a default within its own declaration"}},
      {entry("f", "", integer), {R"(methods[0].name: expected a name starting with "f.")"}},
      {entry("e", R"(, "runMethods": ["e.c"])", integer),
       {R"(runMethods[0]: expected one of this entry's methods, got "e.c")"}},
  };
  for (const auto& [text, expected] : faults) {
    std::ofstream(folder / "e.json") << text;
    try {
      readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind((folder / "e.json").string() + ": ", 0), 0u) << message;
      for (const std::string& part : expected)
        EXPECT_NE(message.find(part), std::string::npos) << part << " in " << message;
    }
  }
  fs::remove_all(folder);
}

TEST(EngineCatalogue, TheSchemaDeclaresTheProtocolVersionsTheHostSpeaks) {
  const nlohmann::json schema = projectSchema("catalogue.schema.json");
  EXPECT_EQ(schema.at("properties").at("protocol").at("const"), kExternalProtocolVersion);
  EXPECT_EQ(schema.at("properties").at("serve").at("properties").at("protocol").at("const"),
            kExternalServeProtocolVersion);
}

TEST(EngineCatalogue, TheVariableAddsEnginesToTheShippedOnes) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-catalogue-add-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder / "a");
  fs::create_directories(folder / "b");
  const auto write = [](const fs::path& file, const std::string& name) {
    std::ofstream(file) << R"({"protocol": 1, "name": ")" << name
                        << R"(", "command": ["{python}", "engine.py"], "defaultMethod": ")" << name
                        << R"(.a", "methods": [{"name": ")" << name
                        << R"(.a", "description": "d", "parameters": []}]})";
  };
  write(folder / "a" / "first.json", "user-first");
  write(folder / "b" / "second.json", "user-second");
  const std::string list = (folder / "a").string() + ":" + (folder / "b").string();
  const EngineRegistry engines = standardEngines([&](const char* name) -> const char* {
    return std::string(name) == "PBDVAL_ENGINE_CATALOGUE" ? list.c_str() : nullptr;
  });
  const std::vector<std::string> names = engines.engineNames();
  for (const char* expected : {"pbd", "pybullet", "mujoco-python", "user-first", "user-second"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  // A user's engine named like a shipped one is an error naming both folders, not a replacement.
  write(folder / "b" / "third.json", "pybullet");
  try {
    standardEngines([&](const char* name) -> const char* {
      return std::string(name) == "PBDVAL_ENGINE_CATALOGUE" ? list.c_str() : nullptr;
    });
    FAIL() << "a user's engine replaced a shipped one";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(containsAll(e.what(), {"'pybullet'", "PBDVAL_ENGINE_CATALOGUE", "another name"}))
        << e.what();
  }
  fs::remove_all(folder);
}

// --- status.json against its schema (docs/schemas/status.schema.json) ---------------------------

TEST_F(ExternalEngineTest, AStatusWithOnlyProtocolStatusAndReasonIsAnErrorNamingTheMissingKeys) {
  const RunOutcome outcome =
      run("cp " + restingTrajectory() + " \"$4/trajectory.csv\"; " +
          R"(printf '{"protocol": 1, "status": "ok", "reason": ""}' > "$4/status.json")");
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(
      outcome.reason, {"status.json", "unsupported: missing", "divergedAt: missing",
                       "engineVersion: missing", "contactMargin: missing", "status.schema.json"}))
      << outcome.reason;
}

TEST_F(ExternalEngineTest, AWronglyTypedStatusFieldIsAnErrorNamingItsJsonPath) {
  const RunOutcome outcome = run(
      "cp " + restingTrajectory() + " \"$4/trajectory.csv\"; " +
      R"(printf '{"protocol": 1, "status": "ok", "reason": "", "unsupported": [], "divergedAt": null, )"
      R"("engineVersion": "shell 1", "effectiveSettings": {"solver": {"kind": "pgs"}}, )"
      R"("integratorStepsPerSceneStep": 1, "contactMargin": -1}' > "$4/status.json")");
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(outcome.reason,
                          {"effectiveSettings.solver: expected a number, a boolean or a string",
                           "contactMargin: expected a number >= 0, got -1"}))
      << outcome.reason;
}

// --- Persistent engines: runs through a server (serve protocol 1) ------------------------------

/// A Python engine served by pbdval.protocol.serve_runs; what each run does is chosen by the
/// file `mode` beside it: ok (copies `trajectory.csv` beside it, status ok), crash (SIGSEGV),
/// hang. Every run records its own pid and its parent's (the server's); a run that finds the
/// state an earlier run left in the module reports an error.
const char* kServedEngine = R"(import os, shutil, signal, sys, time
from pathlib import Path
from pbdval import protocol as pp

HERE = Path(__file__).resolve().parent
earlier_runs: list[int] = []

def main(argv):
    args = pp.parse_arguments(argv, "served test engine")
    mode = (HERE / "mode").read_text().strip()
    (HERE / "server.pid").write_text(str(os.getppid()))
    (HERE / "run.pid").write_text(str(os.getpid()))
    if mode == "crash":
        os.kill(os.getpid(), signal.SIGSEGV)
    if mode == "hang":
        time.sleep(300)
    if earlier_runs:
        pp.write_status(args.out, pp.Status("error", reason="state left by an earlier run", engine_version="t 1"))
        return 0
    earlier_runs.append(1)
    shutil.copy(HERE / "trajectory.csv", args.out / "trajectory.csv")
    pp.write_status(args.out, pp.Status("ok", engine_version="t 1"))
    return 0

if sys.argv[1:2] == ["--serve"]:
    sys.exit(pp.serve_runs(sys.argv[2:], main, "served test engine"))
sys.exit(main(sys.argv[1:]))
)";

class ServedEngineTest : public ExternalEngineTest {
 protected:
  void SetUp() override {
    ExternalEngineTest::SetUp();
    std::ofstream(folder_ / "engine.py") << kServedEngine;
    fs::copy_file(restingTrajectory(), folder_ / "trajectory.csv");
    // A short folder: a Unix socket's path has at most 107 bytes.
    serverFolder_ = fs::temp_directory_path() / ("pbdval-serve-test-" + std::to_string(::getpid()));
    fs::remove_all(serverFolder_);
    server_ = startExternalServer("py", command({"--serve"}), serverFolder_.string());
  }
  void TearDown() override {
    server_.reset();
    fs::remove_all(serverFolder_);
    ExternalEngineTest::TearDown();
  }

  ExternalCommand command(const std::vector<std::string>& extra = {}) const {
    ExternalCommand c{{projectPython(), (folder_ / "engine.py").string()},
                      folder_.string(),
                      std::string(PBDVAL_SOURCE_DIR) + "/python"};
    c.argv.insert(c.argv.end(), extra.begin(), extra.end());
    return c;
  }

  RunOutcome served(const std::string& mode, double limit = 30) {
    std::ofstream(folder_ / "mode") << mode << "\n";
    ExternalEngine engine("py", command(), {}, serverFolder_.string());
    Method method;
    method.name = "py.test";
    return runSimulation(engine, scene_, method, length_, {}, limit);
  }

  fs::path serverFolder_;
  std::unique_ptr<EngineServer> server_;
};

TEST_F(ServedEngineTest, RunsGoToOneServerEachInAFreshChild) {
  ASSERT_TRUE(server_->running());
  const RunOutcome first = served("ok");
  ASSERT_EQ(first.status, RunStatus::Ok) << first.reason;
  const pid_t server = recordedPid(folder_ / "server.pid");
  const pid_t firstRun = recordedPid(folder_ / "run.pid");
  // The second run would be an error had it seen the first one's module state.
  const RunOutcome second = served("ok");
  ASSERT_EQ(second.status, RunStatus::Ok) << second.reason;
  EXPECT_EQ(recordedPid(folder_ / "server.pid"), server);
  EXPECT_NE(recordedPid(folder_ / "run.pid"), firstRun);
  EXPECT_NE(server, firstRun);
}

TEST_F(ServedEngineTest, AServedRunGivesWhatTheSingleShotRunGives) {
  const RunOutcome viaServer = served("ok");
  ASSERT_EQ(viaServer.status, RunStatus::Ok) << viaServer.reason;
  ExternalEngine single("py", command());
  Method method;
  method.name = "py.test";
  std::vector<State> singleSamples;
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& s) { singleSamples.push_back(s); };
  std::vector<State> servedSamples;
  RunCallbacks servedCallbacks;
  servedCallbacks.onSample = [&](const State& s) { servedSamples.push_back(s); };
  ExternalEngine viaServerAgain("py", command(), {}, serverFolder_.string());
  const RunOutcome a = runSimulation(single, scene_, method, length_, callbacks, 30);
  const RunOutcome b = runSimulation(viaServerAgain, scene_, method, length_, servedCallbacks, 30);
  ASSERT_EQ(a.status, RunStatus::Ok) << a.reason;
  ASSERT_EQ(b.status, RunStatus::Ok) << b.reason;
  ASSERT_EQ(singleSamples.size(), servedSamples.size());
  for (std::size_t k = 0; k < singleSamples.size(); ++k)
    for (std::size_t i = 0; i < singleSamples[k].bodies.size(); ++i)
      EXPECT_EQ(singleSamples[k].bodies[i].position, servedSamples[k].bodies[i].position);
  EXPECT_EQ(a.facts.engineVersion, b.facts.engineVersion);
}

TEST_F(ServedEngineTest, ACrashingRunDoesNotTakeDownTheNext) {
  const RunOutcome crash = served("crash");
  EXPECT_EQ(crash.status, RunStatus::Error);
  EXPECT_TRUE(containsAll(crash.reason, {"signal 11"})) << crash.reason;
  EXPECT_TRUE(server_->running());
  const RunOutcome next = served("ok");
  EXPECT_EQ(next.status, RunStatus::Ok) << next.reason;
}

TEST_F(ServedEngineTest, AHangingRunIsATimeoutItsChildIsKilledAndTheServerGoesOn) {
  const RunOutcome hang = served("hang", /*limit=*/1.0);
  EXPECT_EQ(hang.status, RunStatus::Timeout) << hang.reason;
  EXPECT_LT(hang.wallTime, 10.0);
  EXPECT_FALSE(stillRunsAfterWaiting(recordedPid(folder_ / "run.pid")));
  EXPECT_TRUE(server_->running());
  const RunOutcome next = served("ok");
  EXPECT_EQ(next.status, RunStatus::Ok) << next.reason;
}

TEST_F(ServedEngineTest, SIGTERMDuringAServedRunIsTakenAtOnceItsChildKilledAndThrown) {
  // The runner sleeps in poll() until the reply, an interrupt or the deadline (no wall-time
  // limit here: no deadline); the interrupt must wake it, not the poll's one-second cap.
  std::ofstream(folder_ / "mode") << "hang\n";
  fs::remove(folder_ / "run.pid");
  std::fflush(nullptr);
  const pid_t runner = ::fork();
  if (runner == 0) {
    ExternalEngine engine("py", command(), {}, serverFolder_.string());
    Method method;
    method.name = "py.test";
    try {
      runSimulation(engine, scene_, method, length_, {}, 0);
    } catch (const SignalInterrupt& e) {
      ::_exit(10 + e.signal());
    } catch (...) {
    }
    ::_exit(99);
  }
  ASSERT_GT(runner, 0);
  const pid_t child = recordedPid(folder_ / "run.pid");
  ASSERT_GT(child, 0);
  const KillAtExit guard{child};
  const auto sent = std::chrono::steady_clock::now();
  ::kill(runner, SIGTERM);
  const int status = waitBounded(runner);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_TRUE(WIFEXITED(status)) << "the runner died of the signal instead of taking it";
  EXPECT_EQ(WEXITSTATUS(status), 10 + SIGTERM);
  // Taken when it is pending, not at the poll's 1 s cap: half of that tells the two apart
  // (the runner's own work after the signal, killing the child's group, is milliseconds).
  EXPECT_LT(seconds, 0.5);
  EXPECT_FALSE(stillRunsAfterWaiting(child));
  EXPECT_TRUE(server_->running());
}

TEST_F(ServedEngineTest, AServerThatCannotStartMakesItsRunsErrorsQuotingItsStandardError) {
  server_.reset();
  const ExternalCommand broken{
      {"sh", "-c", "echo 'ImportError: No module named engine_library' >&2; exit 1", "server"},
      folder_.string(),
      ""};
  server_ = startExternalServer("py", broken, serverFolder_.string());
  EXPECT_FALSE(server_->running());
  const RunOutcome outcome = served("ok");
  EXPECT_EQ(outcome.status, RunStatus::Error);
  EXPECT_TRUE(
      containsAll(outcome.reason, {"server", "ImportError: No module named engine_library"}))
      << outcome.reason;
}

TEST_F(ServedEngineTest, ServersLaunchedSideBySideStartTogetherAndServeOnceAwaited) {
  // Each server first sleeps 2 s, then starts: awaited one after the other, as servers were
  // started before, the two would take at least 4 s; launched side by side, about 2 s plus the
  // interpreters' start.
  server_.reset();  // the fixture's, on the same socket
  ExternalCommand slow = command({"--serve"});
  slow.argv.insert(slow.argv.begin(), {"sh", "-c", "sleep 2; exec \"$@\"", "server"});
  const fs::path otherFolder = serverFolder_.string() + "-b";
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<EngineServer> first = launchExternalServer("py", slow, serverFolder_.string());
  std::unique_ptr<EngineServer> second = launchExternalServer("py", slow, otherFolder.string());
  const double launched =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(launched, 1.0);  // neither launch waited for its 2 s sleep
  first->awaitListening();
  second->awaitListening();
  const double listening =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(first->running());
  EXPECT_TRUE(second->running());
  EXPECT_GE(listening, 2.0);   // the sleep itself
  EXPECT_LT(listening, 4.0);   // not one after the other
  server_ = std::move(first);  // the fixture's runs go to the first
  const RunOutcome outcome = served("ok");
  EXPECT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  second.reset();
  fs::remove_all(otherFolder);
}

/// The shipped Python engines, served and single-shot, on the same case: the same numbers, to
/// the bit (the served run is the single-shot run in a forked child).
TEST(ServedShippedEngines, PybulletAndMujocoGiveBitwiseTheSameTrajectoryServedAsSingleShot) {
  const EngineRegistry engines =
      standardEngines([](const char*) -> const char* { return nullptr; });
  const pbd::Scene scene =
      pbd::loadScene(std::string(PBDVAL_SOURCE_DIR) + "/cases/double_pendulum.json").scene;
  const fs::path serverFolder =
      fs::temp_directory_path() / ("pbdval-serve-shipped-" + std::to_string(::getpid()));
  for (const char* name : {"pybullet", "mujoco-python"}) {
    const EngineEntry& entry = engines.engine(name);
    ASSERT_TRUE(entry.startServer) << name << " declares no serve command";
    const std::unique_ptr<EngineServer> server = entry.startServer(serverFolder.string());
    server->awaitListening();
    ASSERT_TRUE(server->running()) << name;
    EngineOptions options;
    options.serverFolder = serverFolder.string();
    const Method method = engines.resolve(entry.defaultMethod);
    std::vector<State> single, served;
    RunCallbacks a, b;
    a.onSample = [&](const State& s) { single.push_back(s); };
    b.onSample = [&](const State& s) { served.push_back(s); };
    const RunOutcome singleRun =
        runSimulation(*entry.make(EngineOptions{}), scene, method, {0.5, 0}, a, 120);
    const RunOutcome servedRun =
        runSimulation(*entry.make(options), scene, method, {0.5, 0}, b, 120);
    ASSERT_EQ(singleRun.status, RunStatus::Ok) << name << ": " << singleRun.reason;
    ASSERT_EQ(servedRun.status, RunStatus::Ok) << name << ": " << servedRun.reason;
    ASSERT_EQ(single.size(), served.size()) << name;
    for (std::size_t k = 0; k < single.size(); ++k)
      for (std::size_t i = 0; i < single[k].bodies.size(); ++i) {
        const BodyState &x = single[k].bodies[i], &y = served[k].bodies[i];
        EXPECT_TRUE(x.position == y.position && x.rotation.coeffs() == y.rotation.coeffs() &&
                    x.velocity == y.velocity && x.angularVelocity == y.angularVelocity)
            << name << ": sample " << k << " body " << i;
      }
    EXPECT_EQ(singleRun.settings, servedRun.settings) << name;
  }
  fs::remove_all(serverFolder);
}

// --- The catalogue: relative commands, serve ---------------------------------------------------

TEST(EngineCatalogue, CommandsAreRelativeToTheCatalogueFile) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-catalogue-relative-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder / "engines" / "bin");
  // The engine reports, as its engine version, the folder it runs in.
  std::ofstream(folder / "engines" / "bin" / "engine.sh")
      << "printf '{\"protocol\": 1, \"status\": \"unsupported\", \"reason\": \"r\", "
         "\"unsupported\": "
         "[\"everything\"], \"divergedAt\": null, \"engineVersion\": \"%s\", "
         "\"effectiveSettings\": {}, "
         "\"integratorStepsPerSceneStep\": 1, \"contactMargin\": null}' \"$(pwd -P)\" > "
         "\"$4/status.json\"\n";
  std::ofstream(folder / "engines" / "relative.json")
      << R"({"protocol": 1, "name": "relative", "command": ["sh", "./bin/engine.sh"],
            "defaultMethod": "relative.a", "methods": [{"name": "relative.a", "parameters": []}]})";
  const std::string list = (folder / "engines").string();
  // From another working folder: the command is found beside the catalogue all the same.
  const fs::path before = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  const EngineRegistry engines = standardEngines([&](const char* name) -> const char* {
    return std::string(name) == "PBDVAL_ENGINE_CATALOGUE" ? list.c_str() : nullptr;
  });
  const pbd::Scene scene = pbd::parseScene(kScene, (folder / "scene.json").string()).scene;
  const RunOutcome outcome = runSimulation(*engines.make("relative"), scene,
                                           engines.resolve("relative.a"), {0.1, 0}, {}, 10);
  fs::current_path(before);
  EXPECT_EQ(outcome.status, RunStatus::Unsupported) << outcome.reason;
  EXPECT_EQ(outcome.facts.engineVersion, fs::canonical(folder / "engines").string());
  fs::remove_all(folder);
}

TEST(EngineCatalogue, AServeEntryOfAnotherProtocolIsAnErrorNamingItsPath) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-catalogue-serve-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder / "served.json") << R"({"protocol": 1, "name": "served",
    "command": ["{python}", "engine.py"], "serve": {"protocol": 2, "command": ["{python}", "engine.py", "--serve"]},
    "defaultMethod": "served.a", "methods": [{"name": "served.a", "parameters": []}]})";
  try {
    readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
    FAIL() << "serve protocol 2 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(containsAll(e.what(), {"served.json", "serve.protocol", "expected 1"})) << e.what();
  }
  std::ofstream(folder / "served.json") << R"({"protocol": 1, "name": "served",
    "command": ["{python}", "engine.py"], "serve": {"protocol": 1, "command": ["{python}", "engine.py", "--serve"]},
    "defaultMethod": "served.a", "methods": [{"name": "served.a", "parameters": []}]})";
  const std::vector<EngineEntry> entries =
      readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_TRUE(bool(entries[0].startServer));
  // runsPerChild (docs/external-engines.md#children-that-serve-several-runs): an integer >= 1.
  for (const std::string bad : {"0", "2.5", "\"50\""}) {
    std::ofstream(folder / "served.json") << R"({"protocol": 1, "name": "served",
      "command": ["{python}", "engine.py"], "serve": {"protocol": 1, "command": ["{python}", "engine.py", "--serve"], "runsPerChild": )"
                                          << bad << R"(},
      "defaultMethod": "served.a", "methods": [{"name": "served.a", "parameters": []}]})";
    try {
      readEngineCatalogue(folder.string(), {"/venv/python", "/src/python"});
      FAIL() << "runsPerChild " << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_TRUE(containsAll(e.what(), {"served.json", "serve.runsPerChild"})) << e.what();
    }
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace pbdval
