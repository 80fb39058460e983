#include "validation/io/results.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <ctime>
#include <exception>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <thread>

#include "pbd/math/types.h"
#include "pbdval/build_info.h"
#include "validation/io/atomic_file.h"
#include "validation/io/json_input.h"
#include "validation/io/json_text.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

Json metadataJson(const RunMetadata& m) {
  Json j = {{"created", m.created},
            {"command", m.command},
            {"pbdval",
             {{"version", m.version},
              {"commit", m.commit},
              {"commitState", m.commitState},
              {"buildType", m.buildType},
              {"compiler", m.compiler},
              {"flags", m.flags},
              {"precision", m.precision}}},
            {"machine", {{"hostname", m.hostname}, {"cpu", m.cpu}, {"cores", m.cores}}}};
  if (!m.planDigest.empty()) j["planDigest"] = m.planDigest;
  if (m.shard)
    j["shard"] = {{"index", m.shard->index},
                  {"count", m.shard->count},
                  {"planSize", m.shard->planSize},
                  {"planDigest", m.shard->planDigest}};
  return j;
}

RunMetadata metadataFrom(const JsonField& j) {
  RunMetadata m;
  m.created = j.stringOr("created", "");
  m.command = j.stringOr("command", "");
  if (j.has("pbdval")) {
    const JsonField p = j.at("pbdval").expectObject();
    m.version = p.stringOr("version", "");
    m.commit = p.stringOr("commit", "");
    m.commitState = p.stringOr("commitState", "");
    m.buildType = p.stringOr("buildType", "");
    m.compiler = p.stringOr("compiler", "");
    m.flags = p.stringOr("flags", "");
    m.precision = p.stringOr("precision", "");
  }
  if (j.has("machine")) {
    const JsonField h = j.at("machine").expectObject();
    m.hostname = h.stringOr("hostname", "");
    m.cpu = h.stringOr("cpu", "");
    if (h.has("cores")) m.cores = static_cast<int>(h.at("cores").integer(0, 1 << 20));
  }
  m.planDigest = j.stringOr("planDigest", "");
  if (j.has("shard")) {
    const JsonField s = j.at("shard").expectObject();
    ShardInfo shard;
    shard.count = static_cast<int>(s.at("count").integer(1, 1 << 30));
    shard.index = static_cast<int>(s.at("index").integer(1, shard.count));
    shard.planSize = static_cast<std::size_t>(s.at("planSize").integer(0, 1LL << 40));
    shard.planDigest = s.at("planDigest").string();
    m.shard = shard;
  }
  return m;
}

Json checkJson(const CheckSpec& c) {
  Json j = {{"jsonPath", c.jsonPath}, {"metric", c.metric}};
  if (c.max) j["max"] = *c.max;
  if (c.min) j["min"] = *c.min;
  if (!c.engines.empty()) j["engines"] = c.engines;
  if (!c.methods.empty()) j["methods"] = c.methods;
  if (!c.better.empty()) j["better"] = c.better;
  if (!c.worse.empty()) j["worse"] = c.worse;
  if (!c.description.empty()) j["description"] = c.description;
  return j;
}

CheckSpec checkFrom(const JsonField& j) {
  CheckSpec c;
  c.jsonPath = j.stringOr("jsonPath", "");
  c.metric = j.at("metric").string();
  if (j.has("max")) c.max = j.at("max").number();
  if (j.has("min")) c.min = j.at("min").number();
  if (j.has("engines")) c.engines = j.at("engines").strings();
  if (j.has("methods")) c.methods = j.at("methods").strings();
  c.better = j.stringOr("better", "");
  c.worse = j.stringOr("worse", "");
  c.description = j.stringOr("description", "");
  return c;
}

// ---- results.json's runs, written straight to text ------------------------------------------
// A record's text is exactly what jsonText(recordJson(record)) gives at the runs array's depth
// (tests/validation/test_runner.cpp and the results fuzz target compare them byte for byte):
// the keys in nlohmann's order (its objects are std::maps: byte-wise), its number and string
// forms. Written directly, 10,000 records cost a fraction of building and dumping their JSON
// values (docs/cluster.md#measured).

