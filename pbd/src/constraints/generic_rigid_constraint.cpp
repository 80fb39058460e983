#include "pbd/constraints/generic_rigid_constraint.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "pbd/joints/joint_parts.h"

namespace pbd {
namespace {

/// K and the right-hand side, dim × dim at most 6 × 6 without heap storage.
using SystemMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                   kGenericRigidMaxComponents, kGenericRigidMaxComponents>;
using SystemVector =
    Eigen::Matrix<Real, Eigen::Dynamic, 1, Eigen::ColMajor, kGenericRigidMaxComponents, 1>;

/// exp(θ/2) for θ = angle · axis, axis a unit coordinate axis: (cos(angle/2), sin(angle/2) eₖ).
Quaternion rotationAboutAxis(int axis, Real angle) {
  Quaternion r(std::cos(angle / 2), 0, 0, 0);
  r.vec()(axis) = std::sin(angle / 2);
  return r;
}

}  // namespace

GenericRigidConstraint::GenericRigidConstraint(const std::vector<int>& bodies, int components,
                                               GenericRigidValueFunction value,
                                               GenericRigidGradientFunction gradient,
                                               Real stiffness, Real compliance)
    : value_(std::move(value)),
      gradient_(std::move(gradient)),
      stiffness_(stiffness),
      compliance_(compliance) {
  if (bodies.empty() || bodies.size() > std::size_t(kGenericRigidMaxBodies))
    throw std::invalid_argument("generic rigid-body constraint: " + std::to_string(bodies.size()) +
                                " bodies; 1 to " + std::to_string(kGenericRigidMaxBodies) +
                                " are supported");
  if (components < 1 || components > kGenericRigidMaxComponents)
    throw std::invalid_argument("generic rigid-body constraint: " + std::to_string(components) +
                                " components; 1 to " + std::to_string(kGenericRigidMaxComponents) +
                                " are supported");
  if (!value_) throw std::invalid_argument("generic rigid-body constraint: no value function");
  if (!(stiffness >= 0 && stiffness <= 1))
    throw std::invalid_argument("generic rigid-body constraint: stiffness " +
                                std::to_string(stiffness) + " outside [0, 1]");
  if (!(compliance >= 0) || !std::isfinite(compliance))
    throw std::invalid_argument("generic rigid-body constraint: compliance " +
                                std::to_string(compliance) + " is not a finite value >= 0");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i] < 0)
      throw std::invalid_argument("generic rigid-body constraint: negative body index " +
                                  std::to_string(bodies[i]));
    for (std::size_t j = 0; j < i; ++j)
      if (bodies[j] == bodies[i])
        throw std::invalid_argument("generic rigid-body constraint: body " +
                                    std::to_string(bodies[i]) + " appears twice");
    bodies_[i] = bodies[i];
  }
  bodyCount_ = int(bodies.size());
  componentCount_ = components;
}

void GenericRigidConstraint::jacobian(const GenericRigidPoses& poses,
                                      GenericRigidJacobian& gradient) const {
  gradient.setZero();
  if (gradient_) {
    gradient_(poses, gradient);
    return;
  }
  const int dim = componentCount_;
  const Real relativeStep = std::cbrt(kEpsilon);  // ε^(1/3)
  GenericRigidPoses shifted = poses;
  GenericRigidValue plus = GenericRigidValue::Zero(), minus = GenericRigidValue::Zero();
  for (int i = 0; i < bodyCount_; ++i) {
    const auto b = std::size_t(i);
    for (int c = 0; c < 3; ++c) {  // ∂C/∂xᵢ
      const Real coordinate = poses.position[b](c);
      const Real step = relativeStep * std::max(Real(1), std::abs(coordinate));
      const Real above = coordinate + step, below = coordinate - step;
      shifted.position[b](c) = above;
      value_(shifted, plus);
      shifted.position[b](c) = below;
      value_(shifted, minus);
      shifted.position[b](c) = coordinate;
      gradient.col(6 * i + c).head(dim) = (plus.head(dim) - minus.head(dim)) / (above - below);
    }
    for (int c = 0; c < 3; ++c) {  // ∂C/∂θᵢ, exact rotations by ±h_θ about the world axis c
      shifted.rotation[b] = (rotationAboutAxis(c, relativeStep) * poses.rotation[b]).normalized();
      value_(shifted, plus);
      shifted.rotation[b] = (rotationAboutAxis(c, -relativeStep) * poses.rotation[b]).normalized();
      value_(shifted, minus);
      shifted.rotation[b] = poses.rotation[b];
      gradient.col(6 * i + 3 + c).head(dim) =
          (plus.head(dim) - minus.head(dim)) / (2 * relativeStep);
    }
  }
}

