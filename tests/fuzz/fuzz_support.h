// What the fuzz targets share (fuzz_targets_pbd.cpp, fuzz_targets.cpp).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pbdval::fuzz {

// Relative mesh paths in a fuzzed scene resolve here: a folder that does not exist, so that
// the fuzzer cannot reach the corpus or the project's files by a short relative path.
inline constexpr const char* kSceneName = "/nonexistent-pbdval-fuzz/scene.json";

std::string text(const std::uint8_t* data, std::size_t size);

/// Messages are printed and stored in results.json: they must be valid UTF-8. nlohmann's
/// strict dump() is the check (it throws type_error 316 on a bad byte); aborts so that
/// libFuzzer records the input.
void expectPrintable(const char* message);

}  // namespace pbdval::fuzz