/// A JSON string as nlohmann dumps it (ensure_ascii off, bad UTF-8 replaced by U+FFFD).
void appendString(std::string& out, const std::string& text) {
  const bool plain = std::all_of(text.begin(), text.end(), [](char c) {
    return c >= 0x20 && c < 0x7f && c != '"' && c != '\\';
  });
  if (!plain) {
    out += jsonText(Json(text), -1);
    return;
  }
  out += '"';
  out += text;
  out += '"';
}

/// A double as nlohmann dumps it: its shortest round-trip form (nlohmann's own to_chars, the
/// function its serializer calls), null when not finite (recordJson's number()).
void appendNumber(std::string& out, double value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  std::array<char, 64> buffer{};
  const char* end = nlohmann::detail::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out.append(buffer.data(), std::size_t(end - buffer.data()));
}

/// An object's members, one line each at `indent`, its braces at `indent` − 2; `members` append
/// each member's value after its key (empty: "{}", as nlohmann writes it).
class ObjectText {
 public:
  ObjectText(std::string& out, std::string indent) : out_(out), indent_(std::move(indent)) {
    out_ += '{';
  }
  /// Starts the member `key`; its value is appended next.
  std::string& key(const std::string& name) {
    out_ += first_ ? "\n" : ",\n";
    first_ = false;
    out_ += indent_;
    appendString(out_, name);
    out_ += ": ";
    return out_;
  }
  void close() {
    if (!first_) {
      out_ += '\n';
      out_.append(indent_, 0, indent_.size() - 2);
    }
    out_ += '}';
  }
  const std::string& indent() const { return indent_; }

 private:
  std::string& out_;
  std::string indent_;
  bool first_ = true;
};

void appendStrings(std::string& out, const std::vector<std::string>& items,
                   const std::string& indent) {
  if (items.empty()) {
    out += "[]";
    return;
  }
  out += '[';
  for (std::size_t i = 0; i < items.size(); ++i) {
    out += i == 0 ? "\n" : ",\n";
    out += indent;
    appendString(out, items[i]);
  }
  out += '\n';
  out.append(indent, 0, indent.size() - 2);
  out += ']';
}

void appendStringMap(std::string& out, const std::map<std::string, std::string>& items,
                     const std::string& indent) {
  ObjectText object(out, indent);
  for (const auto& [name, value] : items)
    appendString(object.key(name), value);
  object.close();
}

/// One record (recordJson's members) with its opening brace at `indent` − 2 spaces.
void appendRecordText(std::string& out, const RunRecord& record, const std::string& indent) {
  const RunRequest& r = record.request;
  const std::string inner = indent + "  ";
  ObjectText j(out, indent);
  appendStrings(j.key("assignments"), r.assignments, inner);
  appendString(j.key("case"), r.caseName);
  appendString(j.key("caseFile"), r.caseFile);
  appendString(j.key("engine"), r.engine);
  {
    ObjectText facts(j.key("facts"), inner);
    appendNumber(facts.key("contactMargin"), record.facts.contactMargin);
    appendString(facts.key("engineVersion"), record.facts.engineVersion);
    facts.key("integratorStepsPerSceneStep") +=
        std::to_string(record.facts.integratorStepsPerSceneStep);
    facts.close();
  }
  j.key("fineDivisor") += std::to_string(r.fineDivisor);
  {
    ObjectText byType(j.key("joint_error_by_type"), inner);
    for (const auto& [type, summary] : record.metrics.jointErrorByType) {
      ObjectText s(byType.key(type), inner + "  ");
      if (summary.hasAngular) {
        appendNumber(s.key("joint_error_angular_max"), summary.angularMax);
        appendNumber(s.key("joint_error_angular_rms"), summary.angularRms);
      }
      appendNumber(s.key("joint_error_linear_max"), summary.linearMax);
      appendNumber(s.key("joint_error_linear_rms"), summary.linearRms);
      s.key("joints") += std::to_string(summary.joints);
      if (!summary.trackingQuantity.empty()) {
        appendNumber(s.key("motor_tracking_max"), summary.trackingMax);
        appendString(s.key("motor_tracking_quantity"), summary.trackingQuantity);
        appendNumber(s.key("motor_tracking_rms"), summary.trackingRms);
      }
      s.close();
    }
    byType.close();
  }
  appendString(j.key("method"), r.method);
  {
    ObjectText metrics(j.key("metrics"), inner);
    for (const auto& [name, value] : record.metrics.values)
      appendNumber(metrics.key(name), value);
    metrics.close();
  }
  appendStrings(j.key("notes"), record.metrics.notes, inner);
  appendStringMap(j.key("parameters"), record.methodParameters, inner);
  appendString(j.key("reason"), record.reason);
  appendString(j.key("reference"), record.reference);
  appendString(j.key("referenceMode"), r.referenceMode);
  appendNumber(j.key("referenceStepSize"), r.referenceStepSize);
  appendNumber(j.key("sampleInterval"), r.sampleInterval);
  appendStringMap(j.key("settings"), record.settings, inner);
  appendString(j.key("state_hash"), record.stateHash);
  appendString(j.key("status"), runStatusName(record.status));
  appendString(j.key("trajectory"), r.trajectoryPath);
  j.close();
}

}  // namespace

