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
/// The keywords by their place in kKeywords.
enum Keyword {
  kType,
  kConst,
  kEnum,
  kRequired,
  kProperties,
  kAdditionalProperties,
  kItems,
  kMinimum,
  kMinLength,
  kMinItems,
  kUniqueItems,
  kPattern,
  kIf,
  kThen,
  kElse,
  kAllOf,
  kRef
};

// How many `$ref`s may follow one another without the document moving to a child value: more
// is a loop in the schema ({"$ref": "#"}), refused instead of recursing without end. The
// project's schemas chain at most one.
constexpr int kMaxChainedReferences = 16;

std::string childPath(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

/// Where a value stands in the document, as a chain of its parents: its text
/// (`methods[0].name`) is built only for a message, not for every value checked (17,000 paths
/// of the catalogue's values, 8 M instructions per command).
struct JsonPath {
  const JsonPath* parent = nullptr;  ///< null: the document itself
  const std::string* key = nullptr;  ///< a member of the parent's object, else item `index`
  std::size_t index = 0;

  std::string text() const {
    if (!parent) return {};
    const std::string above = parent->text();
    return key ? childPath(above, *key) : above + "[" + std::to_string(index) + "]";
  }
};

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

}  // namespace

/// What one schema's checks keep between documents: the root schema, each `pattern` compiled
/// once (compiling an ECMAScript expression is costly: compiled for every string it checks, the
/// engine catalogue's patterns took 200 M instructions of every command's start,
/// docs/benchmarks.md), and each subschema's keywords, checked and looked up once, not at every
/// value it applies to (that was 30 M instructions of string comparisons per command).
struct SchemaChecker::Validation {
  const Json& root;
  /// A `pattern`, compiled, and whether each string checked so far matches it (feature and
  /// method names recur across the catalogue's files; std::regex_search costs thousands of
  /// instructions a string).
  struct Pattern {
    std::regex regex;
    std::map<std::string, bool> matches;
  };
  std::map<std::string, Pattern> patterns;
  /// A subschema's keywords, looked up once: where each stands in it (null when absent), and
  /// the subschema its `$ref` names once followed.
  struct Keywords {
    std::array<const Json*, kKeywords.size()> at{};
    const Json* referenced = nullptr;
  };
  std::map<const Json*, Keywords> subschemas;  ///< by address in `root`, which outlives them

  /// Whether `text` matches `pattern` (at `path` in the schema's use, for the message when it
  /// is not a regular expression).
  bool matches(const std::string& pattern, const std::string& text, const JsonPath& path) {
    auto found = patterns.find(pattern);
    if (found == patterns.end()) {
      try {
        found = patterns.emplace(pattern, Pattern{std::regex(pattern, std::regex::ECMAScript), {}})
                    .first;
      } catch (const std::regex_error&) {
        throw std::invalid_argument("schema: pattern \"" + pattern + "\" at " + shown(path.text()) +
                                    " is not a regular expression");
      }
    }
    Pattern& compiled = found->second;
    const auto known = compiled.matches.find(text);
    if (known != compiled.matches.end()) return known->second;
    return compiled.matches.emplace(text, std::regex_search(text, compiled.regex)).first->second;
  }
};

