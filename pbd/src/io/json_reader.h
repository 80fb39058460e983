// Private helpers of the scene loader: JSON values that know their path in the document,
// typed readers with located error messages, and per-object key tables that record which keys
// were consumed, so that every other key can be reported as unknown.
//
// Only nlohmann's forward declarations appear here; the parser itself stays in .cpp files.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pbd/io/scene_loader.h"
#include "pbd/math/types.h"

namespace pbd::scene_io {

using Json = nlohmann::ordered_json;  // keeps the file's key order for messages and dumps

/// Collects the warnings of one load; in strict mode the first warning is thrown instead.
class DiagnosticSink {
 public:
  DiagnosticSink(std::string file, bool strict);

  const std::string& file() const { return file_; }
  [[noreturn]] void error(const std::string& jsonPath, const std::string& message) const;
  void warn(const std::string& jsonPath, const std::string& message);
  std::vector<SceneDiagnostic> takeWarnings() { return std::move(warnings_); }

 private:
  std::string file_;
  bool strict_;
  std::vector<SceneDiagnostic> warnings_;
};

/// The allowed interval of a number, able to describe itself ("> 0", "in [0, 4]").
struct Bounds {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool lowerOpen = false;

  bool contains(double value) const;
  std::string describe() const;  ///< empty for an unbounded interval
};
Bounds positive();
Bounds nonNegative();
Bounds atLeast(double lower);
Bounds between(double lower, double upper);

/// Parses JSON text into a document. Syntax errors are reported with line and column, numbers
/// that overflow (1e999) with their JSON path; duplicate keys are warnings (the last one wins).
Json parseJson(const std::string& text, DiagnosticSink& sink);

class JsonObject;

/// A node of the document together with its JSON path ("RigidBodies[3].scale").
class JsonValue {
 public:
  JsonValue(const Json& node, std::string path, DiagnosticSink& sink);

  const std::string& path() const { return path_; }
  DiagnosticSink& sink() const { return *sink_; }
  const Json& node() const { return *node_; }

  /// Throws "path: expected <expectation>, got <value>".
  [[noreturn]] void fail(const std::string& expectation) const;
  /// Throws "path: <message>".
  [[noreturn]] void error(const std::string& message) const;
  void warn(const std::string& message) const;

  bool isObject() const;
  std::string dump() const;

  Real number(const Bounds& bounds = {}) const;
  int integer(const Bounds& bounds = {}) const;
  bool boolean() const;  ///< true/false or 0/1, as the seed accepts
  std::string string() const;
  Vector3 vector3(const Bounds& componentBounds = {}) const;
  Vector3i integerVector3(const Bounds& componentBounds = {}) const;
  std::vector<Real> numbers() const;
  std::vector<int> integers(const Bounds& bounds = {}) const;

  /// The elements of an array; fails naming `elementDescription` when this is not an array.
  std::vector<JsonValue> elements(const std::string& elementDescription) const;
  JsonObject object() const;

 private:
  const Json* node_;
  std::string path_;
  DiagnosticSink* sink_;
};

/// A JSON object being read. Every key asked for (found or not) becomes a known key of the
/// object; warnUnknownKeys() then reports the others with suggestions.
class JsonObject {
 public:
  explicit JsonObject(const JsonValue& value);

  const std::string& path() const { return value_.path(); }
  const JsonValue& value() const { return value_; }
  [[noreturn]] void error(const std::string& message) const { value_.error(message); }
  void warn(const std::string& message) const { value_.warn(message); }

  std::optional<JsonValue> find(const std::string& key);
  bool has(const std::string& key);
  /// Fails with "missing required key" when absent; `why` explains when it is required.
  JsonValue require(const std::string& key, const std::string& why = "");
  /// The path a key of this object has ("Simulation.gravity").
  std::string keyPath(const std::string& key) const;

  /// One warning per key that no reader asked for, with a "did you mean" suggestion. The key
  /// `comment` is allowed everywhere (the seed's scenes use it for annotations).
  void warnUnknownKeys() const;

 private:
  void markKnown(const std::string& key);

