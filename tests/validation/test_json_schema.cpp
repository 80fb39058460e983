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
                .find("unsupported: expected an array of at least 1 items"),
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
  const Json schema = Json::parse(R"({"type": "string", "pattern": "^a"})");
  EXPECT_THROW(schemaViolations(schema, Json("b")), std::invalid_argument);
}

}  // namespace
}  // namespace pbdval
