#include "pbd/constraints/strain_tet.h"

#include <algorithm>
#include <cmath>

#include "pbd/model/scene.h"

namespace pbd {
namespace {

Matrix3 deformationGradient(const std::array<Vector3, 4>& x, const Matrix3& restInverse) {
  Matrix3 edges;
  edges.col(0) = x[1] - x[0];
  edges.col(1) = x[2] - x[0];
  edges.col(2) = x[3] - x[0];
  return edges * restInverse;
}

/// The material axes (a, b) of a component (a = b for a stretch).
void axesOf(TetStrainComponent component, int& a, int& b) {
  switch (component) {
    case TetStrainComponent::Xx:
      a = b = 0;
      return;
    case TetStrainComponent::Yy:
      a = b = 1;
      return;
    case TetStrainComponent::Zz:
      a = b = 2;
      return;
    case TetStrainComponent::Xy:
      a = 0;
      b = 1;
      return;
    case TetStrainComponent::Xz:
      a = 0;
      b = 2;
      return;
    case TetStrainComponent::Yz:
      a = 1;
      b = 2;
      return;
  }
  a = b = 0;
}

/// C and ∂C/∂f_k (k = 0, 1, 2; the columns of `partial`) of one component.
struct Partials {
  Real value = 0;
  Matrix3 partial = Matrix3::Zero();
};

Partials partials(const Matrix3& f, const StrainTetConstraint& c, TetStrainComponent component) {
  Partials p;
  int a = 0, b = 0;
  axesOf(component, a, b);
  const Vector3 fa = f.col(a), fb = f.col(b);
  if (a == b) {
    if (c.normalizeStretch) {
      const Real length = fa.norm();
      p.value = length - 1;
      if (length > 0) p.partial.col(a) = fa / length;
    } else {
      p.value = fa.squaredNorm() - 1;
      p.partial.col(a) = 2 * fa;
    }
    return p;
  }
  p.value = fa.dot(fb);
  if (c.normalizeShear) {
    const Real la = fa.norm(), lb = fb.norm();
    if (!(la > 0) || !(lb > 0)) return Partials{};
    p.value /= la * lb;
    p.partial.col(a) = fb / (la * lb) - p.value * fa / (la * la);
    p.partial.col(b) = fa / (la * lb) - p.value * fb / (lb * lb);
  } else {
    p.partial.col(a) = fb;
    p.partial.col(b) = fa;
  }
  return p;
}

std::array<Vector3, 4> gradients(const Partials& p, const Matrix3& restInverse) {
  // ∇_{x_{k+1}}C = Σ_a B(k, a) ∂C/∂f_a: the columns of (∂C/∂F) Bᵀ.
  const Matrix3 g = p.partial * restInverse.transpose();
  return {-(g.col(0) + g.col(1) + g.col(2)), g.col(0), g.col(1), g.col(2)};
}

bool isStretch(TetStrainComponent component) {
  return component == TetStrainComponent::Xx || component == TetStrainComponent::Yy ||
         component == TetStrainComponent::Zz;
}

}  // namespace

bool strainTetRest(const std::array<Vector3, 4>& rest, Matrix3& restInverse) {
  Matrix3 d;
  d.col(0) = rest[1] - rest[0];
  d.col(1) = rest[2] - rest[0];
  d.col(2) = rest[3] - rest[0];
  const Real det = d.determinant();
  const Real scale = d.col(0).norm() * d.col(1).norm() * d.col(2).norm();
  // The determinant's round-off is a few ε of the product of the edge lengths.
  if (!(std::abs(det) > 100 * kEpsilon * scale)) return false;
  restInverse = d.inverse();
  return true;
}

Real strainTetValue(const std::array<Vector3, 4>& x, const StrainTetConstraint& c,
                    TetStrainComponent component) {
  return partials(deformationGradient(x, c.restInverse), c, component).value;
}

std::array<Vector3, 4> strainTetGradients(const std::array<Vector3, 4>& x,
                                          const StrainTetConstraint& c,
                                          TetStrainComponent component) {
  return gradients(partials(deformationGradient(x, c.restInverse), c, component), c.restInverse);
}

std::array<Vector3, 4> strainTetPbd(const std::array<Vector3, 4>& x,
                                    const std::array<Real, 4>& inverseMasses,
                                    const StrainTetConstraint& c) {
  std::array<Vector3, 4> correction = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                       Vector3::Zero()};
  for (TetStrainComponent component : kTetStrainComponents) {
    const std::array<Vector3, 4> current = {x[0] + correction[0], x[1] + correction[1],
                                            x[2] + correction[2], x[3] + correction[3]};
    const Partials p = partials(deformationGradient(current, c.restInverse), c, component);
    const std::array<Vector3, 4> g = gradients(p, c.restInverse);
    Real weightedNorm = 0;
    for (std::size_t i = 0; i < 4; ++i)
      weightedNorm += inverseMasses[i] * g[i].squaredNorm();
    if (!(weightedNorm > 0)) continue;
    const Real k = isStretch(component) ? c.stretchStiffness : c.shearStiffness;
    const Real s = k * p.value / weightedNorm;
    for (std::size_t i = 0; i < 4; ++i)
      correction[i] -= s * inverseMasses[i] * g[i];
  }
  return correction;
}

std::vector<StrainTetConstraint> strainTetConstraints(const Scene& scene) {
  std::vector<StrainTetConstraint> constraints;
  const SimulationSettings& settings = scene.simulation;
  if (settings.solidSimulationMethod != 4) return constraints;
  const Real stiffness = solidStiffnessFor(settings);
  for (const TetModelDesc& model : scene.tetModels)
    for (const auto& tet : model.mesh.tetrahedra) {
      StrainTetConstraint c;
      std::array<Vector3, 4> rest;
      bool anyDynamic = false;
      for (std::size_t i = 0; i < 4; ++i) {
        c.particles[i] = model.firstParticle + int(tet[i]);
        const ParticleDesc& particle = scene.particles[std::size_t(c.particles[i])];
        rest[i] = particle.position;
        anyDynamic = anyDynamic || particle.mass > 0;
      }
      if (!anyDynamic || !strainTetRest(rest, c.restInverse)) continue;
      c.stretchStiffness = stiffness;
      c.shearStiffness = stiffness;
      c.normalizeStretch = settings.solid_normalizeStretch;
      c.normalizeShear = settings.solid_normalizeShear;
      constraints.push_back(c);
    }
  return constraints;
}

void solveStrainTets(const std::vector<StrainTetConstraint>& constraints, ParticleStates& particles,
                     std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    const StrainTetConstraint& c = constraints[k];
    std::array<Vector3, 4> x;
    std::array<Real, 4> w;
    for (std::size_t i = 0; i < 4; ++i) {
      x[i] = particles.position[std::size_t(c.particles[i])];
      w[i] = particles.inverseMass[std::size_t(c.particles[i])];
    }
    const std::array<Vector3, 4> d = strainTetPbd(x, w, c);
    for (std::size_t i = 0; i < 4; ++i)
      particles.position[std::size_t(c.particles[i])] += d[i];
  }
}

}  // namespace pbd
