#include "pbd/constraints/generic_constraint.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace pbd {
namespace {

/// K and the right-hand side, dim × dim at most 6 × 6 without heap storage.
using SystemMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor,
                                   kGenericMaxComponents, kGenericMaxComponents>;
using SystemVector =
    Eigen::Matrix<Real, Eigen::Dynamic, 1, Eigen::ColMajor, kGenericMaxComponents, 1>;

}  // namespace

GenericParticleConstraint::GenericParticleConstraint(const std::vector<int>& particles,
                                                     int components, GenericValueFunction value,
                                                     GenericGradientFunction gradient,
                                                     Real stiffness)
    : value_(std::move(value)), gradient_(std::move(gradient)), stiffness_(stiffness) {
  if (particles.empty() || particles.size() > std::size_t(kGenericMaxParticles))
    throw std::invalid_argument("generic constraint: " + std::to_string(particles.size()) +
                                " particles; 1 to " + std::to_string(kGenericMaxParticles) +
                                " are supported");
  if (components < 1 || components > kGenericMaxComponents)
    throw std::invalid_argument("generic constraint: " + std::to_string(components) +
                                " components; 1 to " + std::to_string(kGenericMaxComponents) +
                                " are supported");
  if (!value_) throw std::invalid_argument("generic constraint: no value function");
  if (!(stiffness >= 0 && stiffness <= 1))
    throw std::invalid_argument("generic constraint: stiffness " + std::to_string(stiffness) +
                                " outside [0, 1]");
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles[i] < 0)
      throw std::invalid_argument("generic constraint: negative particle index " +
                                  std::to_string(particles[i]));
    for (std::size_t j = 0; j < i; ++j)
      if (particles[j] == particles[i])
        throw std::invalid_argument("generic constraint: particle " + std::to_string(particles[i]) +
                                    " appears twice");
    particles_[i] = particles[i];
  }
  particleCount_ = int(particles.size());
  componentCount_ = components;
}

void GenericParticleConstraint::jacobian(const GenericPositions& x,
                                         GenericJacobian& gradient) const {
  gradient.setZero();
  if (gradient_) {
    gradient_(x, gradient);
    return;
  }
  const Real relativeStep = std::cbrt(kEpsilon);  // ε^(1/3)
  GenericPositions shifted = x;
  GenericValue plus = GenericValue::Zero(), minus = GenericValue::Zero();
  for (int i = 0; i < particleCount_; ++i)
    for (int c = 0; c < 3; ++c) {
      const Real coordinate = x(c, i);
      const Real step = relativeStep * std::max(Real(1), std::abs(coordinate));
      const Real above = coordinate + step, below = coordinate - step;
      shifted(c, i) = above;
      value_(shifted, plus);
      shifted(c, i) = below;
      value_(shifted, minus);
      shifted(c, i) = coordinate;
      gradient.col(3 * i + c).head(componentCount_) =
          (plus.head(componentCount_) - minus.head(componentCount_)) / (above - below);
    }
}

GenericCorrection genericConstraintPbd(
    const GenericParticleConstraint& constraint, const GenericPositions& x,
    const std::array<Real, kGenericMaxParticles>& inverseMasses) {
  GenericCorrection correction;
  const int n = constraint.particleCount(), dim = constraint.componentCount();
  GenericValue value = GenericValue::Zero();
  constraint.evaluate(x, value);
  GenericJacobian jacobian;
  constraint.jacobian(x, jacobian);
  SystemMatrix k = SystemMatrix::Zero(dim, dim);
  for (int i = 0; i < n; ++i) {
    const Real w = inverseMasses[std::size_t(i)];
    if (w > 0) {
      const auto block = jacobian.block<Eigen::Dynamic, 3>(0, 3 * i, dim, 3);
      k.noalias() += w * (block * block.transpose());
    }
  }
  const Real trace = k.trace();
  if (!(trace > 0) || !std::isfinite(trace) || !value.head(dim).allFinite()) return correction;
  const Eigen::LDLT<SystemMatrix> factorisation(k);
  if (factorisation.info() != Eigen::Success) return correction;
  const Real pivotThreshold = kGenericSingularPivotFactor * kEpsilon * trace;
  if (!(factorisation.vectorD().minCoeff() > pivotThreshold)) return correction;
  const SystemVector multiplier = factorisation.solve(SystemVector(-value.head(dim)));  // Δλ
  for (int i = 0; i < n; ++i) {
    const Real w = inverseMasses[std::size_t(i)];
    if (w > 0)
      correction.delta.col(i) =
          constraint.stiffness() * w *
          (jacobian.block<Eigen::Dynamic, 3>(0, 3 * i, dim, 3).transpose() * multiplier);
  }
  correction.applied = correction.delta.allFinite();
  if (!correction.applied) correction.delta.setZero();
  return correction;
}

void solveGenericConstraints(std::vector<GenericParticleConstraint>& constraints,
                             ParticleStates& particles) {
  for (const GenericParticleConstraint& constraint : constraints) {
    const int n = constraint.particleCount();
    GenericPositions x = GenericPositions::Zero();
    std::array<Real, kGenericMaxParticles> inverseMasses{};
    for (int i = 0; i < n; ++i) {
      const auto index = std::size_t(constraint.particle(i));
      if (index >= particles.size())
        throw std::out_of_range("generic constraint: particle " + std::to_string(index) + " of " +
                                std::to_string(particles.size()));
      x.col(i) = particles.position[index];
      inverseMasses[std::size_t(i)] = particles.inverseMass[index];
    }
    const GenericCorrection correction = genericConstraintPbd(constraint, x, inverseMasses);
    if (!correction.applied) continue;
    for (int i = 0; i < n; ++i)
      particles.position[std::size_t(constraint.particle(i))] += correction.delta.col(i);
  }
}

}  // namespace pbd
