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

/// The seed's CubicKernel (PositionBasedDynamics/SPHKernels.h) expression for expression, for
/// the seed formulation of a fluid (FluidFormulation::Seed): the same function as
/// CubicSplineKernel inside the support, evaluated with the seed's operations (k = 8/(π h³),
/// l = 48/(π h³), pow(1 − q, 3), ∇q = r / (|r| h)), and, as the seed compiles it
/// (NO_DISTANCE_TEST), without the support test: beyond h, W = 2k (1 − q)³ < 0 and
/// ∇W = −l (1 − q)² ∇q. A neighbour is listed only when closer than h, but the density
/// iterations move it, so the seed evaluates the kernel past its support. ∇W is zero for
/// |r| ≤ 10⁻⁶ (the seed leaves it unset there).
class SeedCubicKernel {
 public:
  SeedCubicKernel() = default;
  explicit SeedCubicKernel(Real supportRadius) : radius_(supportRadius) {
    const Real pi = Real(EIGEN_PI);
    const Real h3 = radius_ * radius_ * radius_;
    k_ = Real(8.0) / (pi * h3);
    l_ = Real(48.0) / (pi * h3);
    valueAtZero_ = value(Vector3::Zero());
  }

  Real value(const Vector3& r) const {
    const Real q = r.norm() / radius_;
    if (q <= Real(0.5)) {
      const Real q2 = q * q;
      const Real q3 = q2 * q;
      return k_ * (Real(6.0) * q3 - Real(6.0) * q2 + Real(1.0));
    }
    return k_ * (Real(2.0) * std::pow(Real(1.0) - q, 3));
  }
  Real valueAtZero() const { return valueAtZero_; }

  Vector3 gradient(const Vector3& r) const {
    const Real distance = r.norm();
    const Real q = distance / radius_;
    if (!(distance > Real(1.0e-6))) return Vector3::Zero();
    const Vector3 gradq = r * (Real(1.0) / (distance * radius_));
    if (q <= Real(0.5)) return l_ * q * (Real(3.0) * q - Real(2.0)) * gradq;
    const Real factor = Real(1.0) - q;
    return l_ * (-factor * factor) * gradq;
  }

 private:
  Real radius_ = 1;
  Real k_ = 0;
  Real l_ = 0;
  Real valueAtZero_ = 0;
};

}  // namespace pbd
