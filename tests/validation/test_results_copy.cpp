// results.json read for pbdval merge, each run's record kept as its text
// (readResultsCopyingRecords): written again, the file must have the bytes of the file read as
// values (readResults) and written again, whatever the layout and spelling of the input, and bad
// input must give readResults' errors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "validation/io/results.h"
#include "validation/run/run_record.h"
#include "validation/run/sharding.h"

namespace pbdval {
namespace {

const std::vector<std::string> kKept = {"energy_drift_max", "real_time_factor"};

RunRequest requestFor(const std::string& caseName, const std::string& engine,
                      const std::string& method) {
  RunRequest r;
  r.caseName = caseName;
  r.caseFile = "cases/" + caseName + ".json";
  r.engine = engine;
  r.method = method;
  return r;
}

/// Records through every branch of a record's text: empty lists and maps; angular, motor and
/// linear-only joint errors; non-finite and extreme numbers, -0; strings that need escapes, are
/// not ASCII or not valid UTF-8 (all in values: the keys are ASCII, as pbdval's are).
std::vector<RunRecord> records() {
  std::vector<RunRecord> out;
  RunRecord plain;
  plain.request = requestFor("c", "bullet", "bullet.si");
  plain.status = RunStatus::Ok;
  out.push_back(plain);

  RunRecord full;
  full.request = requestFor("c", "pbd", "pbd.xpbd");
  full.request.assignments = {"subSteps=10", "timeStepSize=0.001"};
  full.request.trajectoryPath = "out/trajectories/c/pbd-pbd.xpbd.csv";
  full.request.referenceMode = "fine";
  full.request.fineDivisor = 32;
  full.request.referenceStepSize = 1.0 / 3.0;
  full.request.sampleInterval = 1e-300;
  full.status = RunStatus::Suspect;
  full.reason = "quote \" backslash \\ tab \t newline \n bell \a é ✓ bad \xff\xfe byte";
  full.methodParameters = {{"subSteps", "10"}, {"Z-upper before lower", "x"}, {"name", "ü"}};
  full.settings = {{"timeStepSize", "0.005"}, {"gravity", "0 0 -9.81"}};
  full.facts.engineVersion = "PBD 1.0 \"quoted\"";
  full.facts.integratorStepsPerSceneStep = 10;
  full.facts.contactMargin = -0.0;
  full.metrics.values = {{"a", 1.0},
                         {"b", -2.5e-17},
                         {"c", 123456789.0},
                         {"d", 1e21},
                         {"e", std::nan("")},
                         {"f", HUGE_VAL},
                         {"g", 0.1},
                         {"h", 5e-324},
                         {"i", -1.7976931348623157e308},
                         {"steps", 1000.0},
                         {"wall_time_s", 0.0123},
                         {"energy_drift_max", 0.25},
                         {"real_time_factor", 812.5}};
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
  out.push_back(full);

  RunRecord negative = plain;  // negative integers
  negative.request = requestFor("c", "ode", "ode.quickstep");
  negative.request.fineDivisor = -5;
  negative.facts.integratorStepsPerSceneStep = -123456789;
  negative.status = RunStatus::Error;
  negative.reason = "engine process crashed";
  out.push_back(negative);
  return out;
}

/// The results text of `runs` as pbdval writes it.
std::string resultsText(const std::vector<RunRecord>& runs) {
  ResultsFile file;
  file.metadata = currentMetadata("pbdval run test");
  file.cases["c"].file = "cases/c.json";
  file.runs = runs;
  std::ostringstream text;
  writeResultsText(text, file);
  return text.str();
}

std::string written(const ResultsFile& results) {
  std::ostringstream text;
  writeResultsText(text, results);
  return text.str();
}

/// What a reader makes of `text`: the file it writes again, or its error.
std::string outcome(const std::function<ResultsFile()>& read) {
  try {
    return written(read());
  } catch (const std::invalid_argument& e) {
    return std::string("error: ") + e.what();
  }
}

/// Both readers on `text`: the same bytes written again, or the same error.
void expectSameOutcome(const std::string& text, const std::string& what) {
  const std::string byValues = outcome([&] { return parseResultsText(text, "r.json"); });
  const std::string copying =
      outcome([&] { return parseResultsTextCopyingRecords(text, "r.json", kKept); });
  EXPECT_EQ(copying, byValues) << what;
}

std::size_t copiedRecords(const ResultsFile& results) {
  std::size_t copied = 0;
  for (const std::string& text : results.recordTexts)
    copied += text.empty() ? 0 : 1;
  return copied;
}

TEST(ResultsCopyingRecords, PbdvalsOwnFileIsCopiedRecordByRecordToTheSameBytes) {
  const std::string text = resultsText(records());
  const ResultsFile copied = parseResultsTextCopyingRecords(text, "r.json", kKept);
  // Every record took the copying path (else the merge would be as slow as before).
  EXPECT_EQ(copiedRecords(copied), records().size());
  EXPECT_EQ(written(copied), text);
  EXPECT_EQ(written(copied), written(parseResultsText(text, "r.json")));
}

TEST(ResultsCopyingRecords, ARecordKeepsItsRequestStatusReasonAndOnlyTheMetricsAsked) {
  const ResultsFile copied =
      parseResultsTextCopyingRecords(resultsText(records()), "r.json", kKept);
  ASSERT_EQ(copied.runs.size(), 3u);
  const RunRecord& full = copied.runs[1];
  const RunRecord expected = records()[1];
  EXPECT_EQ(full.request.caseName, expected.request.caseName);
  EXPECT_EQ(full.request.caseFile, expected.request.caseFile);
  EXPECT_EQ(full.request.engine, expected.request.engine);
  EXPECT_EQ(full.request.method, expected.request.method);
  EXPECT_EQ(full.request.assignments, expected.request.assignments);
  EXPECT_EQ(full.request.trajectoryPath, expected.request.trajectoryPath);
  EXPECT_EQ(full.request.referenceMode, expected.request.referenceMode);
  EXPECT_EQ(full.request.fineDivisor, expected.request.fineDivisor);
  EXPECT_EQ(full.request.referenceStepSize, expected.request.referenceStepSize);
  EXPECT_EQ(full.request.sampleInterval, expected.request.sampleInterval);
  EXPECT_EQ(full.status, RunStatus::Suspect);
  // The reason's bad bytes were written as U+FFFD (json_text.h): that is what is read back.
  EXPECT_EQ(full.reason, parseResultsText(resultsText(records()), "r.json").runs[1].reason);
  EXPECT_EQ(full.metrics.values.size(), 2u);
  EXPECT_EQ(full.metrics.values.at("energy_drift_max"), 0.25);
  EXPECT_EQ(full.metrics.values.at("real_time_factor"), 812.5);
  EXPECT_EQ(copied.runs[2].request.fineDivisor, -5);
}

TEST(ResultsCopyingRecords, AnotherLayoutOrEscapingGivesTheBytesOfTheValueReader) {
  const std::string text = resultsText(records());
  const nlohmann::json document = nlohmann::json::parse(text);
  for (const int indent : {-1, 0, 1, 4})
    for (const bool ascii : {false, true}) {
      const std::string other =
          document.dump(indent, ' ', ascii, nlohmann::json::error_handler_t::strict);
      expectSameOutcome(other, "indent " + std::to_string(indent) + (ascii ? ", ASCII" : ""));
      // Whitespace and escapes are the layout's, not the record's: still copied.
      EXPECT_EQ(copiedRecords(parseResultsTextCopyingRecords(other, "r.json", kKept)), 3u);
    }
}

TEST(ResultsCopyingRecords, NumbersSpelledOtherwiseAreWrittenInTheWritersForm) {
  std::string text = resultsText(records());
  const auto respell = [&](const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  respell("\"steps\": 1000.0", "\"steps\": 1e3");
  respell("\"wall_time_s\": 0.0123", "\"wall_time_s\": 1.230E-2");
  respell("\"g\": 0.1", "\"g\": 0.1000000000000000055511151231257827");
  respell("\"contactMargin\": -0.0", "\"contactMargin\": -0");  // nlohmann's integer 0
  respell("\"c\": 123456789.0", "\"c\": 123456789");
  respell("\"d\": 1e+21", "\"d\": 1000000000000000000000");
  expectSameOutcome(text, "respelled numbers");
  EXPECT_NE(written(parseResultsTextCopyingRecords(text, "r.json", kKept)), resultsText(records()))
      << "-0 is read as +0 by both readers: the bytes differ from the first file's";
}

TEST(ResultsCopyingRecords, ARecordOfAnotherFormIsReadAsValuesAndTheOthersCopied) {
  const std::string text = resultsText(records());
  nlohmann::json document = nlohmann::json::parse(text);
  std::vector<std::pair<std::string, std::function<void(nlohmann::json&)>>> edits = {
      {"an unknown member", [](nlohmann::json& r) { r["zzz"] = 1; }},
      {"no facts", [](nlohmann::json& r) { r.erase("facts"); }},
      {"no trajectory", [](nlohmann::json& r) { r.erase("trajectory"); }},
      {"a fractional fineDivisor", [](nlohmann::json& r) { r["fineDivisor"] = 16.75; }},
      {"a large fineDivisor", [](nlohmann::json& r) { r["fineDivisor"] = 1234567890123LL; }},
      {"an empty motor quantity",
       [](nlohmann::json& r) {
         r["joint_error_by_type"]["x"] = {{"joint_error_linear_max", 1.0},
                                          {"joint_error_linear_rms", 1.0},
                                          {"joints", 2},
                                          {"motor_tracking_max", 3.0},
                                          {"motor_tracking_quantity", ""},
                                          {"motor_tracking_rms", 4.0}};
       }},
      {"an angular rms alone",
       [](nlohmann::json& r) {
         r["joint_error_by_type"]["x"] = {{"joint_error_angular_rms", 1.0},
                                          {"joint_error_linear_max", 1.0},
                                          {"joint_error_linear_rms", 1.0},
                                          {"joints", 2}};
       }},
      {"a key that is not ASCII", [](nlohmann::json& r) { r["parameters"]["é"] = "1"; }},
  };
  for (const auto& [what, edit] : edits) {
    nlohmann::json changed = document;
    edit(changed["runs"][1]);
    const std::string other = changed.dump(2);
    expectSameOutcome(other, what);
    const ResultsFile copied = parseResultsTextCopyingRecords(other, "r.json", kKept);
    EXPECT_EQ(copiedRecords(copied), 2u) << what << ": the two other records are copied";
    EXPECT_TRUE(copied.recordTexts.at(1).empty()) << what;
  }
  // Members in another order (nlohmann's document sorts them: edit the text).
  std::string swapped = text;
  const std::size_t caseAt = swapped.find("\"case\": \"c\",", swapped.find("\"runs\""));
  swapped.erase(caseAt, std::string("\"case\": \"c\",").size());
  swapped.insert(swapped.find("\"status\"", caseAt), "\"case\": \"c\", ");
  expectSameOutcome(swapped, "members out of order");
  // A key given twice: the document keeps the last value.
  std::string twice = text;
  twice.insert(twice.find("\"a\": 1.0"), "\"a\": 7.5, ");
  expectSameOutcome(twice, "a metric given twice");
}

/// A results text with a runs array of `runs` (text) and the schema `schema`.
std::string documentAround(const std::string& runs, const std::string& schema = "pbdval-results") {
  return "{\"cases\": {\"c\": {}}, \"runs\": " + runs + ", \"schema\": \"" + schema +
         "\", \"schemaVersion\": 1}";
}

TEST(ResultsCopyingRecords, BadInputGivesTheValueReadersErrorNamingTheFileAndPath) {
  const std::string good = toJsonText(records()[0]);
  std::string bad = good;
  bad.replace(bad.find("\"ok\""), 4, "\"fine\"");  // an unknown status
  std::string otherCase = good;
  otherCase.replace(otherCase.find("\"case\": \"c\""), 11, "\"case\": \"no_case\"");
  std::string beyondRange = good;  // a number no double holds: nlohmann refuses it
  beyondRange.replace(beyondRange.find("\"metrics\": {}"), 13, "\"metrics\": {\"a\": 1e400}");
  const std::string deep = std::string(300, '[') + std::string(300, ']');
  std::string nested = good;
  nested.replace(nested.find("\"notes\": []"), 11, "\"notes\": " + deep);
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"another schema", documentAround("[" + good + "," + bad + "]", "other")},
      {"an unknown status", documentAround("[" + good + "," + bad + "]")},
      {"a case without an entry", documentAround("[" + otherCase + "]")},
      {"a run that is a number", documentAround("[" + good + ", 7]")},
      {"runs that are not an array", documentAround("{\"x\": 1}")},
      {"no runs", "{\"cases\": {}, \"schema\": \"pbdval-results\", \"schemaVersion\": 1}"},
      {"a syntax error after the runs", documentAround("[" + good + "]") + "}"},
      {"nesting past the limit in a run", documentAround("[" + nested + "]")},
      {"a number beyond a double's range", documentAround("[" + beyondRange + "]")},
      {"runs given twice", "{\"cases\": {\"c\": {}}, \"runs\": [" + good + "], \"runs\": [" + bad +
                               "], \"schema\": \"pbdval-results\", \"schemaVersion\": 1}"},
      {"an empty file", ""},
      {"not JSON", "results"},
  };
  for (const auto& [what, text] : inputs) {
    const std::string error =
        outcome([&] { return parseResultsTextCopyingRecords(text, "r.json", kKept); });
    EXPECT_EQ(error.rfind("error: r.json: ", 0), 0u) << what << ": " << error;
    expectSameOutcome(text, what);
  }
}

TEST(ResultsCopyingRecords, EveryTruncationAndSeededMutationGivesTheValueReadersOutcome) {
  // A differential check over many inputs close to a good file: cut anywhere, or one byte
  // changed, inserted or removed (a fixed seed: the same inputs every run).
  const std::string text = resultsText(records());
  for (std::size_t size = 0; size < text.size(); size += 3)
    expectSameOutcome(text.substr(0, size), "cut at " + std::to_string(size));
  std::mt19937 random(20261128);
  const std::string bytes = "{}[],:\"\\0123456789.eE+-nultrfa \n\t\x01\x7f\xc3\xa9\xff";
  for (int k = 0; k < 3000; ++k) {
    std::string changed = text;
    const std::size_t at = std::uniform_int_distribution<std::size_t>(0, text.size() - 1)(random);
    const char byte =
        bytes[std::uniform_int_distribution<std::size_t>(0, bytes.size() - 1)(random)];
    switch (k % 3) {
      case 0:
        changed[at] = byte;
        break;
      case 1:
        changed.insert(changed.begin() + long(at), byte);
        break;
      default:
        changed.erase(at, 1);
    }
    expectSameOutcome(changed, "mutation " + std::to_string(k) + " at " + std::to_string(at));
  }
}

TEST(ResultsCopyingRecords, MergedShardsReadEitherWayGiveTheSameFile) {
  // Two shards of a plan of five runs, merged from records read as values and from copied
  // records, each merged run's trajectory moved as pbdval merge moves it.
  RunPlan plan;
  const std::vector<RunRecord> kinds = records();
  for (int k = 0; k < 5; ++k)
    plan.requests.push_back(
        requestFor("c", kinds[std::size_t(k) % kinds.size()].request.engine,
                   kinds[std::size_t(k) % kinds.size()].request.method + std::to_string(k)));
  std::vector<std::string> shardTexts;
  for (int index = 1; index <= 2; ++index) {
    ShardInfo info;
    info.index = index;
    info.count = 2;
    const RunPlan part = shardOf(plan, info);
    ResultsFile file;
    file.metadata = currentMetadata("pbdval run --shard");
    file.metadata.shard = info;
    file.metadata.planDigest = runsDigest(plan);
    file.cases["c"].file = "cases/c.json";
    for (std::size_t i = 0; i < part.requests.size(); ++i) {
      RunRecord record = kinds[i % kinds.size()];
      record.request = part.requests[i];
      record.request.trajectoryPath =
          "shard/trajectories/c/" + record.request.engine + "-" + record.request.method + ".csv";
      file.runs.push_back(record);
    }
    shardTexts.push_back(written(file));
  }
  const auto merged = [&](bool copying) {
    std::vector<ShardResults> shards;
    for (std::size_t k = 0; k < shardTexts.size(); ++k) {
      const std::string name = "shard-" + std::to_string(k + 1);
      shards.push_back({name, copying ? parseResultsTextCopyingRecords(shardTexts[k], name, kKept)
                                      : parseResultsText(shardTexts[k], name)});
    }
    ResultsFile file = mergeShards(shards, "pbdval merge shard-1 shard-2 --out out");
    for (RunRecord& r : file.runs)
      r.request.trajectoryPath = "out/trajectories/c/moved-" + r.request.method + ".csv";
    return written(file);
  };
  const std::string byValues = merged(false);
  EXPECT_EQ(merged(true), byValues);
  EXPECT_NE(byValues.find("out/trajectories/c/moved-"), std::string::npos);
  EXPECT_EQ(byValues.find("shard/trajectories"), std::string::npos);
}

}  // namespace
}  // namespace pbdval
