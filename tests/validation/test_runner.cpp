// The runner: isolation of runs (crash, hang, throw, NaN each get their status while the
// others complete), run planning, and the results file round trip.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "engines/selftest_engine.h"
#include "validation/io/results.h"
#include "validation/io/trajectory.h"
#include "validation/run/run_execution.h"
#include "validation/run/run_plan.h"
#include "validation/run/run_record.h"
#include "validation/run/run_scheduler.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;

const std::string kHinge = std::string(PBDVAL_SOURCE_DIR) + "/cases/joint_hinge.json";

fs::path scratch(const std::string& name) {
  const fs::path folder =
      fs::temp_directory_path() / ("pbdval-test-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

RunRequest request(const std::string& engine, const std::string& method,
                   const std::string& caseFile = kHinge) {
  RunRequest r;
  r.caseName = "joint_hinge";
  r.caseFile = caseFile;
  r.engine = engine;
  r.method = method;
  return r;
}

TEST(Runner, EachFailureGetsItsStatusAndTheOtherRunsComplete) {
  const fs::path folder = scratch("isolation");
  std::vector<RunRequest> requests = {
      request("selftest", "selftest.crash"), request("pbd", "pbd"),
      request("selftest", "selftest.hang"),  request("selftest", "selftest.throw"),
      request("selftest", "selftest.nan"),   request("selftest", "selftest.ok")};
  requests[1].trajectoryPath = (folder / "pbd.csv").string();
  requests[0].trajectoryPath = (folder / "crash.csv").string();
  RunScheduler scheduler(testRegistry(), 3, /*timeout=*/2.0, (folder / "scratch").string());
  std::size_t finished = 0;
  const std::vector<RunRecord> records =
      scheduler.runAll(requests, [&](const RunRecord&, std::size_t, std::size_t) { ++finished; });
  ASSERT_EQ(records.size(), requests.size());
  EXPECT_EQ(finished, requests.size());

  EXPECT_EQ(records[0].status, RunStatus::Error);
  // "engine process crashed with signal 11 (Segmentation fault)"; under AddressSanitizer, which
  // catches the SEGV itself, the child aborts (signal 6) or exits with ASan's status.
  EXPECT_EQ(records[0].reason.rfind("engine process ", 0), 0u) << records[0].reason;
  EXPECT_EQ(records[1].status, RunStatus::Ok) << records[1].reason;
  EXPECT_EQ(records[2].status, RunStatus::Timeout);
  EXPECT_NE(records[2].reason.find("wall-time limit of 2 s"), std::string::npos)
      << records[2].reason;
  EXPECT_EQ(records[3].status, RunStatus::Error);
  EXPECT_NE(records[3].reason.find("deliberate failure"), std::string::npos) << records[3].reason;
  EXPECT_EQ(records[4].status, RunStatus::Diverged);
  EXPECT_NE(records[4].reason.find("non-finite"), std::string::npos) << records[4].reason;
  EXPECT_EQ(records[5].status, RunStatus::Ok);

  // The ok run wrote its trajectory; the crashed one left no file, temporary or final.
  EXPECT_TRUE(fs::exists(folder / "pbd.csv"));
  for (const auto& entry : fs::directory_iterator(folder))
    EXPECT_EQ(entry.path().filename().string().find("crash.csv"), std::string::npos)
        << entry.path();
  fs::remove_all(folder);
}

// SIGTERM (or Ctrl-C's SIGINT) to a scheduler stops its workers at once and leaves neither the
// scratch folder nor a temporary trajectory behind; the command then exits with 128 + signal.
TEST(Runner, ASignalStopsTheWorkersAndRemovesTheirFiles) {
  const fs::path folder = scratch("signal");
  const pid_t scheduler = ::fork();
  ASSERT_GE(scheduler, 0);
  if (scheduler == 0) {
    std::vector<RunRequest> requests = {request("selftest", "selftest.hang"),
                                        request("selftest", "selftest.hang"),
                                        request("pbd", "pbd")};
    requests[0].trajectoryPath = (folder / "hang0.csv").string();
    requests[1].trajectoryPath = (folder / "hang1.csv").string();
    try {
      RunScheduler(testRegistry(), 2, /*timeout=*/60, (folder / "scratch").string())
          .runAll(requests, {});
    } catch (const RunInterrupted& e) {
      ::_exit(128 + e.signal());
    }
    ::_exit(0);
  }
  // Give both workers time to start and reach their hang (step 10 of a 5 ms scene).
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::kill(scheduler, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(scheduler, &status, 0), scheduler);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_LT(seconds, 5.0);  // at once: the 60 s run timeout played no part
  for (const auto& entry : fs::directory_iterator(folder))
    ADD_FAILURE() << "left behind: " << entry.path();
  fs::remove_all(folder);
}

// A limit far below what a run takes is a timeout even when the run ends between two checks.
TEST(Runner, ATinyTimeoutIsATimeoutNotOk) {
  const fs::path folder = scratch("tiny-timeout");
  const std::vector<RunRecord> records =
      RunScheduler(testRegistry(), 1, /*timeout=*/1e-3, (folder / "scratch").string())
          .runAll({request("pbd", "pbd")}, {});
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].status, RunStatus::Timeout) << records[0].reason;
  fs::remove_all(folder);
}

