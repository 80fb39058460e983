// The JSON Schema subset the runner validates other programs' documents with
// (validation/io/json_schema.h): each violation named by its JSON path, unknown keywords refused.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "common/text_assertions.h"
#include "pbdval/build_info.h"
#include "validation/io/json_schema.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;
using pbd::test::containsAll;

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines)
    text += line + "\n";
  return text;
}

Json statusSchema() {
  std::ifstream in(std::string(PBDVAL_SOURCE_DIR) + "/docs/schemas/status.schema.json");
  std::stringstream text;
  text << in.rdbuf();
  return Json::parse(text.str());
}

Json validStatus() {
  return Json::parse(R"({"protocol": 1, "status": "ok", "reason": "", "unsupported": [],
    "divergedAt": null, "engineVersion": "e 1", "effectiveSettings": {"iterations": 10},
    "integratorStepsPerSceneStep": 1, "contactMargin": null})");
}

TEST(JsonSchema, AStatusAsTheProtocolDescribesItConforms) {
  EXPECT_TRUE(schemaViolations(statusSchema(), validStatus()).empty())
      << joined(schemaViolations(statusSchema(), validStatus()));
  Json projected = validStatus();
  projected["initialVelocitiesProjected"] = true;
  EXPECT_TRUE(schemaViolations(statusSchema(), projected).empty());
}

TEST(JsonSchema, AStatusOfThreeKeysIsRefusedNamingEveryMissingKey) {
  const Json bare = Json::parse(R"({"protocol": 1, "status": "ok", "reason": ""})");
  const std::vector<std::string> violations = schemaViolations(statusSchema(), bare);
  EXPECT_EQ(violations.size(), 6u) << joined(violations);
  EXPECT_TRUE(containsAll(joined(violations),
                          {"unsupported: missing", "divergedAt: missing", "engineVersion: missing",
                           "effectiveSettings: missing", "integratorStepsPerSceneStep: missing",
                           "contactMargin: missing"}))
      << joined(violations);
}

TEST(JsonSchema, ViolationsInsideArraysAndObjectsNameTheirPath) {
  Json status = validStatus();
  status["status"] = "unsupported";
  status["reason"] = "r";
  status["unsupported"] = Json::parse(R"(["a", 3])");
  status["effectiveSettings"]["solver"] = Json::array({1});
  status["integratorStepsPerSceneStep"] = 0;
  status["extra"] = true;
  const std::string text = joined(schemaViolations(statusSchema(), status));
  EXPECT_TRUE(containsAll(
      text,
      {"unsupported[1]: expected a string, got 3",
       "effectiveSettings.solver: expected a number, a boolean or a string",
       "integratorStepsPerSceneStep: expected a number >= 1, got 0", "extra: not a known key"}))
      << text;
}

TEST(JsonSchema, TheRulesBetweenFieldsHold) {
  Json failed = validStatus();
  failed["status"] = "error";  // a non-ok status needs a reason
  EXPECT_NE(
      joined(schemaViolations(statusSchema(), failed)).find("reason: expected a non-empty string"),
      std::string::npos);
  Json unsupported = validStatus();
  unsupported["status"] = "unsupported";
  unsupported["reason"] = "r";  // but names no feature
  EXPECT_NE(joined(schemaViolations(statusSchema(), unsupported))
                .find("unsupported: expected a non-empty array"),
            std::string::npos);
  Json diverged = validStatus();
  diverged["status"] = "diverged";
  diverged["reason"] = "r";  // with divergedAt null
  EXPECT_NE(
      joined(schemaViolations(statusSchema(), diverged)).find("divergedAt: expected a number"),
      std::string::npos);
  Json okWithReason = validStatus();
  okWithReason["reason"] = "fine";
  EXPECT_NE(joined(schemaViolations(statusSchema(), okWithReason)).find("reason: expected \"\""),
            std::string::npos);
}

TEST(JsonSchema, AKeywordOutsideTheSubsetIsRefusedRatherThanIgnored) {
  const Json schema = Json::parse(R"({"type": "string", "maxLength": 1})");
  EXPECT_THROW(schemaViolations(schema, Json("bc")), std::invalid_argument);
}

TEST(JsonSchema, AReferenceIntoDefsChecksTheValueWhereItStandsAndNamesItsPath) {
  const Json schema = Json::parse(R"({"type": "object", "properties": {
      "parameters": {"type": "array", "items": {"$ref": "#/$defs/parameter"}}},
    "$defs": {"parameter": {"type": "object", "required": ["name"],
                            "properties": {"name": {"type": "string", "minLength": 1}}}}})");
  EXPECT_TRUE(schemaViolations(schema, Json::parse(R"({"parameters": [{"name": "a"}]})")).empty());
  const std::string text = joined(
      schemaViolations(schema, Json::parse(R"({"parameters": [{"name": "a"}, {}, {"name": 2}]})")));
  EXPECT_TRUE(containsAll(text, {"parameters[1].name: missing (required)",
                                 "parameters[2].name: expected a string, got 2"}))
      << text;
  // $defs alone checks nothing: a document unlike the definitions still conforms.
  EXPECT_TRUE(schemaViolations(schema, Json::parse(R"({"other": 1})")).empty());
}

