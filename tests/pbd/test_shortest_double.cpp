// The shortest round-trip formatter (pbd/src/io/shortest_double.cpp): its text is byte for byte
// std::to_chars(double)'s on every class of finite double, reads back to the same double, and
// its table of 128-bit powers of ten and its fixed-point logarithms are checked against exact
// integer arithmetic done here. No tolerance anywhere: bytes and bits are compared.
#include <gtest/gtest.h>

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "pbd/io/number_text.h"
#include "pbd/io/shortest_double.h"

namespace pbd {
namespace {

namespace detail = shortest_double_detail;

// ---- Exact unsigned integers for the checks (little-endian 32-bit limbs) ----

using BigInteger = std::vector<std::uint32_t>;

void multiplyBy(BigInteger& value, std::uint32_t factor) {
  std::uint64_t carry = 0;
  for (std::uint32_t& limb : value) {
    const std::uint64_t product = std::uint64_t{limb} * factor + carry;
    limb = static_cast<std::uint32_t>(product);
    carry = product >> 32;
  }
  if (carry != 0) value.push_back(static_cast<std::uint32_t>(carry));
}

BigInteger multiplied(const BigInteger& a, const BigInteger& b) {
  BigInteger product(a.size() + b.size(), 0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.size(); ++j) {
      const std::uint64_t sum = std::uint64_t{a[i]} * b[j] + product[i + j] + carry;
      product[i + j] = static_cast<std::uint32_t>(sum);
      carry = sum >> 32;
    }
    product[i + b.size()] = static_cast<std::uint32_t>(carry);
  }
  return product;
}

/// factor 2^twos 10^tens, twos and tens >= 0.
BigInteger power(std::uint32_t factor, int twos, int tens) {
  BigInteger value{factor};
  for (int i = 0; i < tens; ++i)
    multiplyBy(value, 10);
  for (int i = 0; i < twos; ++i)
    multiplyBy(value, 2);
  return value;
}

BigInteger fromHalves(std::uint64_t high, std::uint64_t low) {
  return {static_cast<std::uint32_t>(low), static_cast<std::uint32_t>(low >> 32),
          static_cast<std::uint32_t>(high), static_cast<std::uint32_t>(high >> 32)};
}

/// -1, 0, 1 as a < b, a = b, a > b.
int compare(BigInteger a, BigInteger b) {
  while (!a.empty() && a.back() == 0)
    a.pop_back();
  while (!b.empty() && b.back() == 0)
    b.pop_back();
  if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
  for (std::size_t i = a.size(); i-- > 0;)
    if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
  return 0;
}

/// The sign of factor 2^twos 10^tens - 1 (any signs of twos and tens), exactly.
int compareWithOne(std::uint32_t factor, int twos, int tens) {
  const BigInteger left = power(factor, std::max(twos, 0), std::max(tens, 0));
  const BigInteger right = power(1, std::max(-twos, 0), std::max(-tens, 0));
  return compare(left, right);
}

// ---- Comparison with std::to_chars ----

/// The first difference from std::to_chars (or from the value, read back), as a message.
std::optional<std::string> differenceFromToChars(double value) {
  char mine[kShortestDoubleCapacity];
  char* const mineEnd = writeShortestDouble(mine, value);
  char expected[64];
  char* const expectedEnd = std::to_chars(expected, expected + sizeof(expected), value).ptr;
  const std::string mineText(mine, mineEnd);
  const std::string expectedText(expected, expectedEnd);
  char hex[64];
  std::snprintf(hex, sizeof(hex), "%a", value);
  if (mineText != expectedText)
    return std::string(hex) + ": writes \"" + mineText + "\", std::to_chars \"" + expectedText +
           "\"";
  double readBack = 0;
  const auto [end, error] = std::from_chars(mine, mineEnd, readBack);
  if (error != std::errc() || end != mineEnd || std::memcmp(&readBack, &value, sizeof(double)) != 0)
    return std::string(hex) + ": \"" + mineText + "\" does not read back to the same double";
  return std::nullopt;
}

/// Checks every value, reports the first few differences and how many there were.
class DifferenceCount {
 public:
  void check(double value) {
    ++checked_;
    if (const std::optional<std::string> difference = differenceFromToChars(value)) {
      if (differences_ < 10) ADD_FAILURE() << *difference;
      ++differences_;
    }
  }
  /// value, its two neighbours (the finite ones: the formatter's domain) and -value.
  void checkWithNeighbours(double value) {
    check(value);
    check(std::nextafter(value, 0.0));
    const double above = std::nextafter(value, std::numeric_limits<double>::infinity());
    if (std::isfinite(above)) check(above);
    check(-value);
  }
  long differences() const { return differences_; }
  long checked() const { return checked_; }

