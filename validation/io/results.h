// results.json (docs/results.md): every run of a `pbdval run` with the metadata needed to
// reproduce and compare it (build, machine, command). Written atomically.
#pragma once

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "validation/io/json_input.h"
#include "validation/run/run_record.h"

namespace pbdval {

/// Which slice of a plan a results folder holds (`pbdval run --shard K/N`, docs/cluster.md).
struct ShardInfo {
  int index = 1;             ///< K, 1-based
  int count = 1;             ///< N
  std::size_t planSize = 0;  ///< runs in the whole plan (cases that could not be read included)
  std::string planDigest;    ///< of the whole plan: equal plans, equal digests
};

/// Where and how a set of results was produced.
struct RunMetadata {
  std::string created;  ///< UTC, ISO 8601
  std::string command;  ///< the command line
  std::string version, commit, commitState, buildType, compiler, flags, precision;
  std::string hostname, cpu;
  int cores = 0;
  std::optional<ShardInfo> shard;  ///< set for one shard of a plan
  /// runsDigest (sharding.h) of the whole plan the results were made from: the gate and
  /// `pbdval baseline` refuse results whose runs do not give it back (runs lost, added or edited).
  std::string planDigest;
};

/// The metadata of this process (build info compiled in, machine read from the system).
RunMetadata currentMetadata(const std::string& command);

/// The metadata as the JSON object every result file (results.json, sweep.json) stores.
std::string metadataJsonText(const RunMetadata& metadata);

/// A case's gate data: the file the runs were made from, with its SHA-256, and its
/// Validation.checks and .tolerances. The results carry it as a record of what was run; the gate
/// takes checks and tolerances from the baseline, which pins them with the file's hash
/// (docs/gate.md), never from the results it judges.
struct CaseGateData {
  std::string file;
  std::string description;
  std::vector<CheckSpec> checks;
  std::map<std::string, double> tolerances;
  std::string fileSha256;  ///< of the case file's bytes ("" unknown: the file could not be read)
};

/// The JSON object of a case's gate data (results.json's and the baseline's "cases" entries) and
/// back; the reader throws std::invalid_argument naming the file and the JSON path.
nlohmann::json caseGateDataJson(const CaseGateData& data);
CaseGateData caseGateDataFrom(const JsonField& entry);

struct ResultsFile {
  int schemaVersion = kResultsSchemaVersion;
  RunMetadata metadata;
  std::map<std::string, CaseGateData> cases;  ///< by case name
  std::vector<RunRecord> runs;
  /// Set by readResultsCopyingRecords (pbdval merge, which copies every record on): when
  /// recordTexts[i] is not empty it is runs[i]'s record as writeResultsText writes it, from its
  /// opening brace up to the value of its last member, "trajectory" (which a merge rewrites), and
  /// runs[i] holds only what the merge looks at: the request, the status, the reason and the
  /// metrics asked for. writeResultsText then copies the text and writes the trajectory path
  /// after it. Empty (or shorter than runs): runs[i] is the whole record.
  std::vector<std::string> recordTexts;
};

void writeResults(const std::string& path, const ResultsFile& results);
/// The bytes writeResults writes: the document of every record as nlohmann dumps it (2-space
/// indent), each record written as it comes rather than held as one JSON value.
void writeResultsText(std::ostream& out, const ResultsFile& results);
/// Throws std::invalid_argument naming the file and the field on bad input.
ResultsFile readResults(const std::string& path);
/// The same on the file's text; `sourceName` names it in messages.
ResultsFile parseResultsText(const std::string& text, const std::string& sourceName);

/// readResults for a command that writes the records on unchanged (pbdval merge): each run whose
/// record has the form writeResultsText gives it (members in its order, every number and string
/// of a JSON form; the layout and the numbers' spelling may differ: they are written again) is
/// kept as its text (ResultsFile::recordTexts), with only its request, status, reason and the
/// metrics named in `keptMetrics` as values; a run of any other form is read as readResults reads
/// it. Written again, the file has the bytes readResults' file would have; bad input throws what
/// readResults throws (it reads the file again to say it). Reading each record's text once,
/// without building its values, is most of what makes a merge of 10,000 runs take a fraction of
/// a second (docs/cluster.md#measured).
ResultsFile readResultsCopyingRecords(const std::string& path,
                                      const std::vector<std::string>& keptMetrics);
/// The same on the file's text.
ResultsFile parseResultsTextCopyingRecords(const std::string& text, const std::string& sourceName,
                                           const std::vector<std::string>& keptMetrics);

}  // namespace pbdval
