#include "fuzz_targets.h"

#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"
#include "validation/case_spec.h"
#include "validation/gate.h"
#include "validation/results.h"
#include "validation/trajectory.h"

namespace pbdval::fuzz {
namespace {

// Relative mesh paths in a fuzzed scene resolve here: a folder that does not exist, so that
// the fuzzer cannot reach the corpus or the project's files by a short relative path.
constexpr const char* kSceneName = "/nonexistent-pbdval-fuzz/scene.json";

std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Messages are printed and stored in results.json: they must be valid UTF-8. nlohmann's
/// strict dump() is the check (it throws type_error 316 on a bad byte); abort so that
/// libFuzzer records the input.
void expectPrintable(const char* message) {
  try {
    (void)nlohmann::json(std::string(message)).dump();
  } catch (const nlohmann::json::type_error&) {
    std::fprintf(stderr, "error message is not valid UTF-8: %s\n", message);
    std::abort();
  }
}

}  // namespace

void sceneTarget(const std::uint8_t* data, std::size_t size) {
  try {
    const pbd::LoadedScene loaded = pbd::parseScene(text(data, size), kSceneName);
    for (const pbd::SceneDiagnostic& warning : loaded.warnings)
      expectPrintable(warning.text().c_str());
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
  }
}

void caseSpecTarget(const std::uint8_t* data, std::size_t size) {
  pbd::LoadedScene loaded;
  try {
    loaded = pbd::parseScene(text(data, size), kSceneName);
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
    return;
  }
  try {
    (void)parseCaseSpec(loaded.scene);
  } catch (const std::invalid_argument& e) {  // the documented error of parseCaseSpec
    expectPrintable(e.what());
  }
}

void objTarget(const std::uint8_t* data, std::size_t size) {
  try {
    (void)pbd::parseObj(text(data, size), "fuzz.obj");
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
  }
}

void tetGenTarget(const std::uint8_t* data, std::size_t size) {
  const std::string all = text(data, size);
  const std::string separator = "\n===\n";
  const std::size_t split = all.find(separator);
  const std::string node = split == std::string::npos ? all : all.substr(0, split);
  const std::string ele = split == std::string::npos ? "" : all.substr(split + separator.size());
  try {
    (void)pbd::parseTetGen(node, ele, "fuzz.node", "fuzz.ele");
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
  }
}

void resultsTarget(const std::uint8_t* data, std::size_t size) {
  try {
    const ResultsFile results = parseResultsText(text(data, size), "results.json");
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

void trajectoryTarget(const std::uint8_t* data, std::size_t size) {
  try {
    (void)parseTrajectoryCsv(text(data, size), "trajectory.csv");
  } catch (const std::runtime_error& e) {
    expectPrintable(e.what());
  }
}

const std::vector<NamedTarget>& allTargets() {
  static const std::vector<NamedTarget> targets = {
      {"scene", &sceneTarget},
      {"case_spec", &caseSpecTarget},
      {"obj", &objTarget},
      {"tetgen", &tetGenTarget},
      {"results", &resultsTarget},
      {"baseline", &baselineTarget},
      {"trajectory", &trajectoryTarget},
  };
  return targets;
}

}  // namespace pbdval::fuzz
