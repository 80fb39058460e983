#include "pbd/io/number_text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

#include "pbd/io/shortest_double.h"

namespace pbd {

std::optional<double> parseReal(std::string_view text) {
  if (text.empty() || text.front() == '+') return std::nullopt;
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parseInteger(std::string_view text) {
  if (text.empty() || text.front() == '+') return std::nullopt;
  std::int64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc() || ptr != end) return std::nullopt;
  return value;
}

char* writeReal(char* destination, double value) {
  if (!std::isfinite(value)) {
    const std::string_view text = std::isnan(value) ? "nan" : value > 0 ? "inf" : "-inf";
    return std::copy(text.begin(), text.end(), destination);
  }
  static_assert(kShortestDoubleCapacity <= kRealTextCapacity);
  return writeShortestDouble(destination, value);
}

std::string formatReal(double value) {
  char buffer[kRealTextCapacity];
  return std::string(buffer, writeReal(buffer, value));
}

}  // namespace pbd
