#include "pbd/constraints/shape_matching.h"

#include <Eigen/SVD>
#include <algorithm>

#include "pbd/constraints/strain_tet.h"
#include "pbd/model/scene.h"

namespace pbd {

Real shapeMatchingWeight(Real inverseMass) {
  return Real(1) / (inverseMass + kShapeMatchingWeightEpsilon);
}

namespace {

Vector3 weightedCentre(const std::array<Vector3, 4>& x, const std::array<Real, 4>& inverseMasses) {
  Vector3 sum = Vector3::Zero();
  Real total = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const Real m = shapeMatchingWeight(inverseMasses[i]);
    sum += m * x[i];
    total += m;
  }
  return sum / total;
}

}  // namespace

std::array<Vector3, 4> shapeMatchingRestOffsets(const std::array<Vector3, 4>& rest,
                                                const std::array<Real, 4>& inverseMasses) {
  const Vector3 centre = weightedCentre(rest, inverseMasses);
  return {rest[0] - centre, rest[1] - centre, rest[2] - centre, rest[3] - centre};
}

Matrix3 shapeMatchingRotation(const Matrix3& a) {
  const Eigen::JacobiSVD<Matrix3> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix3 u = svd.matrixU();
  const Matrix3 v = svd.matrixV();
  // U Vᵀ is a reflection when det A < 0 (or U, V came out with opposite handedness): flipping
  // the direction of the smallest singular value gives the nearest rotation.
  if ((u * v.transpose()).determinant() < 0) u.col(2) = -u.col(2);
  return u * v.transpose();
}

std::array<Vector3, 4> shapeMatchingPbd(const std::array<Vector3, 4>& x,
                                        const std::array<Real, 4>& inverseMasses,
                                        const ShapeMatchingConstraint& c) {
  std::array<Vector3, 4> correction = {Vector3::Zero(), Vector3::Zero(), Vector3::Zero(),
                                       Vector3::Zero()};
  const Vector3 centre = weightedCentre(x, inverseMasses);
  Matrix3 a = Matrix3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    a += shapeMatchingWeight(inverseMasses[i]) * (x[i] - centre) * c.restOffsets[i].transpose();
  const Matrix3 r = shapeMatchingRotation(a);
  for (std::size_t i = 0; i < 4; ++i) {
    if (!(inverseMasses[i] > 0)) continue;
    const Vector3 goal = centre + r * c.restOffsets[i];
    correction[i] = c.stiffness * (goal - x[i]) / c.clusterCounts[i];
  }
  return correction;
}

std::vector<ShapeMatchingConstraint> shapeMatchingConstraints(const Scene& scene) {
  std::vector<ShapeMatchingConstraint> constraints;
  const SimulationSettings& settings = scene.simulation;
  if (settings.solidSimulationMethod != 5) return constraints;
  const Real stiffness = solidStiffnessFor(settings);
  std::vector<int> counts(scene.particles.size(), 0);
  for (const TetModelDesc& model : scene.tetModels)
    for (const auto& tet : model.mesh.tetrahedra) {
      ShapeMatchingConstraint c;
      std::array<Vector3, 4> rest;
      std::array<Real, 4> inverseMasses;
      bool anyDynamic = false;
      for (std::size_t i = 0; i < 4; ++i) {
        c.particles[i] = model.firstParticle + int(tet[i]);
        const ParticleDesc& particle = scene.particles[std::size_t(c.particles[i])];
        rest[i] = particle.position;
        inverseMasses[i] = particle.mass > 0 ? Real(1) / particle.mass : Real(0);
        anyDynamic = anyDynamic || particle.mass > 0;
      }
      Matrix3 unused;
      if (!anyDynamic || !strainTetRest(rest, unused)) continue;
      c.restOffsets = shapeMatchingRestOffsets(rest, inverseMasses);
      c.stiffness = stiffness;
      for (int p : c.particles)
        ++counts[std::size_t(p)];
      constraints.push_back(c);
    }
  for (ShapeMatchingConstraint& c : constraints)
    for (std::size_t i = 0; i < 4; ++i)
      c.clusterCounts[i] = Real(counts[std::size_t(c.particles[i])]);
  return constraints;
}

void solveShapeMatching(const std::vector<ShapeMatchingConstraint>& constraints,
                        ParticleStates& particles, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    const ShapeMatchingConstraint& c = constraints[k];
    std::array<Vector3, 4> x;
    std::array<Real, 4> w;
    for (std::size_t i = 0; i < 4; ++i) {
      x[i] = particles.position[std::size_t(c.particles[i])];
      w[i] = particles.inverseMass[std::size_t(c.particles[i])];
    }
    const std::array<Vector3, 4> d = shapeMatchingPbd(x, w, c);
    for (std::size_t i = 0; i < 4; ++i)
      particles.position[std::size_t(c.particles[i])] += d[i];
  }
}

}  // namespace pbd
