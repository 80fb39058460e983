// The fuzz targets (docs/fuzzing.md): one function per input reader, taking raw bytes. A target
// returns normally on every input, valid or not; the only exceptions it lets through are
// unexpected ones (a std::out_of_range, a JSON type_error, std::bad_alloc), which libFuzzer
// reports as crashes. Every error message caught must be valid UTF-8.
//
// They are compiled twice: into libFuzzer programs (PBDVAL_FUZZ, scripts/fuzz) and into the
// normal test build, where fuzz_corpus_replay feeds them every file of tests/fuzz/corpus/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pbdval::fuzz {

using Target = void (*)(const std::uint8_t* data, std::size_t size);

void sceneTarget(const std::uint8_t* data, std::size_t size);          ///< pbd::parseScene
void caseSpecTarget(const std::uint8_t* data, std::size_t size);       ///< + parseCaseSpec
void objTarget(const std::uint8_t* data, std::size_t size);            ///< pbd::parseObj
void tetGenTarget(const std::uint8_t* data, std::size_t size);         ///< .node, "\n===\n", .ele
void resultsTarget(const std::uint8_t* data, std::size_t size);        ///< parseResultsText
void baselineTarget(const std::uint8_t* data, std::size_t size);       ///< parseBaselineText
void trajectoryTarget(const std::uint8_t* data, std::size_t size);     ///< parseTrajectoryCsv
void trajectoryNpyTarget(const std::uint8_t* data, std::size_t size);  ///< parseTrajectoryNpy
void measureTarget(const std::uint8_t* data, std::size_t size);        ///< measureTrajectory
void simulateTarget(const std::uint8_t* data,
                    std::size_t size);  ///< load + runSimulation, every engine
void mergeShardTarget(const std::uint8_t* data,
                      std::size_t size);  ///< a shard's results.json, merged

struct NamedTarget {
  const char* name;  ///< also the folder of its corpus: tests/fuzz/corpus/<name>/
  Target run;
};
/// Every target, by name.
const std::vector<NamedTarget>& allTargets();

}  // namespace pbdval::fuzz