TEST(Runner, UnreadableCaseBecomesAnErrorNamingTheFile) {
  const fs::path folder = scratch("bad-case");
  const fs::path bad = folder / "bad.json";
  std::ofstream(bad) << "{ \"RigidBodies\": [ {\"geometryFile\": 3} ] }";
  const RunRecord record = executeRun(request("pbd", "pbd", bad.string()), testRegistry());
  EXPECT_EQ(record.status, RunStatus::Error);
  EXPECT_NE(record.reason.find("bad.json"), std::string::npos) << record.reason;
  EXPECT_NE(record.reason.find("RigidBodies[0].geometryFile"), std::string::npos) << record.reason;

  const RunPlan plan = planRuns({bad.string(), kHinge}, PlanOptions{}, testRegistry());
  ASSERT_EQ(plan.unreadable.size(), 1u);
  EXPECT_EQ(plan.unreadable[0].request.caseName, "bad");
  EXPECT_FALSE(plan.requests.empty());  // the readable case is still planned
  fs::remove_all(folder);
}

// A run with particles writes them beside its trajectory, in its format: every sample's
// particles, the same samples as the trajectory's (tet_bar: 99 particles, 2 s sampled every
// 0.01 s: 201 samples).
TEST(Runner, ParticlesAreWrittenBesideTheTrajectory) {
  EXPECT_EQ(particlePathFor("out/trajectories/c/pbd-pbd.xpbd.csv"),
            "out/trajectories/c/pbd-pbd.xpbd.particles.csv");
  EXPECT_EQ(particlePathFor("out/t/e-m.npy"), "out/t/e-m.particles.npy");
  const fs::path folder = scratch("particles");
  for (const char* extension : {".csv", ".npy"}) {
    RunRequest r = request("pbd", "pbd", std::string(PBDVAL_SOURCE_DIR) + "/cases/tet_bar.json");
    r.caseName = "tet_bar";
    r.trajectoryPath = (folder / (std::string("pbd") + extension)).string();
    const RunRecord record = executeRun(r, testRegistry());
    ASSERT_EQ(record.status, RunStatus::Ok) << record.reason;
    const Trajectory bodies = readTrajectory(r.trajectoryPath);
    const Trajectory particles = readParticleTrajectory(particlePathFor(r.trajectoryPath));
    ASSERT_EQ(particles.samples.size(), 201u) << extension;
    for (std::size_t k = 0; k < particles.samples.size(); ++k) {
      EXPECT_EQ(particles.samples[k].particles.size(), 99u);
      if (!bodies.samples.empty()) {
        EXPECT_EQ(particles.samples[k].time, bodies.samples[k].time);
      }
    }
  }
  // A scene without particles gets no particle file.
  RunRequest hinge = request("pbd", "pbd");
  hinge.trajectoryPath = (folder / "hinge.csv").string();
  ASSERT_EQ(executeRun(hinge, testRegistry()).status, RunStatus::Ok);
  EXPECT_FALSE(fs::exists(particlePathFor(hinge.trajectoryPath)));
  fs::remove_all(folder);
}

