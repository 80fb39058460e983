// Reading validation's own JSON files (results.json, baselines): the file must be a regular
// file, the JSON at most pbd::kMaxJsonDepth levels deep, and every message valid UTF-8 with the
// file name in front. JsonField walks a document with the JSON path of every value, so that a
// wrong type is reported as "runs[2].metrics.energy_drift_max: expected a number, got "abc"".
#pragma once

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pbdval {

/// Parses the file at `path` (`what` names it: "results", "baseline"); throws
/// std::invalid_argument "PATH: what is wrong".
nlohmann::json readJsonFile(const std::string& path, const std::string& what);
/// Parses `text` (named `sourceName` in messages) with the same limits.
nlohmann::json parseJsonText(const std::string& text, const std::string& sourceName);

/// An element of a streamed array (parseJsonTextStreaming): the top-level key that holds the
/// array, the element's index in it and its value (the receiver may move from it).
using StreamedElement =
    std::function<void(const std::string& key, std::size_t index, nlohmann::json& element)>;

/// parseJsonText for documents too big to hold whole (results.json of 10,000 runs): each element
/// of the array under a top-level key named in `streamedKeys` is handed to `onElement` as soon as
/// it has been read, then dropped (`onArray` is called with the key when such an array opens: a
/// key given twice opens twice, and its last value counts, as in parseJsonText's document); the
/// document returned holds those keys with empty arrays (a value that is not an array is kept as it
/// is, for the caller's error message). The same limits and messages as parseJsonText: an error of
/// syntax or depth anywhere in the text throws, even after elements were handed over.
nlohmann::json parseJsonTextStreaming(const std::string& text, const std::string& sourceName,
                                      const std::vector<std::string>& streamedKeys,
                                      const std::function<void(const std::string& key)>& onArray,
                                      const StreamedElement& onElement);
/// The file's bytes, for parseJsonTextStreaming, after the checks readJsonFile makes (a regular
/// file, readable); throws std::invalid_argument "PATH: what is wrong".
std::string readJsonFileText(const std::string& path, const std::string& what);

/// A value of a document with its JSON path; every accessor throws std::invalid_argument
/// "FILE: PATH: expected ..., got ..." on a missing key or a wrong type.
class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string file, std::string path = "");

  bool has(const std::string& key) const;
  JsonField at(const std::string& key) const;  ///< a required key
  JsonField at(std::size_t index) const;
  std::size_t size() const;               ///< of an array
  std::vector<std::string> keys() const;  ///< of an object, in the document's order

  std::string string() const;
  double number() const;                           ///< a finite number
  long integer(long minimum, long maximum) const;  ///< an integer in [minimum, maximum]
  std::vector<std::string> strings() const;
  std::string stringOr(const std::string& key, const std::string& fallback) const;

  JsonField& expectObject();
  JsonField& expectArray();
  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& expectation) const;

 private:
  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

}  // namespace pbdval