namespace {

using Validation = SchemaChecker::Validation;

/// Checks `value` (at `path`) against `schema`, a part of the validation's root; `chained`
/// counts the `$ref`s followed since the document last moved to a child value.
void check(Validation& validation, const Json& schema, const Json& value, const JsonPath& path,
           int chained, std::vector<std::string>& violations) {
  if (schema.is_boolean()) {
    if (!schema.get<bool>()) violations.push_back(shown(path.text()) + ": not allowed here");
    return;
  }
  if (!schema.is_object())
    throw std::invalid_argument("schema at " + shown(path.text()) + ": not an object");
  auto known = validation.subschemas.find(&schema);
  if (known == validation.subschemas.end()) {
    Validation::Keywords keywords;
    for (const auto& item : schema.items()) {
      const std::string& key = item.key();
      const auto keyword = std::find(kKeywords.begin(), kKeywords.end(), key);
      if (keyword != kKeywords.end())
        keywords.at[std::size_t(keyword - kKeywords.begin())] = &item.value();
      else if (std::find(kAnnotations.begin(), kAnnotations.end(), key) == kAnnotations.end())
        throw std::invalid_argument("schema keyword \"" + key + "\" is not supported");
    }
    known = validation.subschemas.emplace(&schema, keywords).first;
  }
  Validation::Keywords& keywords = known->second;
  const auto fail = [&](const std::string& expected) {
    violations.push_back(shown(path.text()) + ": expected " + expected + ", got " + brief(value));
  };
  if (keywords.at[kRef]) {
    if (chained >= kMaxChainedReferences)
      throw std::invalid_argument("schema: $ref " + keywords.at[kRef]->dump() + " at " +
                                  shown(path.text()) + " loops without reaching a value");
    if (!keywords.referenced)
      keywords.referenced = &referenced(validation.root, *keywords.at[kRef]);
    check(validation, *keywords.referenced, value, path, chained + 1, violations);
  }
  if (keywords.at[kType]) {
    const Json& type = *keywords.at[kType];
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
  if (keywords.at[kConst] && value != *keywords.at[kConst]) fail(keywords.at[kConst]->dump());
  if (keywords.at[kEnum]) {
    const Json& options = *keywords.at[kEnum];
    if (std::find(options.begin(), options.end(), value) == options.end()) {
      std::vector<std::string> named;
      for (const Json& o : options)
        named.push_back(o.dump());
      fail("one of " + alternatives(named));
    }
  }
  if (keywords.at[kMinimum] && value.is_number() &&
      value.get<double>() < keywords.at[kMinimum]->get<double>())
    fail("a number >= " + keywords.at[kMinimum]->dump());
  if (keywords.at[kMinLength] && value.is_string() &&
      value.get<std::string>().size() < keywords.at[kMinLength]->get<std::size_t>())
    fail(keywords.at[kMinLength]->get<std::size_t>() == 1
             ? std::string("a non-empty string")
             : "a string of at least " + keywords.at[kMinLength]->dump() + " characters");
  if (keywords.at[kPattern] && value.is_string()) {
    // ECMA-262 regular expressions, as JSON Schema specifies; matched anywhere unless anchored.
    const std::string& pattern = keywords.at[kPattern]->get_ref<const std::string&>();
    if (!validation.matches(pattern, value.get_ref<const std::string&>(), path))
      fail("a string matching " + pattern);
  }
  if (keywords.at[kMinItems] && value.is_array() &&
      value.size() < keywords.at[kMinItems]->get<std::size_t>())
    fail(keywords.at[kMinItems]->get<std::size_t>() == 1
             ? std::string("a non-empty array")
             : "an array of at least " + keywords.at[kMinItems]->dump() + " items");
  if (keywords.at[kUniqueItems] && *keywords.at[kUniqueItems] == true && value.is_array())
    for (std::size_t i = 1; i < value.size(); ++i)
      for (std::size_t k = 0; k < i; ++k)
        if (value.at(i) == value.at(k)) {
          violations.push_back(path.text() + "[" + std::to_string(i) +
                               "]: expected a value not already in " + path.text() + "[" +
                               std::to_string(k) + "], got " + brief(value.at(i)));
          break;
        }
  if (value.is_object()) {
    if (keywords.at[kRequired])
      for (const Json& key : *keywords.at[kRequired])
        if (!value.contains(key.get<std::string>()))
          violations.push_back(childPath(path.text(), key.get<std::string>()) +
                               ": missing (required)");
    const Json* properties = keywords.at[kProperties];
    for (const auto& item : value.items()) {
      const JsonPath member{&path, &item.key(), 0};
      if (properties && properties->contains(item.key())) {
        check(validation, properties->at(item.key()), item.value(), member, 0, violations);
      } else if (keywords.at[kAdditionalProperties]) {
        const Json& extra = *keywords.at[kAdditionalProperties];
        if (extra.is_boolean() && !extra.get<bool>()) {
          std::vector<std::string> names;
          if (properties)
            for (const auto& p : properties->items())
              names.push_back(p.key());
          violations.push_back(member.text() + ": not a known key (known: " + alternatives(names) +
                               ")");
        } else {
          check(validation, extra, item.value(), member, 0, violations);
        }
      }
    }
  }
  if (value.is_array() && keywords.at[kItems])
    for (std::size_t i = 0; i < value.size(); ++i)
      check(validation, *keywords.at[kItems], value.at(i), JsonPath{&path, nullptr, i}, 0,
            violations);
  if (keywords.at[kIf]) {
    std::vector<std::string> ignored;
    check(validation, *keywords.at[kIf], value, path, chained, ignored);
    const Json* branch = ignored.empty() ? keywords.at[kThen] : keywords.at[kElse];
    if (branch) check(validation, *branch, value, path, chained, violations);
  }
  if (keywords.at[kAllOf])
    for (const Json& part : *keywords.at[kAllOf])
      check(validation, part, value, path, chained, violations);
}

}  // namespace

SchemaChecker::SchemaChecker(const Json& schema) : validation_(new Validation{schema, {}, {}}) {}

SchemaChecker::~SchemaChecker() = default;

std::vector<std::string> SchemaChecker::violations(const Json& document) {
  std::vector<std::string> violations;
  check(*validation_, validation_->root, document, JsonPath{}, 0, violations);
  return violations;
}

std::vector<std::string> schemaViolations(const Json& schema, const Json& document) {
  return SchemaChecker(schema).violations(document);
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