// A run of a rod writes its segments beside its trajectory too (rod_helix: 49 segments, 3 s
// sampled every 0.01 s: 301 samples, at the trajectory's times); other scenes get none.
TEST(Runner, RodSegmentsAreWrittenBesideTheTrajectory) {
  EXPECT_EQ(segmentPathFor("out/t/e-m.npy"), "out/t/e-m.segments.npy");
  const fs::path folder = scratch("segments");
  for (const char* extension : {".csv", ".npy"}) {
    RunRequest r = request("pbd", "pbd", std::string(PBDVAL_SOURCE_DIR) + "/cases/rod_helix.json");
    r.caseName = "rod_helix";
    r.trajectoryPath = (folder / (std::string("pbd") + extension)).string();
    ASSERT_EQ(executeRun(r, testRegistry()).status, RunStatus::Ok);
    const Trajectory particles = readParticleTrajectory(particlePathFor(r.trajectoryPath));
    const Trajectory segments = readSegmentTrajectory(segmentPathFor(r.trajectoryPath));
    ASSERT_EQ(segments.samples.size(), 301u) << extension;
    for (std::size_t k = 0; k < segments.samples.size(); ++k) {
      EXPECT_EQ(segments.samples[k].segments.size(), 49u);
      EXPECT_EQ(segments.samples[k].time, particles.samples[k].time);
    }
  }
  RunRequest hinge = request("pbd", "pbd");
  hinge.trajectoryPath = (folder / "hinge.csv").string();
  ASSERT_EQ(executeRun(hinge, testRegistry()).status, RunStatus::Ok);
  EXPECT_FALSE(fs::exists(segmentPathFor(hinge.trajectoryPath)));
  fs::remove_all(folder);
}

// The penetration metric subtracts the contact margin the engine reports in its typed run
// facts (an engine that lets resting contacts overlap by m is not penalised for m). A box
// resting 3 mm deep in a static box, held there by selftest.ok: the FCL depth is 3 mm exactly.
TEST(Runner, PenetrationSubtractsTheMarginTheEngineReports) {
  const fs::path folder = scratch("margin");
  const fs::path scene = folder / "overlap.json";
  std::ofstream(scene) << R"({
    "Simulation": {"timeStepSize": 0.01, "gravitation": [0, 0, 0]},
    "RigidBodies": [
      {"id": 0, "isDynamic": false, "collisionObjectType": 2, "collisionObjectScale": [4, 1, 4],
       "translation": [0, -0.5, 0]},
      {"id": 1, "collisionObjectType": 2, "collisionObjectScale": [1, 1, 1],
       "translation": [0, 0.497, 0], "density": 1000}],
    "Validation": {"duration": 0.05}
  })";
  RunRequest r = request("selftest", "selftest.ok", scene.string());
  r.caseName = "overlap";
  const RunRecord none = executeRun(r, testRegistry());
  r.assignments = {"contactMargin=0.001"};
  const RunRecord margin = executeRun(r, testRegistry());
  ASSERT_EQ(none.status, RunStatus::Ok) << none.reason;
  ASSERT_EQ(margin.status, RunStatus::Ok) << margin.reason;
  EXPECT_EQ(margin.facts.contactMargin, 0.001);
  // Tolerance: the depth 0.5 - 0.497 is exact to a few ulp of 0.5 (1e-16); FCL's box-box
  // separating-axis depth adds round-off of the same order.
  EXPECT_NEAR(none.metrics.values.at("penetration_max"), 0.003, 1e-12);
  EXPECT_NEAR(margin.metrics.values.at("penetration_max"), 0.002, 1e-12);
  fs::remove_all(folder);
}

