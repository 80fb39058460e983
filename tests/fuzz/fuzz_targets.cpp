#include "fuzz_targets.h"

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "adapters/built_in_engines.h"
#include "fuzz_support.h"
#include "pbd/io/scene_loader.h"
#include "validation/io/results.h"
#include "validation/run/case_spec.h"
#include "validation/verdict/gate.h"

namespace pbdval::fuzz {
void caseSpecTarget(const std::uint8_t* data, std::size_t size) {
  pbd::LoadedScene loaded;
  try {
    loaded = pbd::parseScene(text(data, size), kSceneName);
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
    return;
  }
  try {
    // The engines a case may name: the built-in ones, made once (immutable).
    static const EngineRegistry engines = builtInEngines();
    (void)parseCaseSpec(loaded.scene, engines);
  } catch (const std::invalid_argument& e) {  // the documented error of parseCaseSpec
    expectPrintable(e.what());
  }
}

namespace {

/// The file a results reader's results are written as, or its error.
std::string resultsOutcome(const std::function<ResultsFile()>& read) {
  try {
    std::ostringstream written;
    writeResultsText(written, read());
    return written.str();
  } catch (const std::invalid_argument& e) {
    return std::string("error: ") + e.what();
  }
}

}  // namespace

void resultsTarget(const std::uint8_t* data, std::size_t size) {
  // pbdval merge's reader, which copies each record's text, gives the bytes or the error of the
  // reader of values.
  const std::string input = text(data, size);
  if (resultsOutcome([&] { return parseResultsText(input, "results.json"); }) !=
      resultsOutcome([&] {
        return parseResultsTextCopyingRecords(input, "results.json", {"energy_drift_max"});
      })) {
    std::fprintf(stderr, "results: the copying reader's outcome differs from the value reader's\n");
    std::abort();
  }
  try {
    const ResultsFile results = parseResultsText(text(data, size), "results.json");
    // What results.json's writer streams is the document nlohmann dumps whole.
    nlohmann::json runs = nlohmann::json::array();
    for (const RunRecord& r : results.runs)
      runs.push_back(recordJson(r));
    nlohmann::json cases = nlohmann::json::object();
    for (const auto& [name, gateData] : results.cases)
      cases[name] = caseGateDataJson(gateData);
    const nlohmann::json document = {
        {"schema", "pbdval-results"},
        {"schemaVersion", results.schemaVersion},
        {"metadata", nlohmann::json::parse(metadataJsonText(results.metadata))},
        {"cases", cases},
        {"runs", runs}};
    std::ostringstream streamed;
    writeResultsText(streamed, results);
    if (streamed.str() !=
        document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n") {
      std::fprintf(stderr, "results: the streamed text differs from the whole document's\n");
      std::abort();
    }
    // What the gate does with it next (against its own baseline): nothing may throw there.
    try {
      (void)evaluateGate(baselineFromResults(results), results);
    } catch (const std::invalid_argument& e) {
      expectPrintable(e.what());
    }
  } catch (const std::invalid_argument& e) {
    expectPrintable(e.what());
  }
}

void baselineTarget(const std::uint8_t* data, std::size_t size) {
  try {
    const Baseline baseline = parseBaselineText(text(data, size), "baseline.json");
    (void)evaluateGate(baseline, ResultsFile{});
  } catch (const std::invalid_argument& e) {
    expectPrintable(e.what());
  }
}

const std::vector<NamedTarget>& allTargets() {  // the library targets first
  static const std::vector<NamedTarget> targets = {
      {"scene", &sceneTarget},
      {"case_spec", &caseSpecTarget},
      {"obj", &objTarget},
      {"tetgen", &tetGenTarget},
      {"results", &resultsTarget},
      {"baseline", &baselineTarget},
      {"trajectory", &trajectoryTarget},
      {"trajectory_npy", &trajectoryNpyTarget},
      {"measure", &measureTarget},
      {"simulate", &simulateTarget},
      {"merge_shard", &mergeShardTarget},
  };
  return targets;
}

}  // namespace pbdval::fuzz
