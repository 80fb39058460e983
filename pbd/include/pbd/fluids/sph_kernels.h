// The cubic spline SPH kernel (Monaghan 1992) in the normalisation of Koschier et al. 2019 and
// SPlisHSPlasH, with support radius h (the kernel is zero for |r| ≥ h):
//
//   q = |r| / h,  k = 8 / (π h³)
//   W(r) = k (6q³ − 6q² + 1)   for 0 ≤ q ≤ ½
//        = 2k (1 − q)³        for ½ < q ≤ 1
//        = 0                  for q > 1
//   ∇W(r) = W'(q) / h · r/|r|,  W'(q) = k (18q² − 12q) (q ≤ ½), −6k (1 − q)² (½ < q ≤ 1); ∇W(0) = 0
//
// ∫ W dV = 1 over the ball of radius h. The seed (SPHKernels.h, CubicKernel) keeps the radius
// and the constants in static members, so one process can use one radius only; here the kernel
// is a value holding its radius, and every fluid has its own.
#pragma once

#include <cmath>

#include "pbd/math/types.h"

namespace pbd {

class CubicSplineKernel {
 public:
  CubicSplineKernel() = default;
  /// `supportRadius` h > 0: W vanishes at distances ≥ h.
  explicit CubicSplineKernel(Real supportRadius)
      : radius_(supportRadius), scale_(Real(8) / (Real(EIGEN_PI) * cube(supportRadius))) {}

  Real supportRadius() const { return radius_; }

  /// W as a function of the distance |r| ≥ 0.
  Real valueAt(Real distance) const {
    const Real q = distance / radius_;
    if (q <= Real(0.5)) return scale_ * (Real(6) * q * q * (q - 1) + 1);
    if (q <= 1) return 2 * scale_ * cube(1 - q);
    return 0;
  }
  Real value(const Vector3& r) const { return valueAt(r.norm()); }
  /// W(0), a particle's own contribution to its density.
  Real valueAtZero() const { return scale_; }

  /// ∇W(r) (with respect to r); zero at r = 0 and for |r| ≥ h.
  Vector3 gradient(const Vector3& r) const {
    const Real distance = r.norm();
    const Real q = distance / radius_;
    if (!(distance > 0) || q >= 1) return Vector3::Zero();
    const Real slope = q <= Real(0.5) ? scale_ * q * (Real(18) * q - Real(12))
                                      : Real(-6) * scale_ * (1 - q) * (1 - q);
    return (slope / (radius_ * distance)) * r;
  }

 private:
  static Real cube(Real x) { return x * x * x; }

  Real radius_ = 1;
  Real scale_ = Real(8) / Real(EIGEN_PI);
};

}  // namespace pbd