  JsonValue value_;
  std::vector<std::string> knownKeys_;
};

/// One row of a key table: the key, how to read its value into the target and, for the scene
/// writer (scene_writer.cpp), how to write it back from the target into a JSON object (empty:
/// the writer handles the key itself).
template <class Target>
struct KeyReader {
  std::string key;
  std::function<void(const JsonValue&, Target&)> read;
  bool required = false;
  std::function<void(const Target&, Json&)> write{};
};

// Writers of single keys into a JSON object (defined with the parser, in json_reader.cpp).
void writeNumber(Json& object, const std::string& key, Real value);
void writeInteger(Json& object, const std::string& key, int value);
void writeBoolean(Json& object, const std::string& key, bool value);
void writeString(Json& object, const std::string& key, const std::string& value);
void writeVector(Json& object, const std::string& key, const Vector3& value);
void writeIntegerVector(Json& object, const std::string& key, const Vector3i& value);

template <class Target>
using KeyTable = std::vector<KeyReader<Target>>;

/// Reads every key of `table` that the object holds; a missing required key is an error.
template <class Target>
void readKeys(JsonObject& object, const KeyTable<Target>& table, Target& target) {
  for (const auto& entry : table) {
    if (auto value = object.find(entry.key)) {
      entry.read(*value, target);
    } else if (entry.required) {
      object.require(entry.key);
    }
  }
}

/// Writes every key of `table` that has a writer.
template <class Target>
void writeKeys(const KeyTable<Target>& table, const Target& target, Json& object) {
  for (const auto& entry : table)
    if (entry.write) entry.write(target, object);
}

template <class Target>
KeyReader<Target> required(KeyReader<Target> reader) {
  reader.required = true;
  return reader;
}

// Table rows for the common case "this key sets that member".
// Table rows for the common case "this key sets that member" (read and written back).
template <class Target>
KeyReader<Target> numberKey(std::string key, Real Target::*member, Bounds bounds = {}) {
  return {key, [member, bounds](const JsonValue& v, Target& t) { t.*member = v.number(bounds); },
          false, [key, member](const Target& t, Json& j) { writeNumber(j, key, t.*member); }};
}
/// A number whose absence means "the default of whatever uses it" (written back only when set).
template <class Target>
KeyReader<Target> numberKey(std::string key, std::optional<Real> Target::*member,
                            Bounds bounds = {}) {
  return {key, [member, bounds](const JsonValue& v, Target& t) { t.*member = v.number(bounds); },
          false,
          [key, member](const Target& t, Json& j) {
            if (t.*member) writeNumber(j, key, *(t.*member));
          }};
}
template <class Target>
KeyReader<Target> integerKey(std::string key, int Target::*member, Bounds bounds = {}) {
  return {key, [member, bounds](const JsonValue& v, Target& t) { t.*member = v.integer(bounds); },
          false, [key, member](const Target& t, Json& j) { writeInteger(j, key, t.*member); }};
}
template <class Target>
KeyReader<Target> booleanKey(std::string key, bool Target::*member) {
  return {key, [member](const JsonValue& v, Target& t) { t.*member = v.boolean(); }, false,
          [key, member](const Target& t, Json& j) { writeBoolean(j, key, t.*member); }};
}
template <class Target>
KeyReader<Target> vectorKey(std::string key, Vector3 Target::*member, Bounds bounds = {}) {
  return {key, [member, bounds](const JsonValue& v, Target& t) { t.*member = v.vector3(bounds); },
          false, [key, member](const Target& t, Json& j) { writeVector(j, key, t.*member); }};
}
template <class Target>
KeyReader<Target> stringKey(std::string key, std::string Target::*member) {
  return {key, [member](const JsonValue& v, Target& t) { t.*member = v.string(); }, false,
          [key, member](const Target& t, Json& j) { writeString(j, key, t.*member); }};
}

/// Formats a vector for messages: "[0, -9.81, 0]".
std::string formatVector(const Vector3& v);
/// Formats a number for messages with up to 10 significant digits.
std::string formatNumber(double value);

}  // namespace pbd::scene_io
