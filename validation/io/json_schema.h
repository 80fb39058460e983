// JSON Schema validation for the documents the runner reads from other programs (an external
// engine's status.json, the engine catalogue; docs/schemas/): every violation named by its JSON
// path.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pbdval {

/// The violations of `document` against `schema`, each "PATH: expected ..., got ..." with PATH
/// as the catalogue errors write it (`effectiveSettings.solver`, `unsupported[0]`; `(document)`
/// for the whole). Empty when it conforms. `schema` is a JSON Schema (draft 2020-12) using only
/// the keywords the project's schemas need: type, const, enum, required, properties,
/// additionalProperties, items, minimum, minLength, minItems, uniqueItems, pattern (ECMA-262),
/// if/then/else, allOf, $ref into the same schema ("#/$defs/parameter") with $defs (and the
/// annotations $schema, $id, title, description, $comment, default, examples). Throws
/// std::invalid_argument for any other keyword, a $ref that names nothing or one that loops,
/// so that a schema never checks silently less than it says.
std::vector<std::string> schemaViolations(const nlohmann::json& schema,
                                          const nlohmann::json& document);

/// schemaViolations for many documents against one schema (the engine catalogue's files): what
/// does not depend on the document (the compiled patterns, which subschemas use only supported
/// keywords) is worked out once. `schema` must outlive the checker.
class SchemaChecker {
 public:
  explicit SchemaChecker(const nlohmann::json& schema);
  ~SchemaChecker();
  SchemaChecker(const SchemaChecker&) = delete;
  SchemaChecker& operator=(const SchemaChecker&) = delete;
  /// schemaViolations(schema, document).
  std::vector<std::string> violations(const nlohmann::json& document);

  struct Validation;

 private:
  std::unique_ptr<Validation> validation_;
};

/// The project's schema docs/schemas/`name` ("status.schema.json"), read from the source tree.
/// Throws std::runtime_error naming the path when it cannot be read or is not a JSON object.
nlohmann::json projectSchema(const std::string& name);

}  // namespace pbdval
