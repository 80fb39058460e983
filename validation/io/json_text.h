// JSON documents as text, for every file pbdval writes. Text that is not valid UTF-8 (an error
// message quoting a file's raw bytes) is written with U+FFFD in place of the bad bytes instead
// of aborting the whole write: one unreadable input must not cost a run its results.json.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace pbdval {

/// `document` as text, indented by `indent` spaces (-1: one line).
inline std::string jsonText(const nlohmann::json& document, int indent = 2) {
  return document.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace pbdval
