// The shortest decimal text that reads back to a double, written exactly as
// std::to_chars(first, last, double) writes it (libstdc++'s form: fixed or scientific,
// whichever is shorter, a tie to fixed; the exponent signed and of at least two digits, "1e-05",
// "1.5e+20"; a fixed number with no fraction written as the double's exact integer value,
// "123456789012345683968"). The digits come from Schubfach (R. Giulietti, "The Schubfach way
// to render doubles", 2020); pbd/src/io/shortest_double.cpp has the method.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pbd {

/// Room writeShortestDouble needs at its destination ("-1.2345678901234567e-308").
inline constexpr std::size_t kShortestDoubleCapacity = 24;

/// Writes the shortest round-trip text of a finite `value` at `destination`
/// (kShortestDoubleCapacity characters of room, no terminator) and returns the end of what it
/// wrote; it may write anything in the rest of that room. No allocation, no state.
char* writeShortestDouble(char* destination, double value);

/// The parts of the method a test checks by exact integer arithmetic.
namespace shortest_double_detail {

/// g(e) = floor(10^e * 2^(127 - floor(log2 10^e))) + 1, in [2^127, 2^128): 10^e to 128 bits,
/// rounded up.
struct Power128 {
  std::uint64_t high;
  std::uint64_t low;
};
inline constexpr int kMinPowerOfTen = -292;
inline constexpr int kMaxPowerOfTen = 324;
/// g(e) for kMinPowerOfTen <= e <= kMaxPowerOfTen.
Power128 powerOfTen(int e);

/// floor(log10 2^q), floor(log10 (3/4 2^q)) for |q| <= 1200; floor(log2 10^e) for |e| <= 400.
int floorLog10Pow2(int q);
int floorLog10ThreeQuartersPow2(int q);
int floorLog2Pow10(int e);

/// Writes the 8 decimal digits of value < 10^8, leading zeros included.
void writeEightDigits(char* destination, std::uint32_t value);

}  // namespace shortest_double_detail
}  // namespace pbd
