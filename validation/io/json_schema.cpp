#include "validation/io/json_schema.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "pbdval/build_info.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

// `$defs` holds subschemas for `$ref`; it checks nothing where it stands.
constexpr std::array<const char*, 8> kAnnotations = {
    "$schema", "$id", "title", "description", "$comment", "default", "examples", "$defs"};
constexpr std::array<const char*, 17> kKeywords = {
    "type",  "const",   "enum",      "required", "properties",  "additionalProperties",
    "items", "minimum", "minLength", "minItems", "uniqueItems", "pattern",
    "if",    "then",    "else",      "allOf",    "$ref"};

// How many `$ref`s may follow one another without the document moving to a child value: more
// is a loop in the schema ({"$ref": "#"}), refused instead of recursing without end. The
// project's schemas chain at most one.
constexpr int kMaxChainedReferences = 16;

std::string childPath(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string shown(const std::string& path) {
  return path.empty() ? "(document)" : path;
}

std::string brief(const Json& value) {
  std::string text = value.dump();
  return text.size() > 60 ? text.substr(0, 57) + "..." : text;
}

bool hasType(const Json& value, const std::string& type) {
  if (type == "object") return value.is_object();
  if (type == "array") return value.is_array();
  if (type == "string") return value.is_string();
  if (type == "boolean") return value.is_boolean();
  if (type == "null") return value.is_null();
  if (type == "number") return value.is_number();
  if (type == "integer")  // a number without a fractional part (JSON Schema: 1.0 is one)
    return value.is_number_integer() ||
           (value.is_number_float() && std::isfinite(value.get<double>()) &&
            std::floor(value.get<double>()) == value.get<double>());
  throw std::invalid_argument("schema: unknown type \"" + type + "\"");
}

/// A list of names as a sentence: "a", "a or b", "a, b or c".
std::string alternatives(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

/// The subschema a local `$ref` ("#/$defs/parameter", a JSON pointer into the root schema) names.
const Json& referenced(const Json& root, const Json& reference) {
  const std::string text = reference.is_string() ? reference.get<std::string>() : reference.dump();
  if (text.empty() || text[0] != '#')
    throw std::invalid_argument("schema: $ref \"" + text +
                                "\": only references into the same schema (#/...) are supported");
  try {
    return root.at(Json::json_pointer(text.substr(1)));
  } catch (const Json::exception&) {
    throw std::invalid_argument("schema: $ref \"" + text + "\" names nothing in the schema");
  }
}

/// One validation: the root schema, and each `pattern` compiled once (compiling an ECMAScript
/// expression is costly: compiled for every string it checks, the engine catalogue's patterns
/// took 200 M instructions of every command's start, docs/benchmarks.md).
struct Validation {
  const Json& root;
  std::map<std::string, std::regex> patterns;

  const std::regex& pattern(const std::string& text, const std::string& path) {
    const auto found = patterns.find(text);
    if (found != patterns.end()) return found->second;
    try {
      return patterns.emplace(text, std::regex(text, std::regex::ECMAScript)).first->second;
    } catch (const std::regex_error&) {
      throw std::invalid_argument("schema: pattern \"" + text + "\" at " + shown(path) +
                                  " is not a regular expression");
    }
  }
};

/// Checks `value` (at `path`) against `schema`, a part of the validation's root; `chained`
/// counts the `$ref`s followed since the document last moved to a child value.
void check(Validation& validation, const Json& schema, const Json& value, const std::string& path,
           int chained, std::vector<std::string>& violations) {
  if (schema.is_boolean()) {
    if (!schema.get<bool>()) violations.push_back(shown(path) + ": not allowed here");
    return;
  }
  if (!schema.is_object())
    throw std::invalid_argument("schema at " + shown(path) + ": not an object");
  for (const auto& item : schema.items()) {
    const std::string& key = item.key();
    const bool known =
        std::find(kKeywords.begin(), kKeywords.end(), key) != kKeywords.end() ||
        std::find(kAnnotations.begin(), kAnnotations.end(), key) != kAnnotations.end();
    if (!known) throw std::invalid_argument("schema keyword \"" + key + "\" is not supported");
  }
  const auto fail = [&](const std::string& expected) {
    violations.push_back(shown(path) + ": expected " + expected + ", got " + brief(value));
  };
  if (schema.contains("$ref")) {
    if (chained >= kMaxChainedReferences)
      throw std::invalid_argument("schema: $ref " + schema.at("$ref").dump() + " at " +
                                  shown(path) + " loops without reaching a value");
    check(validation, referenced(validation.root, schema.at("$ref")), value, path, chained + 1,
          violations);
  }
  if (schema.contains("type")) {
    const Json& type = schema.at("type");
    std::vector<std::string> types;
    if (type.is_string())
      types.push_back(type.get<std::string>());
    else
      for (const Json& t : type)
        types.push_back(t.get<std::string>());
    if (std::none_of(types.begin(), types.end(),
                     [&](const std::string& t) { return hasType(value, t); })) {
      std::vector<std::string> named;
      for (const std::string& t : types)
        named.push_back(t == "object" || t == "array" || t == "integer" ? "an " + t
                        : t == "null"                                   ? t
                                                                        : "a " + t);
      fail(alternatives(named));
      return;  // the other keywords would only repeat it
    }
  }
  if (schema.contains("const") && value != schema.at("const")) fail(schema.at("const").dump());
  if (schema.contains("enum")) {
    const Json& options = schema.at("enum");
    if (std::find(options.begin(), options.end(), value) == options.end()) {
      std::vector<std::string> named;
      for (const Json& o : options)
        named.push_back(o.dump());
      fail("one of " + alternatives(named));
    }
  }
  if (schema.contains("minimum") && value.is_number() &&
      value.get<double>() < schema.at("minimum").get<double>())
    fail("a number >= " + schema.at("minimum").dump());
  if (schema.contains("minLength") && value.is_string() &&
      value.get<std::string>().size() < schema.at("minLength").get<std::size_t>())
    fail(schema.at("minLength").get<std::size_t>() == 1
             ? std::string("a non-empty string")
             : "a string of at least " + schema.at("minLength").dump() + " characters");
  if (schema.contains("pattern") && value.is_string()) {
    // ECMA-262 regular expressions, as JSON Schema specifies; matched anywhere unless anchored.
    const std::string pattern = schema.at("pattern").get<std::string>();
    if (!std::regex_search(value.get<std::string>(), validation.pattern(pattern, path)))
      fail("a string matching " + pattern);
  }
  if (schema.contains("minItems") && value.is_array() &&
      value.size() < schema.at("minItems").get<std::size_t>())
    fail(schema.at("minItems").get<std::size_t>() == 1
             ? std::string("a non-empty array")
             : "an array of at least " + schema.at("minItems").dump() + " items");
  if (schema.contains("uniqueItems") && schema.at("uniqueItems") == true && value.is_array())
    for (std::size_t i = 1; i < value.size(); ++i)
      for (std::size_t k = 0; k < i; ++k)
        if (value.at(i) == value.at(k)) {
          violations.push_back(path + "[" + std::to_string(i) +
                               "]: expected a value not already in " + path + "[" +
                               std::to_string(k) + "], got " + brief(value.at(i)));
          break;
        }
  if (value.is_object()) {
    if (schema.contains("required"))
      for (const Json& key : schema.at("required"))
        if (!value.contains(key.get<std::string>()))
          violations.push_back(childPath(path, key.get<std::string>()) + ": missing (required)");
    const Json* properties = schema.contains("properties") ? &schema.at("properties") : nullptr;
    for (const auto& item : value.items()) {
      const std::string member = childPath(path, item.key());
      if (properties && properties->contains(item.key())) {
        check(validation, properties->at(item.key()), item.value(), member, 0, violations);
      } else if (schema.contains("additionalProperties")) {
        const Json& extra = schema.at("additionalProperties");
        if (extra.is_boolean() && !extra.get<bool>()) {
          std::vector<std::string> names;
          if (properties)
            for (const auto& p : properties->items())
              names.push_back(p.key());
          violations.push_back(member + ": not a known key (known: " + alternatives(names) + ")");
        } else {
          check(validation, extra, item.value(), member, 0, violations);
        }
      }
    }
  }
  if (value.is_array() && schema.contains("items"))
    for (std::size_t i = 0; i < value.size(); ++i)
      check(validation, schema.at("items"), value.at(i), path + "[" + std::to_string(i) + "]", 0,
            violations);
  if (schema.contains("if")) {
    std::vector<std::string> ignored;
    check(validation, schema.at("if"), value, path, chained, ignored);
    const char* branch = ignored.empty() ? "then" : "else";
    if (schema.contains(branch))
      check(validation, schema.at(branch), value, path, chained, violations);
  }
  if (schema.contains("allOf"))
    for (const Json& part : schema.at("allOf"))
      check(validation, part, value, path, chained, violations);
}

}  // namespace

std::vector<std::string> schemaViolations(const Json& schema, const Json& document) {
  std::vector<std::string> violations;
  Validation validation{schema, {}};
  check(validation, schema, document, "", 0, violations);
  return violations;
}

Json projectSchema(const std::string& name) {
  const std::string path = std::string(PBDVAL_SOURCE_DIR) + "/docs/schemas/" + name;
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const Json schema = Json::parse(text.str(), nullptr, false);
  if (!in || schema.is_discarded() || !schema.is_object())
    throw std::runtime_error("cannot read the schema " + path);
  return schema;
}

}  // namespace pbdval
