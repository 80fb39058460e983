#include "json_reader.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "pbd/io/input_checks.h"
#include "pbd/io/suggestion.h"

namespace pbd::scene_io {
namespace {

constexpr std::size_t kExcerptLength = 60;
// Allowed in every object and ignored: the seed's shipped scenes annotate objects with it.
constexpr const char* kCommentKey = "comment";

// Names the seed's shipped scenes use for keys that were renamed; the seed ignores them.
struct StaleKey {
  const char* stale;
  const char* current;
};
constexpr StaleKey kStaleKeys[] = {
    {"maxIter", "maxIterations"},
    {"maxIterVel", "maxIterationsV"},
    {"tetModelSimulationMethod", "solidSimulationMethod"},
    {"triangleModelSimulationMethod", "clothSimulationMethod"},
    {"triangleModelBendingMethod", "clothBendingMethod"},
};

// The text of a JSON value, shortened for messages.
std::string excerpt(const Json& node) {
  std::string text = node.dump();
  if (text.size() > kExcerptLength) text = text.substr(0, kExcerptLength - 3) + "...";
  return text;
}

std::string quoted(const std::string& text) {
  return "\"" + text + "\"";
}

bool contains(const std::vector<std::string>& keys, const std::string& key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

std::string unknownKeyMessage(const std::string& key, const std::vector<std::string>& known) {
  for (const auto& stale : kStaleKeys) {
    if (key == stale.stale && contains(known, stale.current)) {
      return "unknown key: a stale name that PositionBasedDynamics silently ignores; did you "
             "mean " +
             quoted(stale.current) + "?";
    }
  }
  if (const std::optional<std::string> best = closestName(key, known))
    return "unknown key (ignored); did you mean " + quoted(*best) + "?";
  return "unknown key (ignored)";
}

std::string withBounds(const std::string& what, const Bounds& bounds) {
  const std::string description = bounds.describe();
  return description.empty() ? what : what + " " + description;
}

// Builds the document through nlohmann's SAX interface so that the JSON path of every value is
// known while parsing: overflowing numbers are reported with their path, duplicate keys are
// warned about.
class DocumentBuilder {
 public:
  using number_integer_t = Json::number_integer_t;
  using number_unsigned_t = Json::number_unsigned_t;
  using number_float_t = Json::number_float_t;
  using string_t = Json::string_t;
  using binary_t = Json::binary_t;

  DocumentBuilder(Json& root, const std::string& text, DiagnosticSink& sink)
      : root_(root), text_(text), sink_(sink) {}

  bool null() { return place(Json(nullptr)) != nullptr; }
  bool boolean(bool value) { return place(Json(value)) != nullptr; }
  bool number_integer(number_integer_t value) { return place(Json(value)) != nullptr; }
  bool number_unsigned(number_unsigned_t value) { return place(Json(value)) != nullptr; }
  bool number_float(number_float_t value, const string_t&) { return place(Json(value)) != nullptr; }
  bool string(string_t& value) { return place(Json(value)) != nullptr; }
  bool binary(binary_t& value) { return place(Json::binary(value)) != nullptr; }

  bool start_object(std::size_t) { return open(Json::object()); }
  bool start_array(std::size_t) { return open(Json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(string_t& key) {
    Frame& frame = stack_.back();
    frame.key = key;
    if (frame.container->contains(key)) {
      sink_.warn(valuePath(), "duplicate key; the last value is used (as in the seed)");
    }
    return true;
  }

  bool parse_error(std::size_t position, const std::string& lastToken,
                   const nlohmann::detail::exception& ex) {
    if (ex.id == 406) {  // number overflow: 1e999 and the like
      sink_.error(valuePath(), "expected a finite number, got " + lastToken);
    }
    sink_.error("", "invalid JSON at " + lineAndColumn(position) + ": " + detail(ex.what()));
  }

 private:
  struct Frame {
    Json* container;
    std::string path;
    std::string key;        // objects: the key of the value being read
    std::size_t index = 0;  // arrays: the index of the value being read
  };

  std::string valuePath() const {
    if (stack_.empty()) return "";
    const Frame& frame = stack_.back();
    if (frame.container->is_array()) return frame.path + "[" + std::to_string(frame.index) + "]";
    return frame.path.empty() ? frame.key : frame.path + "." + frame.key;
  }

  Json* place(Json value) {
    if (stack_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    Frame& frame = stack_.back();
    if (frame.container->is_array()) {
      frame.container->push_back(std::move(value));
      ++frame.index;
      return &frame.container->back();
    }
    Json& slot = (*frame.container)[frame.key];
    slot = std::move(value);
    return &slot;
  }

  bool open(Json container) {
    const std::string path = valuePath();
    // Without a limit, 100 000 nested '[' cost seconds and gigabytes (every level keeps its
    // path) before failing somewhere else.
    if (stack_.size() >= static_cast<std::size_t>(kMaxJsonDepth)) {
      sink_.error(path, "arrays and objects nested deeper than " + std::to_string(kMaxJsonDepth) +
                            " levels (the limit for scene files)");
    }
    Json* placed = place(std::move(container));
    stack_.push_back(Frame{placed, path, {}, 0});
    return true;
  }

  bool close() {
    stack_.pop_back();
    return true;
  }

  std::string lineAndColumn(std::size_t position) const {
    // nlohmann reports the number of characters read; the offending one is the last of them.
    const std::size_t offending = std::min(position > 0 ? position - 1 : 0, text_.size());
    std::size_t line = 1, lineStart = 0;
    for (std::size_t i = 0; i < offending; ++i) {
      if (text_[i] == '\n') {
        ++line;
        lineStart = i + 1;
      }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(offending - lineStart + 1);
  }

  // nlohmann's message without its "[json.exception...] parse error at line L, column C: ".
  static std::string detail(const std::string& what) {
    const std::size_t column = what.find("column ");
    const std::size_t colon = what.find(": ", column == std::string::npos ? 0 : column);
    return colon == std::string::npos ? what : what.substr(colon + 2);
  }

  Json& root_;
  const std::string& text_;
  DiagnosticSink& sink_;
  std::vector<Frame> stack_;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

DiagnosticSink::DiagnosticSink(std::string file, bool strict)
    : file_(std::move(file)), strict_(strict) {}

void DiagnosticSink::error(const std::string& jsonPath, const std::string& message) const {
  throw SceneError(SceneDiagnostic{file_, jsonPath, message});
}

void DiagnosticSink::warn(const std::string& jsonPath, const std::string& message) {
  if (strict_) error(jsonPath, message + " [strict: warnings are errors]");
  warnings_.push_back(
      SceneDiagnostic{printableText(file_), printableText(jsonPath), printableText(message)});
}

// ---------------------------------------------------------------------------------------------

bool Bounds::contains(double value) const {
  const bool aboveLower = lowerOpen ? value > lower : value >= lower;
  return aboveLower && value <= upper;
}

std::string Bounds::describe() const {
  const bool hasLower = std::isfinite(lower), hasUpper = std::isfinite(upper);
  if (hasLower && hasUpper) {
    return std::string("in ") + (lowerOpen ? "(" : "[") + formatNumber(lower) + ", " +
           formatNumber(upper) + "]";
  }
  if (hasLower) return (lowerOpen ? "> " : ">= ") + formatNumber(lower);
  if (hasUpper) return "<= " + formatNumber(upper);
  return "";
}

Bounds positive() {
  return Bounds{0, std::numeric_limits<double>::infinity(), true};
}
Bounds nonNegative() {
  return atLeast(0);
}
Bounds atLeast(double lower) {
  return Bounds{lower, std::numeric_limits<double>::infinity(), false};
}
Bounds between(double lower, double upper) {
  return Bounds{lower, upper, false};
}

// ---------------------------------------------------------------------------------------------

Json parseJson(const std::string& text, DiagnosticSink& sink) {
  Json root;
  DocumentBuilder builder(root, text, sink);
  Json::sax_parse(text, &builder);
  return root;
}

// ---------------------------------------------------------------------------------------------

JsonValue::JsonValue(const Json& node, std::string path, DiagnosticSink& sink)
    : node_(&node), path_(std::move(path)), sink_(&sink) {}

void JsonValue::fail(const std::string& expectation) const {
  error("expected " + expectation + ", got " + excerpt(*node_));
}

void JsonValue::error(const std::string& message) const {
  sink_->error(path_, message);
}

void JsonValue::warn(const std::string& message) const {
  sink_->warn(path_, message);
}

bool JsonValue::isObject() const {
  return node_->is_object();
}
std::string JsonValue::dump() const {
  return node_->dump();
}

Real JsonValue::number(const Bounds& bounds) const {
  if (!node_->is_number()) fail(withBounds("a number", bounds));
  const double value = node_->get<double>();
  // Checked after the conversion: a double that is finite may overflow a float build.
  if (!std::isfinite(static_cast<Real>(value))) fail("a finite number");
  if (!bounds.contains(value)) fail(withBounds("a number", bounds));
  return static_cast<Real>(value);
}

int JsonValue::integer(const Bounds& bounds) const {
  const std::string expectation = withBounds("an integer", bounds);
  if (!node_->is_number()) fail(expectation);
  double value = 0;
  if (node_->is_number_unsigned()) {
    const auto u = node_->get<Json::number_unsigned_t>();
    if (u > static_cast<Json::number_unsigned_t>(INT_MAX)) fail(expectation);
    value = static_cast<double>(u);
  } else if (node_->is_number_integer()) {
    const auto i = node_->get<Json::number_integer_t>();
    if (i > INT_MAX || i < INT_MIN) fail(expectation);
    value = static_cast<double>(i);
  } else {
    value = node_->get<double>();  // 2.0 is accepted as 2; 2.5 is not an integer
    if (std::floor(value) != value || value > INT_MAX || value < INT_MIN) fail(expectation);
  }
  if (!bounds.contains(value)) fail(expectation);
  return static_cast<int>(value);
}

bool JsonValue::boolean() const {
  if (node_->is_boolean()) return node_->get<bool>();
  if (node_->is_number()) {
    const double value = node_->get<double>();
    if (value == 0 || value == 1) return value == 1;
  }
  fail("a boolean (true/false or 0/1)");
}

std::string JsonValue::string() const {
  if (!node_->is_string()) fail("a string");
  return node_->get<std::string>();
}

Vector3 JsonValue::vector3(const Bounds& componentBounds) const {
  const std::string expectation = withBounds("an array of 3 finite numbers", componentBounds);
  if (!node_->is_array() || node_->size() != 3) fail(expectation);
  Vector3 result;
  for (int i = 0; i < 3; ++i) {
    const Json& component = (*node_)[static_cast<std::size_t>(i)];
    if (!component.is_number()) fail(expectation);
    const double value = component.get<double>();
    if (!std::isfinite(static_cast<Real>(value)) || !componentBounds.contains(value)) {
      fail(expectation);
    }
    result[i] = static_cast<Real>(value);
  }
  return result;
}

Vector3i JsonValue::integerVector3(const Bounds& componentBounds) const {
  if (!node_->is_array() || node_->size() != 3) {
    fail(withBounds("an array of 3 integers", componentBounds));
  }
  Vector3i result;
  for (int i = 0; i < 3; ++i) {
    const JsonValue component((*node_)[static_cast<std::size_t>(i)],
                              path_ + "[" + std::to_string(i) + "]", *sink_);
    result[i] = component.integer(componentBounds);
  }
  return result;
}

std::vector<Real> JsonValue::numbers() const {
  if (!node_->is_array()) fail("an array of finite numbers");
  std::vector<Real> result;
  for (const JsonValue& element : elements("finite numbers"))
    result.push_back(element.number());
  return result;
}

std::vector<int> JsonValue::integers(const Bounds& bounds) const {
  if (!node_->is_array()) fail(withBounds("an array of integers", bounds));
  std::vector<int> result;
  for (const JsonValue& element : elements("integers"))
    result.push_back(element.integer(bounds));
  return result;
}

std::vector<JsonValue> JsonValue::elements(const std::string& elementDescription) const {
  if (!node_->is_array()) fail("an array of " + elementDescription);
  std::vector<JsonValue> result;
  result.reserve(node_->size());
  for (std::size_t i = 0; i < node_->size(); ++i) {
    result.emplace_back((*node_)[i], path_ + "[" + std::to_string(i) + "]", *sink_);
  }
  return result;
}

JsonObject JsonValue::object() const {
  return JsonObject(*this);
}

// ---------------------------------------------------------------------------------------------

JsonObject::JsonObject(const JsonValue& value) : value_(value) {
  if (!value.isObject()) value.fail("an object");
}

void JsonObject::markKnown(const std::string& key) {
  if (!contains(knownKeys_, key)) knownKeys_.push_back(key);
}

std::optional<JsonValue> JsonObject::find(const std::string& key) {
  markKnown(key);
  const auto it = value_.node().find(key);
  if (it == value_.node().end()) return std::nullopt;
  return JsonValue(*it, keyPath(key), value_.sink());
}

bool JsonObject::has(const std::string& key) {
  return find(key).has_value();
}

JsonValue JsonObject::require(const std::string& key, const std::string& why) {
  if (auto value = find(key)) return *value;
  error("missing required key " + quoted(key) + (why.empty() ? "" : " (" + why + ")"));
}

std::string JsonObject::keyPath(const std::string& key) const {
  return path().empty() ? key : path() + "." + key;
}

void JsonObject::warnUnknownKeys() const {
  for (const auto& item : value_.node().items()) {
    if (item.key() != kCommentKey && !contains(knownKeys_, item.key())) {
      value_.sink().warn(keyPath(item.key()), unknownKeyMessage(item.key(), knownKeys_));
    }
  }
}

// ---------------------------------------------------------------------------------------------

std::string formatNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string formatVector(const Vector3& v) {
  return "[" + formatNumber(static_cast<double>(v.x())) + ", " +
         formatNumber(static_cast<double>(v.y())) + ", " +
         formatNumber(static_cast<double>(v.z())) + "]";
}

void writeNumber(Json& object, const std::string& key, Real value) {
  object[key] = double(value);
}
void writeInteger(Json& object, const std::string& key, int value) {
  object[key] = value;
}
void writeBoolean(Json& object, const std::string& key, bool value) {
  object[key] = value;
}
void writeString(Json& object, const std::string& key, const std::string& value) {
  object[key] = value;
}
void writeVector(Json& object, const std::string& key, const Vector3& value) {
  object[key] = {double(value.x()), double(value.y()), double(value.z())};
}
void writeIntegerVector(Json& object, const std::string& key, const Vector3i& value) {
  object[key] = {value.x(), value.y(), value.z()};
}

}  // namespace pbd::scene_io
