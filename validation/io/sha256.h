// SHA-256 (FIPS 180-4) of a byte string, as lowercase hex: the fingerprint a baseline pins each
// case file with (docs/gate.md), so that the gate can tell the case a result was run from, and
// refuse checks or tolerances that did not come from it.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace pbdval {

/// The 64 hex digits of SHA-256(bytes).
std::string sha256Hex(std::string_view bytes);

/// SHA-256 of a file's bytes; nullopt when it cannot be read (missing, a folder, no access).
std::optional<std::string> fileSha256(const std::string& path);

}  // namespace pbdval