TEST(JsonSchema, AReferenceThatNamesNothingOrLoopsIsRefusedAsASchemaError) {
  EXPECT_THROW(schemaViolations(Json::parse(R"({"$ref": "#/$defs/none"})"), Json(1)),
               std::invalid_argument);
  EXPECT_THROW(schemaViolations(Json::parse(R"({"$ref": "other.json#/x"})"), Json(1)),
               std::invalid_argument);
  EXPECT_THROW(schemaViolations(Json::parse(R"({"$ref": "#"})"), Json(1)), std::invalid_argument);
}

TEST(JsonSchema, APatternIsAnEcmaScriptExpressionSearchedInTheString) {
  const Json anchored = Json::parse(R"({"pattern": "^[a-z][a-z0-9-]*$"})");
  EXPECT_TRUE(schemaViolations(anchored, Json("mujoco-python")).empty());
  const std::vector<std::string> violations = schemaViolations(anchored, Json("My Engine"));
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_EQ(violations[0],
            "(document): expected a string matching ^[a-z][a-z0-9-]*$, got \"My Engine\"");
  // Unanchored, a pattern may match anywhere (JSON Schema); it applies to strings only.
  const Json unanchored = Json::parse(R"({"pattern": "b"})");
  EXPECT_TRUE(schemaViolations(unanchored, Json("abc")).empty());
  EXPECT_TRUE(schemaViolations(unanchored, Json(3)).empty());
  EXPECT_EQ(schemaViolations(unanchored, Json("ac")).size(), 1u);
}

TEST(JsonSchema, OneCheckerOverManyDocumentsReportsWhatAFreshCheckOfEachWould) {
  // SchemaChecker keeps the compiled patterns, the strings they matched and each subschema's
  // keywords between documents: each document's violations must still be exactly those of a
  // check of that document alone, whichever documents came before (the same strings valid in
  // one place and not in another, paths through references and arrays).
  const Json schema = Json::parse(R"({"type": "object", "required": ["name"],
    "properties": {"name": {"type": "string", "pattern": "^[a-z][a-z0-9-]*$"},
                   "methods": {"type": "array", "items": {"$ref": "#/$defs/method"}}},
    "additionalProperties": false,
    "$defs": {"method": {"type": "object", "required": ["name"], "properties": {
      "name": {"type": "string", "pattern": "^[a-z][A-Za-z0-9]*(\\.[a-z][A-Za-z0-9]*)*$"},
      "kind": {"enum": ["a", "b"]}},
      "if": {"properties": {"kind": {"const": "b"}}}, "then": {"required": ["extra"]}}}})");
  const std::vector<Json> documents = {
      Json::parse(R"({"name": "pbd", "methods": [{"name": "pbd.xpbd"}, {"name": "Pbd"}]})"),
      Json::parse(R"({"name": "Pbd", "methods": [{"name": "pbd.xpbd", "kind": "b"}]})"),
      Json::parse(R"({"name": "mujoco-python"})"),
      Json::parse(R"({"name": "pbd", "methods": [{"name": "pbd.xpbd"}, {"name": "pbd"}]})"),
      Json::parse(R"({"methods": [{"kind": "c"}, {"name": "pbd.Xpbd"}], "other": 1})"),
      // A string each pattern has seen, now where the other pattern applies: both wrong.
      Json::parse(R"({"name": "pbd.xpbd", "methods": [{"name": "mujoco-python"}]})"),
      Json::parse(R"({"name": "pbd"})")};
  SchemaChecker checker(schema);
  std::size_t violationsSeen = 0;
  for (const Json& document : documents) {
    const std::vector<std::string> alone = schemaViolations(schema, document);
    EXPECT_EQ(checker.violations(document), alone) << document.dump();
    violationsSeen += alone.size();
  }
  // The documents do break the rules (8 violations by hand): the comparison means something.
  EXPECT_GE(violationsSeen, 8u);
  // An unsupported keyword is refused when a document first reaches it, and every time after.
  const Json partly = Json::parse(R"({"properties": {"deep": {"maxLength": 1}}})");
  SchemaChecker partlyChecker(partly);
  EXPECT_TRUE(partlyChecker.violations(Json::parse(R"({"shallow": 1})")).empty());
  EXPECT_THROW(partlyChecker.violations(Json::parse(R"({"deep": "x"})")), std::invalid_argument);
  EXPECT_THROW(partlyChecker.violations(Json::parse(R"({"deep": "x"})")), std::invalid_argument);
}

TEST(JsonSchema, UniqueItemsNamesEachRepeatAndTheItemItRepeats) {
  const Json schema = Json::parse(R"({"properties": {"m": {"uniqueItems": true}}})");
  EXPECT_TRUE(schemaViolations(schema, Json::parse(R"({"m": ["a", "b", 1, "1"]})")).empty());
  const std::vector<std::string> violations =
      schemaViolations(schema, Json::parse(R"({"m": ["a", "b", "a", {"x": 1}, {"x": 1}]})"));
  EXPECT_EQ(joined(violations),
            "m[2]: expected a value not already in m[0], got \"a\"\n"
            "m[4]: expected a value not already in m[3], got {\"x\":1}\n");
}

TEST(JsonSchema, AnIntegerIsANumberWithoutAFractionalPart) {
  const Json schema = Json::parse(R"({"type": "integer"})");
  EXPECT_TRUE(schemaViolations(schema, Json::parse("10")).empty());
  EXPECT_TRUE(schemaViolations(schema, Json::parse("10.0")).empty());  // JSON Schema: 1.0 is one
  EXPECT_TRUE(schemaViolations(schema, Json::parse("1e20")).empty());  // beyond int64, still whole
  EXPECT_EQ(schemaViolations(schema, Json::parse("1.5")).size(), 1u);
}

}  // namespace
}  // namespace pbdval