TEST(Runner, PlanSelectsEnginesAndMethods) {
  PlanOptions options;
  options.engines = {"pbd"};
  RunPlan plan = planRuns({kHinge}, options, testRegistry());
  // A case that names no PBD method runs the engine's run methods: both of the library's.
  ASSERT_EQ(plan.requests.size(), 2u);
  EXPECT_EQ(plan.requests[0].method, "pbd");
  EXPECT_EQ(plan.requests[1].method, "pbd.xpbd");
  EXPECT_EQ(plan.requests[0].trajectoryPath, "out/trajectories/joint_hinge/pbd-pbd.csv");
  EXPECT_EQ(plan.requests[1].trajectoryPath, "out/trajectories/joint_hinge/pbd-pbd.xpbd.csv");

  // Methods of engines not named in --engines run only when listed.
  options.engines = {"pbd", "selftest"};
  options.methods = {"selftest.nan"};
  plan = planRuns({kHinge}, options, testRegistry());
  ASSERT_EQ(plan.requests.size(), 2u);  // pbd's default (named engine) + the listed method
  EXPECT_EQ(plan.requests[0].method, "pbd");
  EXPECT_EQ(plan.requests[1].method, "selftest.nan");

  options.engines = {"pbd"};
  options.methods = {"selftest.ok"};
  EXPECT_THROW(planRuns({kHinge}, options, testRegistry()),
               std::invalid_argument);  // method of an unselected engine
  options.methods = {"no.such.method"};
  EXPECT_THROW(planRuns({kHinge}, options, testRegistry()), std::invalid_argument);
}

TEST(Runner, AMethodOfAnEngineRunByNameOnlySelectsItWithoutEngines) {
  // selftest runs by name only (runByDefault false): a plan without --engines leaves it out...
  PlanOptions options;
  RunPlan plan = planRuns({kHinge}, options, testRegistry());
  for (const RunRequest& r : plan.requests)
    EXPECT_NE(r.engine, "selftest");
  // ...and its method named in --methods alone is enough to run it.
  options.methods = {"pbd", "selftest.ok"};
  plan = planRuns({kHinge}, options, testRegistry());
  ASSERT_EQ(plan.requests.size(), 2u);
  EXPECT_EQ(plan.requests[0].method, "pbd");
  EXPECT_EQ(plan.requests[1].method, "selftest.ok");
}

TEST(Results, RoundTripKeepsEveryField) {
  RunRecord r;
  r.request = request("pbd", "pbd");
  r.request.assignments = {"subSteps=10"};
  r.status = RunStatus::Diverged;
  r.reason = "body 1 blew up";
  r.methodParameters = {{"subSteps", "10"}};
  r.settings = {{"timeStepSize", "0.005"}};
  r.facts.engineVersion = "test engine 1.0";
  r.facts.integratorStepsPerSceneStep = 10;
  r.facts.contactMargin = 2.5e-5;
  r.metrics.values = {
      {"energy_drift_max", 0.125}, {"wall_time_s", 1.5}, {"nan_metric", std::nan("")}};
  JointErrorSummary hinge;
  hinge.linearMax = 1e-3;
  hinge.linearRms = 5e-4;
  hinge.angularMax = 2e-2;
  hinge.joints = 3;
  r.metrics.jointErrorByType["hinge"] = hinge;
  r.metrics.notes = {"a note"};
  r.stateHash = "0123456789abcdef";
  r.reference = "analytic pendulum";

  ResultsFile file;
  file.metadata = currentMetadata("pbdval run test");
  file.cases["joint_hinge"].file = kHinge;
  CheckSpec check;
  check.metric = "energy_drift_max";
  check.max = 0.5;
  file.cases["joint_hinge"].checks.push_back(check);
  file.runs = {r};
  const fs::path folder = scratch("results");
  writeResults((folder / "results.json").string(), file);
  const ResultsFile back = readResults((folder / "results.json").string());

  ASSERT_EQ(back.runs.size(), 1u);
  const RunRecord& b = back.runs[0];
  EXPECT_EQ(b.request.assignments, r.request.assignments);
  EXPECT_EQ(b.status, r.status);
  EXPECT_EQ(b.reason, r.reason);
  EXPECT_EQ(b.settings, r.settings);
  EXPECT_EQ(b.facts.engineVersion, r.facts.engineVersion);
  EXPECT_EQ(b.facts.integratorStepsPerSceneStep, 10);
  EXPECT_EQ(b.facts.contactMargin, 2.5e-5);
  EXPECT_EQ(b.metrics.values.at("energy_drift_max"), 0.125);
  EXPECT_TRUE(std::isnan(b.metrics.values.at("nan_metric")));  // null in JSON
  EXPECT_EQ(b.metrics.jointErrorByType.at("hinge").joints, 3);
  EXPECT_EQ(b.stateHash, r.stateHash);
  EXPECT_EQ(back.metadata.commit, file.metadata.commit);
  EXPECT_EQ(back.cases.at("joint_hinge").checks.at(0).max, 0.5);

  std::ofstream(folder / "garbage.json") << "{\"schema\": \"something else\"}";
  EXPECT_THROW(readResults((folder / "garbage.json").string()), std::invalid_argument);
  fs::remove_all(folder);
}