GenericRigidCorrection genericRigidProjection(const GenericRigidConstraint& constraint,
                                              const GenericRigidPoses& poses,
                                              const GenericRigidInverseMasses& inverseMasses,
                                              Real complianceTilde,
                                              const GenericRigidValue& multiplier) {
  GenericRigidCorrection correction;
  const int n = constraint.bodyCount(), dim = constraint.componentCount();
  GenericRigidValue value = GenericRigidValue::Zero();
  constraint.evaluate(poses, value);
  GenericRigidJacobian jacobian;
  constraint.jacobian(poses, jacobian);
  // Jᵢ Wᵢ Jᵢᵀ = mᵢ⁻¹ J_x J_xᵀ + J_θ I_w⁻¹ J_θᵀ, summed over the dynamic bodies.
  SystemMatrix k = SystemMatrix::Zero(dim, dim);
  for (int i = 0; i < n; ++i) {
    const EndInverseMass& w = inverseMasses[std::size_t(i)];
    if (!(w.linear > 0)) continue;  // static: W = 0
    const auto linear = jacobian.block<Eigen::Dynamic, 3>(0, 6 * i, dim, 3);
    const auto angular = jacobian.block<Eigen::Dynamic, 3>(0, 6 * i + 3, dim, 3);
    k.noalias() += w.linear * (linear * linear.transpose());
    k.noalias() += angular * (w.angular * angular.transpose());
  }
  const Real trace = k.trace();
  if (!(trace > 0) || !std::isfinite(trace) || !value.head(dim).allFinite()) return correction;
  k.diagonal().array() += complianceTilde;
  const Eigen::LDLT<SystemMatrix> factorisation(k);
  if (factorisation.info() != Eigen::Success) return correction;
  const Real pivotThreshold = kGenericSingularPivotFactor * kEpsilon * k.trace();
  if (!(factorisation.vectorD().minCoeff() > pivotThreshold)) return correction;
  const SystemVector rhs = -value.head(dim) - complianceTilde * multiplier.head(dim);
  const SystemVector applied = constraint.stiffness() * factorisation.solve(rhs);  // k Δλ
  for (int i = 0; i < n; ++i) {
    const auto b = std::size_t(i);
    const EndInverseMass& w = inverseMasses[b];
    if (!(w.linear > 0)) continue;
    correction.linear[b] =
        w.linear * (jacobian.block<Eigen::Dynamic, 3>(0, 6 * i, dim, 3).transpose() * applied);
    correction.angular[b] =
        w.angular * (jacobian.block<Eigen::Dynamic, 3>(0, 6 * i + 3, dim, 3).transpose() * applied);
  }
  correction.multiplier.head(dim) = applied;
  bool finite = correction.multiplier.allFinite();
  for (int i = 0; i < n; ++i)
    finite = finite && correction.linear[std::size_t(i)].allFinite() &&
             correction.angular[std::size_t(i)].allFinite();
  if (!finite) return GenericRigidCorrection();
  correction.applied = true;
  return correction;
}

void solveGenericRigidConstraints(std::vector<GenericRigidConstraint>& constraints,
                                  RigidBodyStates& bodies, Real substepSize, bool firstIteration) {
  for (GenericRigidConstraint& constraint : constraints) {
    if (firstIteration) constraint.multiplier().setZero();
    const int n = constraint.bodyCount();
    GenericRigidPoses poses;
    GenericRigidInverseMasses inverseMasses{};
    for (int i = 0; i < n; ++i) {
      const auto index = std::size_t(constraint.body(i));
      if (index >= bodies.size())
        throw std::out_of_range("generic rigid-body constraint: body " + std::to_string(index) +
                                " of " + std::to_string(bodies.size()));
      poses.position[std::size_t(i)] = bodies.position[index];
      poses.rotation[std::size_t(i)] = bodies.rotation[index];
      inverseMasses[std::size_t(i)] = joint_parts::rigidEnd(bodies, constraint.body(i));
    }
    const Real complianceTilde = constraint.compliance() / (substepSize * substepSize);
    const GenericRigidCorrection correction = genericRigidProjection(
        constraint, poses, inverseMasses, complianceTilde, constraint.multiplier());
    if (!correction.applied) continue;
    constraint.multiplier() += correction.multiplier;
    for (int i = 0; i < n; ++i)
      joint_parts::applyPositionCorrection(bodies, constraint.body(i),
                                           correction.linear[std::size_t(i)],
                                           correction.angular[std::size_t(i)]);
  }
}

}  // namespace pbd
