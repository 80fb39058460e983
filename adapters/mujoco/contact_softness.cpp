#include "adapters/mujoco/contact_softness.h"

#include <algorithm>
#include <cmath>

namespace pbdval::mujoco {

double restitutionOfDampingRatio(double zeta) {
  if (zeta <= 0) return 1;
  if (zeta < 1) {
    const double root = std::sqrt(1 - zeta * zeta);
    const double phase = std::atan2(2 * zeta * root, 2 * zeta * zeta - 1);
    return std::exp(-zeta * phase / root);
  }
  if (zeta == 1) return std::exp(-2.0);
  const double root = std::sqrt(zeta * zeta - 1);
  return std::exp(-zeta * std::log((zeta + root) / (zeta - root)) / root);
}

double dampingRatioForRestitution(double restitution, double maxDampingRatio) {
  if (restitution >= 1) return 0;
  if (restitution <= restitutionOfDampingRatio(maxDampingRatio)) return maxDampingRatio;
  double low = 0, high = maxDampingRatio;  // e(low) > restitution ≥ e(high)
  for (int i = 0; i < 200 && high - low > 1e-15 * maxDampingRatio; ++i) {
    const double middle = (low + high) / 2;
    (restitutionOfDampingRatio(middle) > restitution ? low : high) = middle;
  }
  return (low + high) / 2;
}

DirectSolref contactSolref(double timeConstant, double stepSize, double restitution) {
  DirectSolref s;
  const double maxDampingRatio = timeConstant / (2 * stepSize);
  s.dampingRatio = dampingRatioForRestitution(restitution, maxDampingRatio);
  s.stiffness = 1 / (timeConstant * timeConstant);
  s.damping = 2 * s.dampingRatio / timeConstant;
  return s;
}

}  // namespace pbdval::mujoco
