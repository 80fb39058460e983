#include "validation/io/json_input.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "pbd/io/input_checks.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& message) {
  throw std::invalid_argument(pbd::printableText(file + ": " + message));
}

std::string excerpt(const Json& value) {
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

/// nlohmann's parse with a callback: the depth limit, and `keep` deciding on each event (the
/// callback's contract: false drops the value); the messages of parseJsonText.
Json parseWithLimits(const std::string& text, const std::string& sourceName,
                     const std::function<bool(int, Json::parse_event_t, Json&)>& keep) {
  bool tooDeep = false;
  // The callback sees the depth of every value as it is read: stop at the limit rather than
  // build an arbitrarily deep document.
  const Json::parser_callback_t limitDepth = [&](int depth, Json::parse_event_t event,
                                                 Json& parsed) {
    // `depth` of an array or object start is the number of containers around it.
    const bool opens =
        event == Json::parse_event_t::array_start || event == Json::parse_event_t::object_start;
    if (opens && depth >= pbd::kMaxJsonDepth) {
      tooDeep = true;
      throw std::invalid_argument("nesting");
    }
    return !keep || keep(depth, event, parsed);
  };
  try {
    return Json::parse(text, limitDepth);
  } catch (const Json::exception& e) {
    // nlohmann's text: "[json.exception.parse_error.101] parse error at line 1, column 3: ..."
    std::string what = e.what();
    const std::size_t start = what.find("] ");
    if (start != std::string::npos) what = what.substr(start + 2);
    fail(sourceName, "not valid JSON: " + what);
  } catch (const std::invalid_argument&) {
    if (!tooDeep) throw;
    fail(sourceName, "arrays and objects nested deeper than " + std::to_string(pbd::kMaxJsonDepth) +
                         " levels (the limit for JSON inputs)");
  }
}

}  // namespace

Json parseJsonText(const std::string& text, const std::string& sourceName) {
  return parseWithLimits(text, sourceName, nullptr);
}

Json parseJsonTextStreaming(const std::string& text, const std::string& sourceName,
                            const std::vector<std::string>& streamedKeys,
                            const std::function<void(const std::string& key)>& onArray,
                            const StreamedElement& onElement) {
  // The callback's depths: the top-level object opens at 0, its keys and their values are at
  // 1, the elements of a top-level array at 2 (their object_end and array_end events too).
  std::string key;         // the top-level key being read
  bool streaming = false;  // inside the array of a streamed key
  std::size_t index = 0;
  const auto keep = [&](int depth, Json::parse_event_t event, Json& parsed) {
    using Event = Json::parse_event_t;
    if (depth == 1 && event == Event::key) {
      key = parsed.get<std::string>();
      return true;
    }
    if (depth == 1 && event == Event::array_start) {
      streaming = std::find(streamedKeys.begin(), streamedKeys.end(), key) != streamedKeys.end();
      index = 0;
      if (streaming) onArray(key);
      return true;
    }
    if (depth == 1 && event == Event::array_end) {
      streaming = false;
      return true;
    }
    const bool elementRead =
        event == Event::value || event == Event::object_end || event == Event::array_end;
    if (!streaming || depth != 2 || !elementRead) return true;
    onElement(key, index++, parsed);
    return false;  // dropped: the document keeps an empty array
  };
  return parseWithLimits(text, sourceName, keep);
}

std::string readJsonFileText(const std::string& path, const std::string& what) {
  const std::string problem = pbd::inputFileProblem(path, what);
  if (!problem.empty()) fail(path, problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be read");
  // Read in one piece, the size known: a 40 MB results.json is not copied through a stream.
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  std::string text;
  if (size < 0) {  // not seekable: read it as a stream
    in.clear();
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
  }
  text.resize(std::size_t(size));
  in.read(text.data(), size);
  text.resize(std::size_t(in.gcount()));
  if (in.bad()) fail(path, "cannot be read");
  return text;
}

Json readJsonFile(const std::string& path, const std::string& what) {
  return parseJsonText(readJsonFileText(path, what), path);
}

JsonField::JsonField(const Json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

void JsonField::fail(const std::string& expectation) const {
  pbdval::fail(file_, (path_.empty() ? std::string("top level") : path_) + ": expected " +
                          expectation + ", got " + excerpt(*value_));
}

JsonField& JsonField::expectObject() {
  if (!value_->is_object()) fail("an object");
  return *this;
}

JsonField& JsonField::expectArray() {
  if (!value_->is_array()) fail("an array");
  return *this;
}

bool JsonField::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

JsonField JsonField::at(const std::string& key) const {
  if (!value_->is_object()) fail("an object with the key \"" + key + "\"");
  const auto it = value_->find(key);
  const std::string path = path_.empty() ? key : path_ + "." + key;
  if (it == value_->end())
    pbdval::fail(file_, (path_.empty() ? std::string("top level") : path_) +
                            ": missing required key \"" + key + "\"");
  return JsonField(*it, file_, path);
}

JsonField JsonField::at(std::size_t index) const {
  if (!value_->is_array() || index >= value_->size()) fail("an array");
  return JsonField((*value_)[index], file_, path_ + "[" + std::to_string(index) + "]");
}

std::size_t JsonField::size() const {
  if (!value_->is_array()) fail("an array");
  return value_->size();
}

std::vector<std::string> JsonField::keys() const {
  if (!value_->is_object()) fail("an object");
  std::vector<std::string> result;
  for (const auto& item : value_->items())
    result.push_back(item.key());
  return result;
}

std::string JsonField::string() const {
  if (!value_->is_string()) fail("a string");
  return value_->get<std::string>();
}

double JsonField::number() const {
  if (!value_->is_number()) fail("a number");
  const double value = value_->get<double>();
  if (!std::isfinite(value)) fail("a finite number");
  return value;
}

long JsonField::integer(long minimum, long maximum) const {
  const std::string expectation =
      "an integer in [" + std::to_string(minimum) + ", " + std::to_string(maximum) + "]";
  if (!value_->is_number()) fail(expectation);
  const double value = value_->get<double>();  // compared as a double: no overflowing cast
  if (!(value >= double(minimum) && value <= double(maximum)) || value != std::floor(value))
    fail(expectation);
  return static_cast<long>(value);
}

std::vector<std::string> JsonField::strings() const {
  std::vector<std::string> result;
  for (std::size_t i = 0; i < size(); ++i)
    result.push_back(at(i).string());
  return result;
}

std::string JsonField::stringOr(const std::string& key, const std::string& fallback) const {
  return has(key) ? at(key).string() : fallback;
}

}  // namespace pbdval
