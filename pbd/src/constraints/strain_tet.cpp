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

std::array<Vector3, 4> seedStrainTetPbd(const std::array<Vector3, 4>& x,
                                        const std::array<Real, 4>& inverseMasses,
                                        const StrainTetConstraint& c) {
  // PositionBasedDynamics::solve_StrainTetraConstraint, operation by operation.
  std::array<Vector3, 4> corr = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                 Vector3::Zero()};
  const Matrix3& b = c.restInverse;
  const std::array<Vector3, 3> columns = {b.col(0), b.col(1), b.col(2)};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j <= i; ++j) {
      Matrix3 p;
      p.col(0) = (x[1] + corr[1]) - (x[0] + corr[0]);
      p.col(1) = (x[2] + corr[2]) - (x[0] + corr[0]);
      p.col(2) = (x[3] + corr[3]) - (x[0] + corr[0]);
      const Vector3 fi = p * columns[std::size_t(i)];
      const Vector3 fj = p * columns[std::size_t(j)];
      Real sij = fi.dot(fj);
      const bool normalizedShear = c.normalizeShear && i != j;
      Real wi = 0, wj = 0, s1 = 0, s3 = 0;
      if (normalizedShear) {
        wi = fi.norm();
        wj = fj.norm();
        s1 = Real(1) / (wi * wj);
        s3 = s1 * s1 * s1;
      }
      std::array<Vector3, 4> d;
      d[0] = Vector3::Zero();
      for (int k = 0; k < 3; ++k) {
        Vector3& dk = d[std::size_t(k) + 1];
        dk = fj * b(k, i) + fi * b(k, j);
        if (normalizedShear)
          dk = s1 * dk - sij * s3 * (wj * wj * fi * b(k, i) + wi * wi * fj * b(k, j));
        d[0] -= dk;
      }
      if (normalizedShear) sij *= s1;
      Real lambda = inverseMasses[0] * d[0].squaredNorm() + inverseMasses[1] * d[1].squaredNorm() +
                    inverseMasses[2] * d[2].squaredNorm() + inverseMasses[3] * d[3].squaredNorm();
      if (std::abs(lambda) < c.cutoff) continue;
      if (i == j) {
        if (c.normalizeStretch) {
          const Real s = std::sqrt(sij);
          lambda = Real(2) * s * (s - Real(1)) / lambda * c.stretchStiffness;
        } else {
          lambda = (sij - Real(1)) / lambda * c.stretchStiffness;
        }
      } else {
        lambda = sij / lambda * c.shearStiffness;
      }
      for (std::size_t n = 0; n < 4; ++n)
        corr[n] -= lambda * inverseMasses[n] * d[n];
    }
  return corr;
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
      c.cutoff = femCutoffFor(settings);
      if (c.cutoff > 0) {
        // The seed's init_StrainTetraConstraint: D_m⁻¹ when |det D_m| > 10⁻⁶.
        Matrix3 d;
        d.col(0) = rest[1] - rest[0];
        d.col(1) = rest[2] - rest[0];
        d.col(2) = rest[3] - rest[0];
        if (!(std::abs(d.determinant()) > c.cutoff)) continue;
        c.restInverse = d.inverse();
      } else if (!anyDynamic || !strainTetRest(rest, c.restInverse)) {
        continue;
      }
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
    const std::array<Vector3, 4> d =
        c.cutoff > 0 ? seedStrainTetPbd(x, w, c) : strainTetPbd(x, w, c);
    for (std::size_t i = 0; i < 4; ++i)
      particles.position[std::size_t(c.particles[i])] += d[i];
  }
}

}  // namespace pbd
