#include "pbd/collision/analytic_shapes.h"

#include <cmath>

namespace pbd::sdf {
namespace {

Real signOf(Real value) {
  return value < 0 ? Real(-1) : Real(1);
}

/// The 2D rounded-box formula shared by the box and the cylinder: φ and ∂φ/∂q for
/// q = p − b (any dimension).
template <int N>
Real boxDistance(const Eigen::Matrix<Real, N, 1>& q, Eigen::Matrix<Real, N, 1>& dPhiDq) {
  const Eigen::Matrix<Real, N, 1> outside = q.cwiseMax(Real(0));
  const Real outsideLength = outside.norm();
  Eigen::Index largest = 0;
  for (Eigen::Index k = 1; k < N; ++k)
    if (q(k) > q(largest)) largest = k;
  if (outsideLength > 0) {
    dPhiDq = outside / outsideLength;
    return outsideLength;
  }
  dPhiDq.setZero();
  dPhiDq(largest) = 1;
  return q(largest);
}

/// ρ̂ = (x, 0, z)/ρ, or e_x on the y axis.
Vector3 radialDirection(const Vector3& x, Real rho) {
  return rho > 0 ? Vector3(x.x() / rho, 0, x.z() / rho) : Vector3::UnitX();
}

}  // namespace

DistanceSample sphere(const Vector3& x, Real radius) {
  const Real length = x.norm();
  const Vector3 direction = length > 0 ? Vector3(x / length) : Vector3::UnitX();
  return {length - radius, direction};
}

DistanceSample box(const Vector3& x, const Vector3& halfExtents) {
  const Vector3 q = x.cwiseAbs() - halfExtents;
  Vector3 dPhiDq;
  const Real distance = boxDistance<3>(q, dPhiDq);
  const Vector3 signs(signOf(x.x()), signOf(x.y()), signOf(x.z()));
  return {distance, signs.cwiseProduct(dPhiDq)};
}

DistanceSample cylinder(const Vector3& x, Real radius, Real halfHeight) {
  const Real rho = std::hypot(x.x(), x.z());
  const Vector2 q(rho - radius, std::abs(x.y()) - halfHeight);
  Vector2 dPhiDq;
  const Real distance = boxDistance<2>(q, dPhiDq);
  const Vector3 gradient =
      dPhiDq.x() * radialDirection(x, rho) + dPhiDq.y() * signOf(x.y()) * Vector3::UnitY();
  return {distance, gradient};
}

DistanceSample torus(const Vector3& x, Real majorRadius, Real minorRadius) {
  const Real rho = std::hypot(x.x(), x.z());
  const Vector2 q(rho - majorRadius, x.y());
  const Real length = q.norm();
  if (!(length > 0)) return {-minorRadius, Vector3::UnitY()};  // on the centre circle
  const Vector3 gradient = (q.x() * radialDirection(x, rho) + q.y() * Vector3::UnitY()) / length;
  return {length - minorRadius, gradient};
}

DistanceSample hollowSphere(const Vector3& x, Real radius, Real thickness) {
  const DistanceSample solid = sphere(x, radius);
  return {std::abs(solid.distance) - thickness, signOf(solid.distance) * solid.gradient};
}

DistanceSample hollowBox(const Vector3& x, const Vector3& halfExtents, Real thickness) {
  const DistanceSample solid = box(x, halfExtents);
  return {std::abs(solid.distance) - thickness, signOf(solid.distance) * solid.gradient};
}

}  // namespace pbd::sdf
