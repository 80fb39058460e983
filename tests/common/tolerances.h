// Precision-aware tolerances for tests that run in both the double and the float build.
#pragma once

#include <cmath>

#include "pbd/math/types.h"

namespace pbd::test {

/// Central-difference step: ε^(1/3) balances truncation O(h²) against cancellation O(ε/h).
inline Real finiteDifferenceStep() {
  return std::cbrt(kEpsilon);
}
/// The resulting accuracy on O(1) derivatives is ~ε^(2/3); allow 100× that.
inline Real finiteDifferenceTolerance() {
  return 100 * std::pow(kEpsilon, Real(2) / 3);
}

}  // namespace pbd::test