 private:
  long differences_ = 0;
  long checked_ = 0;
};

double fromBits(std::uint64_t bits) {
  double value = 0;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

double parsed(const std::string& text) {
  double value = 0;
  std::from_chars(text.data(), text.data() + text.size(), value);
  return value;
}

// ---- The method's parts, against exact arithmetic ----

TEST(ShortestDouble, TheTableHoldsEachPowerOfTenTo128BitsRoundedUp) {
  for (int e = detail::kMinPowerOfTen; e <= detail::kMaxPowerOfTen; ++e) {
    SCOPED_TRACE("10^" + std::to_string(e));
    const detail::Power128 g = detail::powerOfTen(e);
    ASSERT_GE(g.high, std::uint64_t{1} << 63);  // g >= 2^127
    // g - 1 = floor(10^e 2^s), s = 127 - floor(log2 10^e): with 10^e 2^s = numerator /
    // denominator, (g - 1) denominator <= numerator < g denominator.
    const int s = 127 - detail::floorLog2Pow10(e);
    const BigInteger numerator = power(1, std::max(s, 0), std::max(e, 0));
    const BigInteger denominator = power(1, std::max(-s, 0), std::max(-e, 0));
    const std::uint64_t lowMinusOne = g.low - 1;
    const std::uint64_t highMinusOne = g.low == 0 ? g.high - 1 : g.high;
    EXPECT_LE(compare(multiplied(fromHalves(highMinusOne, lowMinusOne), denominator), numerator),
              0);
    EXPECT_GT(compare(multiplied(fromHalves(g.high, g.low), denominator), numerator), 0);
  }
}

TEST(ShortestDouble, TheFixedPointLogarithmsAreTheFloorsOfTheExactOnes) {
  for (int q = -1200; q <= 1200; ++q) {
    SCOPED_TRACE("q = " + std::to_string(q));
    // k = floor(log10 2^q): 10^k <= 2^q < 10^(k+1).
    const int k = detail::floorLog10Pow2(q);
    EXPECT_GE(compareWithOne(1, q, -k), 0);
    EXPECT_LT(compareWithOne(1, q, -k - 1), 0);
    // floor(log10 (3/4) 2^q): 10^k <= 3 2^(q-2) < 10^(k+1).
    const int k34 = detail::floorLog10ThreeQuartersPow2(q);
    EXPECT_GE(compareWithOne(3, q - 2, -k34), 0);
    EXPECT_LT(compareWithOne(3, q - 2, -k34 - 1), 0);
  }
  for (int e = -400; e <= 400; ++e) {
    SCOPED_TRACE("e = " + std::to_string(e));
    // f = floor(log2 10^e): 2^f <= 10^e < 2^(f+1).
    const int f = detail::floorLog2Pow10(e);
    EXPECT_GE(compareWithOne(1, -f, e), 0);
    EXPECT_LT(compareWithOne(1, -f - 1, e), 0);
  }
}

TEST(ShortestDouble, EveryEightDigitNumberIsWrittenWithItsDigits) {
  long differences = 0;
  char digits[8];
  for (std::uint32_t value = 0; value < 100000000; ++value) {
    detail::writeEightDigits(digits, value);
    std::uint32_t rest = value;
    bool same = true;
    for (int i = 7; i >= 0; --i, rest /= 10)
      same = same && digits[i] == static_cast<char>('0' + rest % 10);
    if (!same && differences++ < 10) ADD_FAILURE() << value << ": " << std::string(digits, 8);
  }
  EXPECT_EQ(differences, 0);
}

// ---- The text, against std::to_chars, class by class ----

TEST(ShortestDouble, SignedZerosAreWrittenAsToCharsWritesThem) {
  EXPECT_EQ(differenceFromToChars(0.0), std::nullopt);
  EXPECT_EQ(differenceFromToChars(-0.0), std::nullopt);
  char text[kShortestDoubleCapacity];
  EXPECT_EQ(std::string(text, writeShortestDouble(text, -0.0)), "-0");
}

TEST(ShortestDouble, SubnormalsAndTheEndsOfTheNormalRangeAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  count.checkWithNeighbours(std::numeric_limits<double>::denorm_min());
  count.checkWithNeighbours(fromBits((std::uint64_t{1} << 52) - 1));  // largest subnormal
  count.checkWithNeighbours(DBL_MIN);
  count.checkWithNeighbours(DBL_MAX);
  count.check(fromBits(2));
  count.check(fromBits(3));
  std::mt19937_64 random(20261129);
  for (int i = 0; i < 100000; ++i)
    count.check(fromBits(random() & ((std::uint64_t{1} << 52) - 1)));
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble,
     PowersOfTwoAndTenAcrossTheRangeAndTheirNeighboursAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  for (int e = -1074; e <= 1023; ++e)
    count.checkWithNeighbours(std::ldexp(1.0, e));
  for (int e = -323; e <= 308; ++e)
    count.checkWithNeighbours(parsed("1e" + std::to_string(e)));
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble, IntegersUpToTwoToTheFiftyThreeAndBeyondAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  for (int i = 0; i <= 100000; ++i)
    count.check(static_cast<double>(i));
  for (std::int64_t i = -1000; i <= 1000; ++i) {
    count.check(static_cast<double>((std::int64_t{1} << 53) + i));
    count.check(static_cast<double>((std::int64_t{1} << 62) + i * 1024));
  }
  std::mt19937_64 random(53);
  for (int i = 0; i < 200000; ++i) {
    count.check(static_cast<double>(random() >> 11));                  // below 2^53
    count.check(static_cast<double>(random()));                        // up to 2^64
    count.check(std::ldexp(static_cast<double>(random() >> 11), 30));  // integers to 2^83
  }
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble, NumbersAtTheFixedScientificSwitchAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  for (const char* text :
       {"1e-5", "1e-4", "1.5e-5", "0.000123", "0.0001234", "1e15", "1e16", "1e21", "1e22", "1e23",
        "123456789012345680000", "1.2345678901234567e21", "1.23e22", "12345678901234567e5"})
    count.checkWithNeighbours(parsed(text));
  // Every digit count at every decimal exponent around both switches (fixed and scientific
  // of the same length meet there), random digits.
  std::mt19937_64 random(22);
  for (int digits = 1; digits <= 17; ++digits) {
    for (int exponent = -12; exponent <= 26; ++exponent) {
      for (int i = 0; i < 200; ++i) {
        std::string text = std::to_string(1 + random() % 9) + ".";
        for (int d = 1; d < digits; ++d)
          text += static_cast<char>('0' + random() % 10);
        count.checkWithNeighbours(parsed(text + "e" + std::to_string(exponent)));
      }
    }
  }
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble, ValuesOfOneToSeventeenSignificantDigitsAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  std::mt19937_64 random(17);
  for (int digits = 1; digits <= 17; ++digits) {
    for (int i = 0; i < 20000; ++i) {
      std::string text;
      for (int d = 0; d < digits; ++d)
        text += static_cast<char>('0' + random() % 10);
      const int exponent = static_cast<int>(random() % 640) - 330;
      count.check(parsed(text + "e" + std::to_string(exponent)));
    }
  }
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble, TenMillionRandomBitPatternsAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  std::mt19937_64 random(1729);
  while (count.checked() < 10000000) {
    const double value = fromBits(random());
    if (std::isfinite(value)) count.check(value);
  }
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble, OneMillionRandomDoublesInATrajectorysRangeAreWrittenAsToCharsWritesThem) {
  DifferenceCount count;
  std::mt19937_64 random(10);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0);
  for (int i = 0; i < 1000000; ++i)
    count.check(uniform(random));
  EXPECT_EQ(count.differences(), 0);
}

TEST(ShortestDouble, WriteRealWritesItAndNamesTheValuesThatAreNotFinite) {
  char text[kRealTextCapacity];
  EXPECT_EQ(std::string(text, writeReal(text, 0.1)), "0.1");
  EXPECT_EQ(std::string(text, writeReal(text, -2.5e-7)), "-2.5e-07");
  EXPECT_EQ(std::string(text, writeReal(text, 1e22)), "1e+22");
  EXPECT_EQ(formatReal(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(formatReal(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(formatReal(std::numeric_limits<double>::quiet_NaN()), "nan");
}

}  // namespace
}  // namespace pbd
