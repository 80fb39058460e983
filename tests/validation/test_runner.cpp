// The runner: isolation of runs (crash, hang, throw, NaN each get their status while the
// others complete), run planning, and the results file round trip.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "validation/results.h"
#include "validation/run_plan.h"
#include "validation/run_record.h"

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
  RunScheduler scheduler(3, /*timeout=*/2.0, (folder / "scratch").string());
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

TEST(Runner, UnreadableCaseBecomesAnErrorNamingTheFile) {
  const fs::path folder = scratch("bad-case");
  const fs::path bad = folder / "bad.json";
  std::ofstream(bad) << "{ \"RigidBodies\": [ {\"geometryFile\": 3} ] }";
  const RunRecord record = executeRun(request("pbd", "pbd", bad.string()));
  EXPECT_EQ(record.status, RunStatus::Error);
  EXPECT_NE(record.reason.find("bad.json"), std::string::npos) << record.reason;
  EXPECT_NE(record.reason.find("RigidBodies[0].geometryFile"), std::string::npos) << record.reason;

  const RunPlan plan = planRuns({bad.string(), kHinge}, PlanOptions{});
  ASSERT_EQ(plan.unreadable.size(), 1u);
  EXPECT_EQ(plan.unreadable[0].request.caseName, "bad");
  EXPECT_FALSE(plan.requests.empty());  // the readable case is still planned
  fs::remove_all(folder);
}

TEST(Runner, PlanSelectsEnginesAndMethods) {
  PlanOptions options;
  options.engines = {"pbd"};
  RunPlan plan = planRuns({kHinge}, options);
  ASSERT_EQ(plan.requests.size(), 1u);
  EXPECT_EQ(plan.requests[0].method, "pbd");
  EXPECT_EQ(plan.requests[0].trajectoryPath, "out/trajectories/joint_hinge/pbd-pbd.csv");

  // Methods of engines not named in --engines run only when listed.
  options.engines = {"pbd", "selftest"};
  options.methods = {"selftest.nan"};
  plan = planRuns({kHinge}, options);
  ASSERT_EQ(plan.requests.size(), 2u);  // pbd's default (named engine) + the listed method
  EXPECT_EQ(plan.requests[0].method, "pbd");
  EXPECT_EQ(plan.requests[1].method, "selftest.nan");

  options.engines = {"pbd"};
  options.methods = {"selftest.ok"};
  EXPECT_THROW(planRuns({kHinge}, options),
               std::invalid_argument);  // method of an unselected engine
  options.methods = {"no.such.method"};
  EXPECT_THROW(planRuns({kHinge}, options), std::invalid_argument);
}

TEST(Results, RoundTripKeepsEveryField) {
  RunRecord r;
  r.request = request("pbd", "pbd");
  r.request.assignments = {"subSteps=10"};
  r.status = RunStatus::Diverged;
  r.reason = "body 1 blew up";
  r.methodParameters = {{"subSteps", "10"}};
  r.settings = {{"timeStepSize", "0.005"}};
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

}  // namespace
}  // namespace pbdval
