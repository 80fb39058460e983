// Results folders written as one transaction (validation/io/results_folder.h), outputs that would
// overwrite inputs (validation/io/atomic_file.h checkOutputsAreNotInputs), the one "did you mean"
// (pbd/io/suggestion.h) and the --set checks against what each engine honours
// (validation/run/overrides.h checkAssignments).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "adapters/registry.h"
#include "engines/selftest_engine.h"
#include "pbd/io/suggestion.h"
#include "validation/io/atomic_file.h"
#include "validation/io/results_folder.h"
#include "validation/run/overrides.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;

class ResultsFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/pbdval-results-folder-XXXXXX";
    ASSERT_NE(::mkdtemp(pattern), nullptr);
    root_ = pattern;
  }
  void TearDown() override { fs::remove_all(root_); }

  std::string path(const std::string& name) const { return (root_ / name).string(); }
  static void write(const std::string& file, const std::string& text) {
    fs::create_directories(fs::path(file).parent_path());
    std::ofstream(file) << text;
  }
  static std::string read(const std::string& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  fs::path root_;
};

TEST_F(ResultsFolderTest, CommitReplacesTheOwnedEntriesAndKeepsTheOthers) {
  const std::string out = path("out");
  write(out + "/results.json", "old");
  write(out + "/trajectories/a/old.csv", "old trajectory");
  write(out + "/notes.txt", "the user's");
  {
    ResultsFolder folder(out, "pbdval run");
    write(folder.staging() + "/trajectories/b/new.csv", "new trajectory");
    write(folder.staging() + "/results.json", "new");
    EXPECT_EQ(folder.finalPath(folder.staging() + "/trajectories/b/new.csv"),
              out + "/trajectories/b/new.csv");
    folder.commit({"trajectories", "results.json"}, "results.json");
    EXPECT_FALSE(fs::exists(folder.staging()));
  }
  EXPECT_EQ(read(out + "/results.json"), "new");
  EXPECT_EQ(read(out + "/trajectories/b/new.csv"), "new trajectory");
  EXPECT_FALSE(fs::exists(out + "/trajectories/a/old.csv"));  // not left unlisted
  EXPECT_EQ(read(out + "/notes.txt"), "the user's");
}

TEST_F(ResultsFolderTest, WithoutCommitThePreviousResultsStayAndNothingIsLeft) {
  const std::string out = path("out");
  write(out + "/results.json", "old");
  write(out + "/trajectories/a/old.csv", "old trajectory");
  std::string staging;
  {
    ResultsFolder folder(out, "pbdval run");
    staging = folder.staging();
    write(staging + "/trajectories/a/old.csv", "new trajectory");
  }  // an error or a signal: destroyed without commit
  EXPECT_EQ(read(out + "/results.json"), "old");
  EXPECT_EQ(read(out + "/trajectories/a/old.csv"), "old trajectory");
  EXPECT_FALSE(fs::exists(staging));
}

TEST_F(ResultsFolderTest, AFolderItCreatedIsRemovedAgainWhenNothingWasCommitted) {
  const std::string out = path("new/deeper/out");
  { ResultsFolder folder(out, "pbdval sweep"); }
  EXPECT_FALSE(fs::exists(path("new")));
  EXPECT_TRUE(fs::exists(root_));
}