/// Records that exercise every branch of a run's JSON form: angular and motor joint errors,
/// non-finite metrics, strings that need escaping or are not valid UTF-8, empty lists and maps.
std::vector<RunRecord> variedRecords() {
  std::vector<RunRecord> records;
  RunRecord plain;
  plain.request = request("bullet", "bullet");
  plain.status = RunStatus::Ok;
  records.push_back(plain);  // empty assignments, maps, notes and joint errors
  RunRecord full;
  full.request = request("pbd", "pbd.xpbd");
  full.request.assignments = {"subSteps=10", "timeStepSize=0.001"};
  full.request.trajectoryPath = "out/trajectories/joint_hinge/pbd-pbd.xpbd.csv";
  full.request.referenceMode = "fine";
  full.request.fineDivisor = 32;
  full.request.referenceStepSize = 1.0 / 3.0;
  full.request.sampleInterval = 1e-300;
  full.status = RunStatus::Suspect;
  full.reason = "quote \" backslash \\ tab \t newline \n bell \a é ✓ bad \xff\xfe byte";
  full.methodParameters = {{"subSteps", "10"}, {"Z-upper before lower", "x"}, {"é", "ü"}};
  full.settings = {{"timeStepSize", "0.005"}, {"gravity", "0 0 -9.81"}};
  full.facts.engineVersion = "PBD 1.0";
  full.facts.integratorStepsPerSceneStep = 10;
  full.facts.contactMargin = -0.0;
  full.metrics.values = {{"a", 1.0},   {"b", -2.5e-17},         {"c", 123456789.0},
                         {"d", 1e21},  {"e", std::nan("")},     {"f", HUGE_VAL},
                         {"g", 0.1},   {"h", 5e-324},           {"i", -1.7976931348623157e308},
                         {"j", 100.0}, {"wall_time_s", 0.0123}, {"\x01 control", 2.0}};
  JointErrorSummary hinge;
  hinge.linearMax = 1e-3;
  hinge.linearRms = 5e-4;
  hinge.hasAngular = true;
  hinge.angularMax = 2e-2;
  hinge.angularRms = std::nan("");
  hinge.joints = 3;
  JointErrorSummary motor = hinge;
  motor.trackingQuantity = "angular_velocity";
  motor.trackingMax = 0.25;
  motor.trackingRms = 0.125;
  JointErrorSummary ball;
  ball.linearMax = 7.0;
  ball.joints = 1;
  full.metrics.jointErrorByType = {{"hinge", hinge}, {"motor_hinge", motor}, {"ball", ball}};
  full.metrics.notes = {"first note", "second \"quoted\" note"};
  full.stateHash = "0123456789abcdef";
  full.reference = "fine: pbd.xpbd at h/32";
  records.push_back(full);
  return records;
}

