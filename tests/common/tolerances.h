// Precision-aware tolerances for tests that run in both the double and the float build.
#pragma once

#include <cmath>
#include <limits>

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

/// ε of `Real` over ε of double: exactly 1 in the double build, 2²⁹ in the float build (both
/// powers of two, so scaling by it is exact).
inline constexpr Real kEpsilonRatio = Real(kEpsilon / std::numeric_limits<double>::epsilon());

/// A round-off bound written for the double build (say 1e-13 = 450 ε_double on O(1) values),
/// kept as the same multiple of ε of `Real`: the identical number in the double build, 2²⁹ times
/// larger in the float build. Use it only where the bound is round-off, i.e. a count of
/// operations × ε × magnitude; physics or truncation errors do not scale with ε.
inline constexpr Real roundOffBound(double boundInDouble) {
  return Real(boundInDouble) * kEpsilonRatio;
}

}  // namespace pbd::test