TEST_F(ResultsFolderTest, ASecondWriterIsRefusedNamingTheFirst) {
  const std::string out = path("out");
  ResultsFolder first(out, "pbdval run");
  try {
    ResultsFolder second(out, "pbdval run");
    FAIL() << "a second writer was let in";
  } catch (const FolderBusy& e) {
    EXPECT_NE(std::string(e.what()).find("another pbdval run is writing here (pid " +
                                         std::to_string(::getpid()) + ")"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ResultsFolderTest, StagingFoldersOfKilledCommandsAreRemoved) {
  const std::string out = path("out");
  write(out + "/.pbdval-staging-999999/trajectories/x.csv", "from a killed run");
  ResultsFolder folder(out, "pbdval run");
  EXPECT_FALSE(fs::exists(out + "/.pbdval-staging-999999"));
}

TEST_F(ResultsFolderTest, ForeignResultsAreThoseOfAnotherSetOfRuns) {
  const std::string file = path("results.json");
  EXPECT_FALSE(foreignResults(file, {}));  // no file: nothing to lose
  write(file,
        R"({"runs": [{"case": "a", "engine": "pbd", "method": "pbd", "assignments": []},
                     {"case": "b", "engine": "ode", "method": "ode.quickstep", "assignments": ["x=1"]}]})");
  const RunKey a{"a", "pbd", "pbd", {}}, b{"b", "ode", "ode.quickstep", {"x=1"}};
  EXPECT_FALSE(foreignResults(file, {b, a}));  // the same runs in another order
  const auto fewer = foreignResults(file, {a});
  ASSERT_TRUE(fewer);
  EXPECT_NE(fewer->find("holds 2 runs of another plan"), std::string::npos) << *fewer;
  EXPECT_NE(fewer->find("b ode/ode.quickstep x=1 is not in this command's plan"), std::string::npos)
      << *fewer;
  EXPECT_TRUE(foreignResults(file, {a, RunKey{"b", "ode", "ode.quickstep", {"x=2"}}}));
  write(
      file,
      R"({"runs": [{"case": "a", "engine": "pbd", "method": "pbd", "assignments": ["x=1", "y=2"]}]})");
  EXPECT_FALSE(foreignResults(file, {RunKey{"a", "pbd", "pbd", {"y=2", "x=1"}}}));  // --set order
  write(file, "not json");
  const auto unreadable = foreignResults(file, {a});
  ASSERT_TRUE(unreadable);
  EXPECT_NE(unreadable->find("not a pbdval results file"), std::string::npos);
}

TEST_F(ResultsFolderTest, AnOutputIsComparedWithTheInputsByDeviceAndInode) {
  const std::string scene = path("scene.json");
  write(scene, "{}");
  ASSERT_EQ(::link(scene.c_str(), path("hard.json").c_str()), 0);
  fs::create_symlink(scene, path("soft.json"));
  for (const std::string& name :
       {scene, path("hard.json"), path("soft.json"), path("./x/../scene.json")})
    EXPECT_THROW(checkOutputsAreNotInputs({{"--out", name}}, {{"the scene", scene}}),
                 std::invalid_argument)
        << name;
  EXPECT_NO_THROW(checkOutputsAreNotInputs({{"--out", path("other.csv")}}, {{"the scene", scene}}));
  // Two outputs that do not exist yet but name one file.
  EXPECT_THROW(
      checkOutputsAreNotInputs({{"--out", path("a.csv")}, {"--particles", path("./a.csv")}}, {}),
      std::invalid_argument);
  // Devices are written in place, never replaced: two outputs may both be /dev/null.
  EXPECT_NO_THROW(
      checkOutputsAreNotInputs({{"--out", "/dev/null"}, {"--particles", "/dev/null"}}, {}));
  EXPECT_NO_THROW(checkOutputsAreNotInputs({{"--out", ""}}, {{"the scene", scene}}));
}

TEST(DidYouMean, SuggestsTheClosestNameWithinTheLimit) {
  const std::vector<std::string> names = {"timeStepSize", "subSteps", "maxIterations"};
  EXPECT_EQ(pbd::closestName("timeStepsize", names), "timeStepSize");    // case only
  EXPECT_EQ(pbd::closestName("subStep", names), "subSteps");             // one deletion
  EXPECT_EQ(pbd::closestName("maxItertaions", names), "maxIterations");  // a transposition
  EXPECT_FALSE(pbd::closestName("dt", names));                           // nothing within 2 edits
  EXPECT_EQ(pbd::closestName("maxIt", names), "maxIterations");          // cut short
  EXPECT_FALSE(pbd::closestName("ma", names));  // too short to be a beginning
  EXPECT_EQ(pbd::didYouMean("subStep", names), "; did you mean \"subSteps\"?");
  EXPECT_EQ(pbd::didYouMean("dt", names), "");
  EXPECT_EQ(pbd::editDistance("kitten", "sitting"), 3u);  // the textbook example
}

TEST(CheckAssignments, AKeyOnlySomeRunsHonourIsRefusedNamingThem) {
  const EngineRegistry& engines = testRegistry();
  EXPECT_NO_THROW(checkAssignments({"timeStepSize=0.001"}, {"pbd", "ode.quickstep"}, engines));
  EXPECT_NO_THROW(checkAssignments({"subSteps=4"}, {"pbd"}, engines));
  try {
    checkAssignments({"subSteps=4"}, {"pbd", "ode.quickstep"}, engines);
    FAIL() << "subSteps accepted for ODE";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("has no effect in ode/ode.quickstep"), std::string::npos) << message;
    EXPECT_NE(message.find("it applies to pbd/pbd"), std::string::npos) << message;
  }
  EXPECT_THROW(checkAssignments({"subSteps=0"}, {"pbd"}, engines), std::invalid_argument);
  EXPECT_THROW(checkAssignments({"subSteps=2", "subSteps=3"}, {"pbd"}, engines),
               std::invalid_argument);
  try {
    checkAssignments({"iteration=5"}, {"ode.quickstep"}, engines);
    FAIL() << "an unknown key accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean \"iterations\"?"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace pbdval
