// Numbers as text, read and written in one place for the whole project: scene and mesh
// readers, method parameters, `--set`, command-line options and every file pbdval writes.
//
// Reading is strict: the whole text must be one number in C locale form ("0.25", "-1e-3"),
// finite and representable; no leading '+', no spaces, no "inf" or "nan". Writing gives the
// shortest text that reads back to the same double ("0.1", not "0.10000000000000001"), byte for
// byte what std::to_chars(double) writes (pbd/io/shortest_double.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace pbd {

/// A finite double, or nullopt when `text` is not exactly one.
std::optional<double> parseReal(std::string_view text);

/// An integer written without fraction or exponent ("12", "-3"), or nullopt when `text` is not
/// exactly one or does not fit in 64 bits.
std::optional<std::int64_t> parseInteger(std::string_view text);

/// The shortest decimal text that reads back to `value` ("nan", "inf", "-inf" for non-finite).
std::string formatReal(double value);

/// Room `writeReal` needs at its destination.
inline constexpr std::size_t kRealTextCapacity = 32;
/// Writes formatReal's text at `destination` (kRealTextCapacity characters of room, no
/// terminator; the rest of that room may be written too) and returns the end of the text: for
/// writers that format many numbers into one buffer.
char* writeReal(char* destination, double value);

}  // namespace pbd
