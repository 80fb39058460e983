#include "validation/io/json_schema.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace pbdval {
namespace {

using Json = nlohmann::json;

constexpr std::array<const char*, 7> kAnnotations = {
    "$schema", "$id", "title", "description", "$comment", "default", "examples"};
constexpr std::array<const char*, 13> kKeywords = {
    "type",  "const",   "enum",      "required", "properties", "additionalProperties",
    "items", "minimum", "minLength", "minItems", "if",         "then",
    "else"};

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
  if (type == "integer")
    return value.is_number_integer() ||
           (value.is_number_float() &&
            value.get<double>() ==
                static_cast<double>(static_cast<long long>(value.get<double>())));
  throw std::invalid_argument("schema: unknown type \"" + type + "\"");
}

/// A list of names as a sentence: "a", "a or b", "a, b or c".
std::string alternatives(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

void check(const Json& schema, const Json& value, const std::string& path,
           std::vector<std::string>& violations) {
  if (schema.is_boolean()) {
    if (!schema.get<bool>()) violations.push_back(shown(path) + ": not allowed here");
    return;
  }
  if (!schema.is_object())
    throw std::invalid_argument("schema at " + shown(path) + ": not an object");
  for (const auto& item : schema.items()) {
    const std::string& key = item.key();
    const bool known =
        std::find(kKeywords.begin(), kKeywords.end(), key) != kKeywords.end() || key == "allOf" ||
        std::find(kAnnotations.begin(), kAnnotations.end(), key) != kAnnotations.end();
    if (!known) throw std::invalid_argument("schema keyword \"" + key + "\" is not supported");
  }
  const auto fail = [&](const std::string& expected) {
    violations.push_back(shown(path) + ": expected " + expected + ", got " + brief(value));
  };
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
  if (schema.contains("minItems") && value.is_array() &&
      value.size() < schema.at("minItems").get<std::size_t>())
    fail("an array of at least " + schema.at("minItems").dump() + " items");
  if (value.is_object()) {
    if (schema.contains("required"))
      for (const Json& key : schema.at("required"))
        if (!value.contains(key.get<std::string>()))
          violations.push_back(childPath(path, key.get<std::string>()) + ": missing (required)");
    const Json properties = schema.value("properties", Json::object());
    for (const auto& item : value.items()) {
      const std::string member = childPath(path, item.key());
      if (properties.contains(item.key())) {
        check(properties.at(item.key()), item.value(), member, violations);
      } else if (schema.contains("additionalProperties")) {
        const Json& extra = schema.at("additionalProperties");
        if (extra.is_boolean() && !extra.get<bool>()) {
          std::vector<std::string> names;
          for (const auto& p : properties.items())
            names.push_back(p.key());
          violations.push_back(member + ": not a known key (known: " + alternatives(names) + ")");
        } else {
          check(extra, item.value(), member, violations);
        }
      }
    }
  }
  if (value.is_array() && schema.contains("items"))
    for (std::size_t i = 0; i < value.size(); ++i)
      check(schema.at("items"), value.at(i), path + "[" + std::to_string(i) + "]", violations);
  if (schema.contains("if")) {
    std::vector<std::string> ignored;
    check(schema.at("if"), value, path, ignored);
    const char* branch = ignored.empty() ? "then" : "else";
    if (schema.contains(branch)) check(schema.at(branch), value, path, violations);
  }
  if (schema.contains("allOf"))
    for (const Json& part : schema.at("allOf"))
      check(part, value, path, violations);
}

}  // namespace

std::vector<std::string> schemaViolations(const Json& schema, const Json& document) {
  std::vector<std::string> violations;
  check(schema, document, "", violations);
  return violations;
}

}  // namespace pbdval