TEST(Results, TheWrittenFileHasTheBytesOfTheWholeDocumentDumpedByNlohmann) {
  // The writer streams each record's text; the expected bytes are the whole document built as
  // one JSON value from recordJson and dumped by nlohmann (the form results.json always had).
  for (const std::size_t count : {std::size_t(0), std::size_t(1), std::size_t(5)}) {
    ResultsFile file;
    file.metadata = currentMetadata("pbdval run test");
    file.metadata.planDigest = "abc";
    file.cases["joint_hinge"].file = kHinge;
    file.cases["joint_hinge"].tolerances = {{"energy_drift_max", 1e-3}};
    const std::vector<RunRecord> varied = variedRecords();
    for (std::size_t i = 0; i < count; ++i)
      file.runs.push_back(varied[i % varied.size()]);
    nlohmann::json runs = nlohmann::json::array();
    for (const RunRecord& r : file.runs)
      runs.push_back(recordJson(r));
    nlohmann::json cases = nlohmann::json::object();
    for (const auto& [name, data] : file.cases)
      cases[name] = caseGateDataJson(data);
    const nlohmann::json document = {
        {"schema", "pbdval-results"},
        {"schemaVersion", file.schemaVersion},
        {"metadata", nlohmann::json::parse(metadataJsonText(file.metadata))},
        {"cases", cases},
        {"runs", runs}};
    const std::string expected =
        document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    const fs::path folder = scratch("results-bytes");
    writeResults((folder / "results.json").string(), file);
    std::ifstream in(folder / "results.json", std::ios::binary);
    const std::string written((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
    EXPECT_EQ(written, expected) << count << " runs";
    fs::remove_all(folder);
  }
}

/// A results document around `runs` (JSON text of the array), with `schema`.
std::string resultsText(const std::string& runs, const std::string& schema = "pbdval-results") {
  return "{\"cases\": {\"joint_hinge\": {}}, \"runs\": " + runs + ", \"schema\": \"" + schema +
         "\", \"schemaVersion\": 1}";
}

std::string errorOf(const std::function<void()>& read) {
  try {
    read();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(Results, TheReaderReportsTheDocumentBeforeItsRunsAndTheFirstBadRunInOrder) {
  // The runs are converted while the text is parsed, before the keys after them ("schema"):
  // their errors still come in the order of a reader that sees the whole document first.
  const std::string good = toJsonText(variedRecords()[0]);
  std::string bad = good;
  bad.replace(bad.find("\"ok\""), 4, "\"fine\"");  // an unknown status
  std::string otherCase = good;
  otherCase.replace(otherCase.find("\"joint_hinge\""), 13, "\"no_case\"");
  const auto read = [](const std::string& text) {
    return errorOf([&] { (void)parseResultsText(text, "r.json"); });
  };
  EXPECT_NE(read(resultsText("[" + good + "," + bad + "]", "other"))
                .find("expected a pbdval results file"),
            std::string::npos);
  EXPECT_NE(
      read(resultsText("[" + good + "," + bad + "]")).find("r.json: runs[1]: status: unknown"),
      std::string::npos);
  EXPECT_NE(read(resultsText("[" + otherCase + "," + bad + "]"))
                .find("r.json: runs[0]: case \"no_case\" has no entry"),
            std::string::npos);
  EXPECT_NE(read(resultsText("[" + good + ", 7]")).find("r.json: runs[1]"), std::string::npos);
  EXPECT_NE(read(resultsText("{\"x\": 1}")).find("r.json: runs: expected an array"),
            std::string::npos);
  // A syntax error after good and bad runs is reported as such.
  EXPECT_NE(read(resultsText("[" + good + "," + bad + "]") + "}").find("r.json: not valid JSON"),
            std::string::npos);
  // So is nesting past the limit inside a run.
  const std::string deep = std::string(300, '[') + std::string(300, ']');
  std::string nested = good;
  nested.replace(nested.find("\"notes\": []"), 11, "\"notes\": " + deep);
  EXPECT_NE(read(resultsText("[" + nested + "]")).find("nested deeper than"), std::string::npos);
}

TEST(Results, ARunsKeyGivenTwiceKeepsItsLastValueAsTheWholeDocumentDoes) {
  const std::string good = toJsonText(variedRecords()[0]);
  const std::string twice = "{\"cases\": {\"joint_hinge\": {}}, \"runs\": [" + good + "," + good +
                            "], \"runs\": [" + good +
                            "], \"schema\": \"pbdval-results\", "
                            "\"schemaVersion\": 1}";
  // nlohmann's document keeps the last value of a repeated key.
  ASSERT_EQ(nlohmann::json::parse(twice).at("runs").size(), 1u);
  EXPECT_EQ(parseResultsText(twice, "r.json").runs.size(), 1u);
  const std::string thenEmpty = "{\"cases\": {\"joint_hinge\": {}}, \"runs\": [" + good +
                                "], \"runs\": [], \"schema\": \"pbdval-results\", "
                                "\"schemaVersion\": 1}";
  EXPECT_EQ(parseResultsText(thenEmpty, "r.json").runs.size(), 0u);
}

}  // namespace
}  // namespace pbdval