Json caseGateDataJson(const CaseGateData& data) {
  Json checks = Json::array();
  for (const CheckSpec& c : data.checks)
    checks.push_back(checkJson(c));
  Json j = {{"file", data.file},
            {"description", data.description},
            {"checks", checks},
            {"tolerances", data.tolerances}};
  if (!data.fileSha256.empty()) j["sha256"] = data.fileSha256;
  return j;
}

CaseGateData caseGateDataFrom(const JsonField& entry) {
  CaseGateData data;
  data.file = entry.stringOr("file", "");
  data.description = entry.stringOr("description", "");
  data.fileSha256 = entry.stringOr("sha256", "");
  if (entry.has("checks")) {
    const JsonField checks = entry.at("checks").expectArray();
    for (std::size_t i = 0; i < checks.size(); ++i)
      data.checks.push_back(checkFrom(checks.at(i).expectObject()));
  }
  if (entry.has("tolerances")) {
    const JsonField tolerances = entry.at("tolerances").expectObject();
    for (const std::string& metric : tolerances.keys())
      data.tolerances[metric] = tolerances.at(metric).number();
  }
  return data;
}

RunMetadata currentMetadata(const std::string& command) {
  RunMetadata m;
  m.created = utcNow();
  m.command = command;
  m.version = PBDVAL_VERSION;
  m.commit = PBDVAL_GIT_COMMIT;
  m.commitState = PBDVAL_GIT_DIRTY;
  m.buildType = PBDVAL_BUILD_TYPE;
  m.compiler = PBDVAL_CXX_COMPILER;
  m.flags = PBDVAL_CXX_FLAGS;
  m.precision = sizeof(pbd::Real) == 8 ? "double" : "float";
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  m.hostname = host;
  m.cpu = cpuModel();
  m.cores = static_cast<int>(std::thread::hardware_concurrency());
  return m;
}

std::string metadataJsonText(const RunMetadata& metadata) {
  return jsonText(metadataJson(metadata), -1);
}

void writeResultsText(std::ostream& out, const ResultsFile& results) {
  Json cases = Json::object();
  for (const auto& [name, data] : results.cases)
    cases[name] = caseGateDataJson(data);
  // The document without its runs, then each run's record written into it in place of the
  // empty array: the bytes of the whole document dumped at once (nlohmann orders the keys, so
  // "runs" lies between "metadata" and "schema"), without holding every record as JSON.
  const Json document = {{"schema", "pbdval-results"},
                         {"schemaVersion", results.schemaVersion},
                         {"metadata", metadataJson(results.metadata)},
                         {"cases", cases},
                         {"runs", Json::array()}};
  const std::string frame = jsonText(document);
  const std::string emptyRuns = "\n  \"runs\": []";  // a top-level key: indented by 2
  const std::size_t at = frame.find(emptyRuns);
  if (at == std::string::npos) throw std::logic_error("results.json: no top-level runs key");
  out.write(frame.data(), std::streamsize(at + emptyRuns.size() - 1));
  std::string record;
  for (std::size_t i = 0; i < results.runs.size(); ++i) {
    record = i == 0 ? "\n    " : ",\n    ";
    if (i < results.recordTexts.size() && !results.recordTexts[i].empty()) {
      // The record's text as read (readResultsCopyingRecords), up to its trajectory's value.
      out.write(record.data(), std::streamsize(record.size()));
      const std::string& text = results.recordTexts[i];
      out.write(text.data(), std::streamsize(text.size()));
      record.clear();
      appendString(record, results.runs[i].request.trajectoryPath);
      record += "\n    }";
    } else {
      appendRecordText(record, results.runs[i], "      ");
    }
    out.write(record.data(), std::streamsize(record.size()));
  }
  if (!results.runs.empty()) out << "\n  ";
  out << ']';
  out.write(frame.data() + at + emptyRuns.size(),
            std::streamsize(frame.size() - at - emptyRuns.size()));
  out << '\n';
}

