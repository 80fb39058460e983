// Assertions on error and warning texts.
#pragma once

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace pbd::test {

/// Success when `text` contains every one of `parts`; the failure names the first missing one.
inline ::testing::AssertionResult containsAll(const std::string& text,
                                              std::initializer_list<std::string> parts) {
  for (const auto& part : parts) {
    if (text.find(part) == std::string::npos) {
      return ::testing::AssertionFailure() << "'" << part << "' not in: " << text;
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace pbd::test
