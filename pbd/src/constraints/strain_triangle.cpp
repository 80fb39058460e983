#include "pbd/constraints/strain_triangle.h"

#include <algorithm>
#include <cmath>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/scene.h"

namespace pbd {
namespace {

using Matrix2x2 = Eigen::Matrix<Real, 2, 2>;
using Matrix3x2 = Eigen::Matrix<Real, 3, 2>;

Matrix3x2 deformationGradient(const std::array<Vector3, 3>& x, const Matrix2x2& restInverse) {
  Matrix3x2 edges;
  edges.col(0) = x[1] - x[0];
  edges.col(1) = x[2] - x[0];
  return edges * restInverse;
}

/// C and ∂C/∂f_x, ∂C/∂f_y of one component.
struct Partials {
  Real value = 0;
  Vector3 x = Vector3::Zero();
  Vector3 y = Vector3::Zero();
};

Partials partials(const Matrix3x2& f, const StrainTriangleConstraint& c,
                  StrainComponent component) {
  Partials p;
  const Vector3 fx = f.col(0), fy = f.col(1);
  switch (component) {
    case StrainComponent::Xx:
    case StrainComponent::Yy: {
      const bool alongX = component == StrainComponent::Xx;
      const Vector3 fa = alongX ? fx : fy;
      Vector3& g = alongX ? p.x : p.y;
      if (c.normalizeStretch) {
        const Real length = fa.norm();
        p.value = length - 1;
        if (length > 0) g = fa / length;
      } else {
        p.value = fa.squaredNorm() - 1;
        g = 2 * fa;
      }
      break;
    }
    case StrainComponent::Xy: {
      p.value = fx.dot(fy);
      if (c.normalizeShear) {
        const Real lx = fx.norm(), ly = fy.norm();
        if (!(lx > 0) || !(ly > 0)) return Partials{};
        p.value /= lx * ly;
        p.x = fy / (lx * ly) - p.value * fx / (lx * lx);
        p.y = fx / (lx * ly) - p.value * fy / (ly * ly);
      } else {
        p.x = fy;
        p.y = fx;
      }
      break;
    }
  }
  return p;
}

std::array<Vector3, 3> gradients(const Partials& p, const Matrix2x2& restInverse) {
  const Vector3 g1 = restInverse(0, 0) * p.x + restInverse(0, 1) * p.y;
  const Vector3 g2 = restInverse(1, 0) * p.x + restInverse(1, 1) * p.y;
  return {-g1 - g2, g1, g2};
}

Real stiffnessOf(const StrainTriangleConstraint& c, StrainComponent component) {
  switch (component) {
    case StrainComponent::Xx:
      return c.xxStiffness;
    case StrainComponent::Xy:
      return c.xyStiffness;
    case StrainComponent::Yy:
      return c.yyStiffness;
  }
  return 0;
}

}  // namespace

bool strainTriangleRest(const std::array<Vector3, 3>& rest, Matrix2x2& restInverse) {
  const Vector3 e1 = rest[1] - rest[0], e2 = rest[2] - rest[0];
  const Vector3 normal = e1.cross(e2);
  const Real normalLength = normal.norm(), edgeLength = e1.norm();
  if (!(normalLength > 0) || !(edgeLength > 0)) return false;
  const Vector3 xAxis = e1 / edgeLength;
  const Vector3 yAxis = (normal / normalLength).cross(xAxis);
  Matrix2x2 restEdges;
  restEdges << e1.dot(xAxis), e2.dot(xAxis), e1.dot(yAxis), e2.dot(yAxis);
  if (!(std::abs(restEdges.determinant()) > 0)) return false;
  restInverse = restEdges.inverse();
  return true;
}

Real strainTriangleValue(const std::array<Vector3, 3>& x, const StrainTriangleConstraint& c,
                         StrainComponent component) {
  return partials(deformationGradient(x, c.restInverse), c, component).value;
}

std::array<Vector3, 3> strainTriangleGradients(const std::array<Vector3, 3>& x,
                                               const StrainTriangleConstraint& c,
                                               StrainComponent component) {
  return gradients(partials(deformationGradient(x, c.restInverse), c, component), c.restInverse);
}

std::array<Vector3, 3> strainTrianglePbd(const std::array<Vector3, 3>& x,
                                         const std::array<Real, 3>& inverseMasses,
                                         const StrainTriangleConstraint& c) {
  std::array<Vector3, 3> correction = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  for (StrainComponent component :
       {StrainComponent::Xx, StrainComponent::Xy, StrainComponent::Yy}) {
    const std::array<Vector3, 3> current = {x[0] + correction[0], x[1] + correction[1],
                                            x[2] + correction[2]};
    const Partials p = partials(deformationGradient(current, c.restInverse), c, component);
    const std::array<Vector3, 3> g = gradients(p, c.restInverse);
    Real weightedNorm = 0;
    for (std::size_t i = 0; i < 3; ++i)
      weightedNorm += inverseMasses[i] * g[i].squaredNorm();
    if (!(weightedNorm > 0)) continue;
    const Real s = stiffnessOf(c, component) * p.value / weightedNorm;
    for (std::size_t i = 0; i < 3; ++i)
      correction[i] -= s * inverseMasses[i] * g[i];
  }
  return correction;
}

std::vector<StrainTriangleConstraint> strainTriangleConstraints(const Scene& scene) {
  std::vector<StrainTriangleConstraint> constraints;
  const SimulationSettings& settings = scene.simulation;
  if (settings.clothSimulationMethod != 3) return constraints;
  for (const TriangleModelDesc& model : scene.triangleModels) {
    for (const std::array<int, 3>& triangle : model.mesh.triangles) {
      StrainTriangleConstraint c;
      for (std::size_t i = 0; i < 3; ++i)
        c.particles[i] = model.firstParticle + triangle[i];
      std::array<Vector3, 3> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      if (!anyDynamic || !strainTriangleRest(rest, c.restInverse)) continue;
      c.xxStiffness = settings.cloth_xxStiffness;
      c.yyStiffness = settings.cloth_yyStiffness;
      c.xyStiffness = settings.cloth_xyStiffness;
      c.normalizeStretch = settings.cloth_normalizeStretch;
      c.normalizeShear = settings.cloth_normalizeShear;
      constraints.push_back(c);
    }
  }
  return constraints;
}

void solveStrainTriangles(const std::vector<StrainTriangleConstraint>& constraints,
                          ParticleStates& particles, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    const StrainTriangleConstraint& c = constraints[k];
    std::array<Vector3, 3> x;
    std::array<Real, 3> w;
    gatherParticles(particles, c.particles, x, w);
    const std::array<Vector3, 3> d = strainTrianglePbd(x, w, c);
    applyCorrections(particles, c.particles, d);
  }
}

}  // namespace pbd