void writeResults(const std::string& path, const ResultsFile& results) {
  OutputFile file(path);
  writeResultsText(file.stream(), results);
  file.commit();
}

namespace {

/// The runs of a results document, converted as the parser hands them over; the first record
/// that cannot be converted is kept to be thrown in its turn, after the checks of the document
/// around the runs (a file that is not a results file is reported as such, whatever its runs).
struct StreamedRuns {
  std::vector<RunRecord> records;
  std::exception_ptr firstError;  ///< of the record at index records.size()
};

ResultsFile parseResults(const nlohmann::json& document, StreamedRuns& streamed,
                         const std::string& path);

ResultsFile parseResultsStreaming(const std::string& text, const std::string& path) {
  StreamedRuns streamed;
  const Json document = parseJsonTextStreaming(
      text, path, {"runs"}, [&](const std::string&) { streamed = {}; },
      [&](const std::string&, std::size_t index, Json& run) {
        if (streamed.firstError) return;
        try {
          streamed.records.push_back(
              recordFromJson(run, path + ": runs[" + std::to_string(index) + "]"));
        } catch (const std::invalid_argument&) {
          streamed.firstError = std::current_exception();
        }
      });
  return parseResults(document, streamed, path);
}

}  // namespace

ResultsFile readResults(const std::string& path) {
  return parseResultsStreaming(readJsonFileText(path, "results"), path);
}

ResultsFile parseResultsText(const std::string& text, const std::string& sourceName) {
  return parseResultsStreaming(text, sourceName);
}

namespace {
ResultsFile parseResults(const nlohmann::json& document, StreamedRuns& streamed,
                         const std::string& path) {
  JsonField root(document, path);
  if (!document.is_object() || !document.contains("schema") || !document.at("schema").is_string() ||
      document.at("schema").get<std::string>() != "pbdval-results")
    throw std::invalid_argument(
        path + ": expected a pbdval results file (\"schema\": \"pbdval-results\")");
  ResultsFile results;
  const double version = root.at("schemaVersion").number();
  if (version != kResultsSchemaVersion)
    throw std::invalid_argument(path + ": schemaVersion " + Json(version).dump() +
                                " is not supported (expected " +
                                std::to_string(kResultsSchemaVersion) + ")");
  if (root.has("metadata")) results.metadata = metadataFrom(root.at("metadata").expectObject());
  // The cases block carries every case's checks: without it the gate would skip them silently.
  const JsonField cases = root.at("cases").expectObject();
  for (const std::string& name : cases.keys()) {
    results.cases[name] = caseGateDataFrom(cases.at(name).expectObject());
  }
  root.at("runs").expectArray();  // its elements were streamed
  results.runs = std::move(streamed.records);
  for (std::size_t i = 0; i < results.runs.size(); ++i) {
    const std::string& caseName = results.runs[i].request.caseName;
    if (!results.cases.count(caseName))
      throw std::invalid_argument(path + ": runs[" + std::to_string(i) + "]: case \"" + caseName +
                                  "\" has no entry in \"cases\" (its checks would be skipped)");
  }
  if (streamed.firstError) std::rethrow_exception(streamed.firstError);
  return results;
}

}  // namespace

