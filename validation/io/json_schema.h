// JSON Schema validation for the documents the runner reads from other programs (an external
// engine's status.json, docs/schemas/): every violation named by its JSON path.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace pbdval {

/// The violations of `document` against `schema`, each "PATH: expected ..., got ..." with PATH
/// as the catalogue errors write it (`effectiveSettings.solver`, `unsupported[0]`; `(document)`
/// for the whole). Empty when it conforms. `schema` is a JSON Schema (draft 2020-12) using only
/// the keywords the project's schemas need: type, const, enum, required, properties,
/// additionalProperties, items, minimum, minLength, minItems, if/then/else, allOf (and the
/// annotations $schema, $id, title, description, $comment, default, examples). Throws
/// std::invalid_argument for any other keyword, so that a schema never checks silently less
/// than it says.
std::vector<std::string> schemaViolations(const nlohmann::json& schema,
                                          const nlohmann::json& document);

}  // namespace pbdval