// ---- results.json's runs copied on (pbdval merge) --------------------------------------------
// A merge writes every record of its shards again unchanged (but its trajectory path). Reading a
// record into values (a map per metric, parameter and setting) and writing them back as text is
// what cost a merge of 10,000 runs seconds; here each record is read once, token by token, in the
// writer's own layout, and its text for the merged file is written as it is read. Strings are
// copied as they are when they are printable ASCII without escapes (the form the writer gives
// them); numbers are read and written again in the writer's form (nlohmann's shortest round trip),
// so that a shard written by another JSON writer (another indentation or number spelling) gives
// the same bytes as readResults and writeResults would. Whatever is of another form goes the
// readResults way: a record with members in another order, missing or added (read as a document,
// written from its values), or a file that is not in order (read again by readResults, whose error
// the caller gets).
namespace {

/// What the copying reader does not take itself (see above).
struct OtherForm {};

bool isJsonSpace(char c) {
  return c == ' ' || c == '\n' || c == '\r' || c == '\t';
}

/// A JSON string token: the bytes between its quotes, and whether they are the string itself
/// (printable ASCII without a backslash: what appendString writes as it is).
struct StringToken {
  std::string_view raw;
  bool plain = true;
};

/// JSON tokens read from text; whatever is not JSON throws OtherForm.
class Cursor {
 public:
  Cursor(const char* begin, const char* end) : at_(begin), end_(end) {}
  const char* at() const { return at_; }
  const char* end() const { return end_; }
  void skipSpace() {
    while (at_ != end_ && isJsonSpace(*at_))
      ++at_;
  }
  bool atEnd() {
    skipSpace();
    return at_ == end_;
  }
  /// Takes the character `c` when it comes next.
  bool take(char c) {
    skipSpace();
    if (at_ == end_ || *at_ != c) return false;
    ++at_;
    return true;
  }
  void expect(char c) {
    if (!take(c)) throw OtherForm{};
  }
  /// Takes the literal `word` (null) when it comes next.
  bool takeWord(std::string_view word) {
    skipSpace();
    if (std::size_t(end_ - at_) < word.size() || std::string_view(at_, word.size()) != word)
      return false;
    at_ += word.size();
    return true;
  }
  StringToken string() {
    expect('"');
    const char* begin = at_;
    const void* quote = std::memchr(at_, '"', std::size_t(end_ - at_));
    if (!quote) throw OtherForm{};
    const char* close = static_cast<const char*>(quote);
    unsigned other = 0;  // a control character, a backslash or a byte outside printable ASCII
    for (const char* c = begin; c != close; ++c) {
      const auto byte = static_cast<unsigned char>(*c);
      other |= unsigned(byte < 0x20) | unsigned(byte >= 0x7f) | unsigned(byte == '\\');
    }
    if (!other) {
      at_ = close + 1;
      return {std::string_view(begin, std::size_t(close - begin)), true};
    }
    // The string's true end, past escaped quotes (its escapes and UTF-8 are checked by decoded).
    const char* c = begin;
    while (c != end_ && *c != '"') {
      if (static_cast<unsigned char>(*c) < 0x20) throw OtherForm{};
      if (*c == '\\' && ++c == end_) throw OtherForm{};
      ++c;
    }
    if (c == end_) throw OtherForm{};
    at_ = c + 1;
    return {std::string_view(begin, std::size_t(c - begin)), false};
  }
  /// A number token (JSON's grammar: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?).
  std::string_view number() {
    skipSpace();
    const char* begin = at_;
    const auto digits = [this] {
      const char* from = at_;
      while (at_ != end_ && *at_ >= '0' && *at_ <= '9')
        ++at_;
      if (at_ == from) throw OtherForm{};
    };
    if (at_ != end_ && *at_ == '-') ++at_;
    if (at_ != end_ && *at_ == '0')
      ++at_;
    else
      digits();
    if (at_ != end_ && *at_ == '.') {
      ++at_;
      digits();
    }
    if (at_ != end_ && (*at_ == 'e' || *at_ == 'E')) {
      ++at_;
      if (at_ != end_ && (*at_ == '+' || *at_ == '-')) ++at_;
      digits();
    }
    return {begin, std::size_t(at_ - begin)};
  }
  /// Skips one value, following its brackets and strings only (what it spans is checked by the
  /// JSON parser that reads it next).
  void skipValue() {
    int depth = 0;
    do {
      skipSpace();
      if (at_ == end_) throw OtherForm{};
      const char c = *at_;
      if (c == '"') {
        (void)string();
      } else if (c == '{' || c == '[') {
        ++depth;
        ++at_;
      } else if (c == '}' || c == ']') {
        if (--depth < 0) throw OtherForm{};
        ++at_;
      } else if (c == ',' || c == ':') {
        if (depth == 0) throw OtherForm{};
        ++at_;
      } else {  // a number or a literal
        ++at_;
        while (at_ != end_ && !isJsonSpace(*at_) && std::strchr(",:{}[]\"", *at_) == nullptr)
          ++at_;
      }
    } while (depth > 0);
  }

 private:
  const char* at_;
  const char* end_;
};

/// The string a token of escapes or non-ASCII bytes stands for, decoded by nlohmann (the
/// document reader's decoding, its checks of escapes and UTF-8).
std::string decoded(const StringToken& token) {
  try {
    return Json::parse(token.raw.data() - 1, token.raw.data() + token.raw.size() + 1)
        .get<std::string>();
  } catch (const Json::exception&) {
    throw OtherForm{};
  }
}

// The indentation of a record's members, of the members of its objects and of theirs
// (writeResultsText: the runs array is a top-level member's value).
constexpr std::string_view kMemberIndent = "      ";
constexpr std::string_view kNestedIndent = "        ";
constexpr std::string_view kNested2Indent = "          ";

/// One record of the runs array, read on the fast path (see above): its request, status, reason
/// and the kept metrics as values, its text as writeResultsText writes it, up to the value of
/// "trajectory". Throws OtherForm for a record of another form, having written part of it.
class RecordCopier {
 public:
  explicit RecordCopier(const std::vector<std::string>& keptMetrics) : kept_(keptMetrics) {}

  void copy(Cursor& in, RunRecord& record, std::string& out) {
    RunRequest& request = record.request;
    in.expect('{');
    out += '{';
    member(in, "assignments", true, out, kMemberIndent);
    strings(in, out, &request.assignments);
    member(in, "case", false, out, kMemberIndent);
    request.caseName = string(in, out);
    member(in, "caseFile", false, out, kMemberIndent);
    request.caseFile = string(in, out);
    member(in, "engine", false, out, kMemberIndent);
    request.engine = string(in, out);
    member(in, "facts", false, out, kMemberIndent);
    in.expect('{');
    out += '{';
    member(in, "contactMargin", true, out, kNestedIndent);
    (void)number(in, out, false);
    member(in, "engineVersion", false, out, kNestedIndent);
    (void)string(in, out);
    member(in, "integratorStepsPerSceneStep", false, out, kNestedIndent);
    (void)integer(in, out);
    close(in, '}', out, kMemberIndent);
    member(in, "fineDivisor", false, out, kMemberIndent);
    request.fineDivisor = integer(in, out);
    member(in, "joint_error_by_type", false, out, kMemberIndent);
    map(in, out, kNestedIndent, kMemberIndent, [&](std::string_view) { jointErrors(in, out); });
    member(in, "method", false, out, kMemberIndent);
    request.method = string(in, out);
    member(in, "metrics", false, out, kMemberIndent);
    map(in, out, kNestedIndent, kMemberIndent, [&](std::string_view name) {
      const double value = number(in, out, true);
      if (std::find(kept_.begin(), kept_.end(), name) != kept_.end())
        record.metrics.values[std::string(name)] = value;
    });
    member(in, "notes", false, out, kMemberIndent);
    strings(in, out, nullptr);
    member(in, "parameters", false, out, kMemberIndent);
    map(in, out, kNestedIndent, kMemberIndent, [&](std::string_view) { (void)string(in, out); });
    member(in, "reason", false, out, kMemberIndent);
    record.reason = string(in, out);
    member(in, "reference", false, out, kMemberIndent);
    (void)string(in, out);
    member(in, "referenceMode", false, out, kMemberIndent);
    request.referenceMode = string(in, out);
    member(in, "referenceStepSize", false, out, kMemberIndent);
    request.referenceStepSize = number(in, out, false);
    member(in, "sampleInterval", false, out, kMemberIndent);
    request.sampleInterval = number(in, out, false);
    member(in, "settings", false, out, kMemberIndent);
    map(in, out, kNestedIndent, kMemberIndent, [&](std::string_view) { (void)string(in, out); });
    member(in, "state_hash", false, out, kMemberIndent);
    (void)string(in, out);
    member(in, "status", false, out, kMemberIndent);
    const std::optional<RunStatus> status = runStatusNamed(string(in, out));
    if (!status) throw OtherForm{};
    record.status = *status;
    member(in, "trajectory", false, out, kMemberIndent);
    const StringToken trajectory = in.string();  // written by writeResultsText, maybe changed
    request.trajectoryPath = trajectory.plain ? std::string(trajectory.raw) : decoded(trajectory);
    in.expect('}');
  }

 private:
  /// The member `name` comes next (after a comma unless `first`): its line is written.
  static void member(Cursor& in, std::string_view name, bool first, std::string& out,
                     std::string_view indent) {
    if (!first) in.expect(',');
    const StringToken key = in.string();
    if (!key.plain || key.raw != name) throw OtherForm{};
    in.expect(':');
    memberLine(key.raw, first, out, indent);
  }
  static void memberLine(std::string_view name, bool first, std::string& out,
                         std::string_view indent) {
    out += first ? "\n" : ",\n";
    out += indent;
    out += '"';
    out += name;
    out += "\": ";
  }
  /// The closing bracket `c` of an object or array that has members, on a line at `indent`.
  static void close(Cursor& in, char c, std::string& out, std::string_view indent) {
    in.expect(c);
    out += '\n';
    out += indent;
    out += c;
  }
  /// A string, written as appendString writes it; the string (valid until the next call).
  std::string_view string(Cursor& in, std::string& out) {
    const StringToken token = in.string();
    if (token.plain) {
      out += '"';
      out += token.raw;
      out += '"';
      return token.raw;
    }
    decoded_ = decoded(token);
    appendString(out, decoded_);
    return decoded_;
  }
  /// A number (or null where `nullable`: NaN, as recordFromJson reads it), written as
  /// appendNumber writes its value; the value.
  static double number(Cursor& in, std::string& out, bool nullable) {
    if (nullable && in.takeWord("null")) {
      out += "null";
      return std::nan("");
    }
    const std::string_view text = in.number();
    double value = 0;  // "-0" is the integer 0 to nlohmann, read as +0.0
    if (text != "-0") {
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      // Out of a double's range (1e400): nlohmann's value is another (infinite), not ours.
      if (error != std::errc() || end != text.data() + text.size()) throw OtherForm{};
    }
    appendNumber(out, value);
    return value;
  }
  /// An integer in std::to_string's form (no fraction or exponent, not -0) and int's range
  /// (at most 9 digits), written as it is.
  static int integer(Cursor& in, std::string& out) {
    const std::string_view text = in.number();
    int value = 0;
    const std::size_t digits = text.size() - (text[0] == '-' ? 1 : 0);
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (digits > 9 || text == "-0" || error != std::errc() || end != text.data() + text.size())
      throw OtherForm{};
    out += text;
    return value;
  }
  /// An array of strings, written as appendStrings writes it at a record's member.
  void strings(Cursor& in, std::string& out, std::vector<std::string>* values) {
    in.expect('[');
    if (in.take(']')) {
      out += "[]";
      return;
    }
    out += '[';
    bool first = true;
    do {
      out += first ? "\n" : ",\n";
      out += kNestedIndent;
      const std::string_view text = string(in, out);
      if (values) values->emplace_back(text);
      first = false;
    } while (in.take(','));
    close(in, ']', out, kMemberIndent);
  }
  /// An object of a std::map (keys in increasing byte order, printable ASCII), its members at
  /// `indent`; `value(key)` reads and writes each member's value.
  template <class Value>
  static void map(Cursor& in, std::string& out, std::string_view indent,
                  std::string_view closeIndent, const Value& value) {
    in.expect('{');
    if (in.take('}')) {
      out += "{}";
      return;
    }
    out += '{';
    std::string_view previous;
    bool first = true;
    do {
      const StringToken key = in.string();
      if (!key.plain || (!first && key.raw <= previous)) throw OtherForm{};
      in.expect(':');
      memberLine(key.raw, first, out, indent);
      value(key.raw);
      previous = key.raw;
      first = false;
    } while (in.take(','));
    close(in, '}', out, closeIndent);
  }
  /// A joint type's summary: the angular pair when there is one, the linear pair, the joints,
  /// the motor tracking's three when there is a quantity (recordJson's members).
  void jointErrors(Cursor& in, std::string& out) {
    in.expect('{');
    out += '{';
    StringToken key = in.string();
    bool first = true;
    // The member whose key was read last must be `name`; then its value, then nextKey.
    const auto memberNamed = [&](std::string_view name) {
      if (!key.plain || key.raw != name) throw OtherForm{};
      in.expect(':');
      memberLine(name, first, out, kNested2Indent);
      first = false;
    };
    const auto nextKey = [&] {
      in.expect(',');
      key = in.string();
    };
    if (key.plain && key.raw == "joint_error_angular_max") {
      memberNamed("joint_error_angular_max");
      (void)number(in, out, true);
      nextKey();
      memberNamed("joint_error_angular_rms");
      (void)number(in, out, true);
      nextKey();
    }
    memberNamed("joint_error_linear_max");
    (void)number(in, out, true);
    nextKey();
    memberNamed("joint_error_linear_rms");
    (void)number(in, out, true);
    nextKey();
    memberNamed("joints");
    (void)integer(in, out);
    if (in.take(',')) {
      key = in.string();
      memberNamed("motor_tracking_max");
      (void)number(in, out, true);
      nextKey();
      memberNamed("motor_tracking_quantity");
      if (string(in, out).empty()) throw OtherForm{};  // an empty quantity: no tracking
      nextKey();
      memberNamed("motor_tracking_rms");
      (void)number(in, out, true);
    }
    close(in, '}', out, kNestedIndent);
  }

  const std::vector<std::string>& kept_;
  std::string decoded_;  ///< the last string decoded
};

/// A record of another form, read as the whole document's reader reads it (at the depth it has
/// there: inside an object and an array); any error throws OtherForm (readResults says it).
RunRecord recordOfOtherForm(std::string_view text, const std::string& path, std::size_t index) {
  try {
    const Json document = parseJsonText("[[" + std::string(text) + "]]", path);
    return recordFromJson(document.at(0).at(0), path + ": runs[" + std::to_string(index) + "]");
  } catch (const std::exception&) {
    throw OtherForm{};
  }
}

ResultsFile copyingRecords(const std::string& text, const std::string& path,
                           const std::vector<std::string>& keptMetrics) {
  Cursor in(text.data(), text.data() + text.size());
  const char* runsBegin = nullptr;
  const char* runsEnd = nullptr;
  StreamedRuns streamed;
  std::vector<std::string> texts;
  RecordCopier copier(keptMetrics);
  const auto copyRuns = [&] {
    in.expect('[');
    if (in.take(']')) return;
    std::size_t capacity = 0;
    do {
      in.skipSpace();
      const char* begin = in.at();
      RunRecord record;
      std::string recordText;
      recordText.reserve(capacity);
      try {
        copier.copy(in, record, recordText);
      } catch (const OtherForm&) {
        Cursor span(begin, in.end());
        span.skipValue();
        record = recordOfOtherForm(std::string_view(begin, std::size_t(span.at() - begin)), path,
                                   streamed.records.size());
        recordText.clear();
        in = span;
      }
      capacity = std::max(capacity, recordText.size());
      streamed.records.push_back(std::move(record));
      texts.push_back(std::move(recordText));
    } while (in.take(','));
    in.expect(']');
  };
  in.expect('{');
  if (!in.take('}')) {
    do {
      const StringToken key = in.string();
      if (!key.plain) throw OtherForm{};
      in.expect(':');
      if (key.raw == "runs") {
        if (runsBegin) throw OtherForm{};  // twice: readResults keeps the last
        in.skipSpace();
        runsBegin = in.at();
        copyRuns();
        runsEnd = in.at();
      } else {
        in.skipValue();
      }
    } while (in.take(','));
    in.expect('}');
  }
  if (!in.atEnd() || !runsBegin) throw OtherForm{};
  // The document around the runs, read as readResults reads it (with an empty runs array).
  std::string frame(text.data(), runsBegin);
  frame += "[]";
  frame.append(runsEnd, text.data() + text.size());
  ResultsFile results = parseResults(parseJsonText(frame, path), streamed, path);
  results.recordTexts = std::move(texts);
  return results;
}

}  // namespace

ResultsFile parseResultsTextCopyingRecords(const std::string& text, const std::string& sourceName,
                                           const std::vector<std::string>& keptMetrics) {
  try {
    return copyingRecords(text, sourceName, keptMetrics);
  } catch (const OtherForm&) {
  } catch (const std::invalid_argument&) {
  }
  return parseResultsText(text, sourceName);
}

ResultsFile readResultsCopyingRecords(const std::string& path,
                                      const std::vector<std::string>& keptMetrics) {
  return parseResultsTextCopyingRecords(readJsonFileText(path, "results"), path, keptMetrics);
}

}  // namespace pbdval
