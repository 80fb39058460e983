#include "pbd/constraints/dihedral_bending.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pbd/constraints/particle_stencil.h"
#include "pbd/model/mesh.h"
#include "pbd/model/scene.h"

namespace pbd {
namespace {

const Real kPi = Real(EIGEN_PI);

/// The normals of the two triangles, scaled by 1/|N|² (zero-sized when degenerate).
struct ScaledNormals {
  Vector3 a, b;
  Vector3 edge;
  Real edgeLength;
  bool valid;
};

ScaledNormals scaledNormals(const std::array<Vector3, 4>& x) {
  ScaledNormals n;
  n.edge = x[1] - x[0];
  n.edgeLength = n.edge.norm();
  const Vector3 normalA = n.edge.cross(x[2] - x[0]);
  const Vector3 normalB = (x[3] - x[0]).cross(n.edge);
  const Real a2 = normalA.squaredNorm(), b2 = normalB.squaredNorm();
  n.valid = n.edgeLength > kEpsilon && a2 > kEpsilon * kEpsilon && b2 > kEpsilon * kEpsilon;
  n.a = n.valid ? Vector3(normalA / a2) : Vector3::Zero();
  n.b = n.valid ? Vector3(normalB / b2) : Vector3::Zero();
  return n;
}

/// θ − θ₀ wrapped into (−π, π].
Real wrappedDifference(Real angle, Real rest) {
  Real d = angle - rest;
  if (d > kPi) d -= 2 * kPi;
  if (d <= -kPi) d += 2 * kPi;
  return d;
}

}  // namespace

Real dihedralAngle(const std::array<Vector3, 4>& x) {
  const Vector3 edge = x[1] - x[0];
  const Vector3 normalA = edge.cross(x[2] - x[0]);
  const Vector3 normalB = (x[3] - x[0]).cross(edge);
  const Real na = normalA.norm(), nb = normalB.norm(), ne = edge.norm();
  if (!(na > 0) || !(nb > 0) || !(ne > 0)) return std::numeric_limits<Real>::quiet_NaN();
  return std::atan2(normalA.cross(normalB).dot(edge) / (na * nb * ne),
                    normalA.dot(normalB) / (na * nb));
}

std::array<Vector3, 4> dihedralAngleGradient(const std::array<Vector3, 4>& x) {
  const ScaledNormals n = scaledNormals(x);
  if (!n.valid) return {Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), Vector3::Zero()};
  const Vector3 unitEdge = n.edge / n.edgeLength;
  return {Vector3(-(x[2] - x[1]).dot(unitEdge) * n.a - (x[3] - x[1]).dot(unitEdge) * n.b),
          Vector3((x[2] - x[0]).dot(unitEdge) * n.a + (x[3] - x[0]).dot(unitEdge) * n.b),
          Vector3(-n.edgeLength * n.a), Vector3(-n.edgeLength * n.b)};
}

BendingCorrection dihedralBendingPbd(const std::array<Vector3, 4>& x,
                                     const std::array<Real, 4>& inverseMasses,
                                     const DihedralBendingConstraint& c) {
  BendingCorrection out;
  const Real angle = dihedralAngle(x);
  if (std::isnan(angle)) return out;  // a degenerate triangle: no direction
  const std::array<Vector3, 4> g = dihedralAngleGradient(x);
  Real weightedNorm = 0;
  for (std::size_t i = 0; i < 4; ++i)
    weightedNorm += inverseMasses[i] * g[i].squaredNorm();
  if (!(weightedNorm > kEpsilon * kEpsilon)) return out;
  const Real s = wrappedDifference(angle, c.restAngle) / weightedNorm;
  for (std::size_t i = 0; i < 4; ++i)
    out.positions[i] = -c.stiffness * s * inverseMasses[i] * g[i];
  return out;
}

namespace {

/// n₁, n₂ (each divided by its squared norm) of the seed's solve and init, from x in pbdval's
/// order: the seed's p₀ = x₂, p₁ = x₃, p₂ = x₀, p₃ = x₁.
void seedNormals(const std::array<Vector3, 4>& x, Vector3& n1, Vector3& n2) {
  const Vector3 &p0 = x[2], &p1 = x[3], &p2 = x[0], &p3 = x[1];
  n1 = (p2 - p0).cross(p3 - p0);
  n1 /= n1.squaredNorm();
  n2 = (p3 - p1).cross(p2 - p1);
  n2 /= n2.squaredNorm();
}

Real seedAngle(Vector3 n1, Vector3 n2) {
  n1.normalize();
  n2.normalize();
  Real dot = n1.dot(n2);
  if (dot < -1) dot = -1;
  if (dot > 1) dot = 1;
  return std::acos(dot);
}

}  // namespace

Real seedDihedralRestAngle(const std::array<Vector3, 4>& x) {
  // DihedralConstraint::initConstraint.
  if ((x[1] - x[0]).norm() < Real(1e-6)) return std::numeric_limits<Real>::quiet_NaN();
  Vector3 n1, n2;
  seedNormals(x, n1, n2);
  return seedAngle(n1, n2);
}

BendingCorrection seedDihedralBendingPbd(const std::array<Vector3, 4>& x,
                                         const std::array<Real, 4>& inverseMasses,
                                         const DihedralBendingConstraint& c) {
  // PositionBasedDynamics::solve_DihedralConstraint, operation by operation.
  BendingCorrection out;
  const Vector3 &p0 = x[2], &p1 = x[3], &p2 = x[0], &p3 = x[1];
  const Real w0 = inverseMasses[2], w1 = inverseMasses[3], w2 = inverseMasses[0],
             w3 = inverseMasses[1];
  if (w0 == 0 && w1 == 0) return out;
  const Vector3 e = p3 - p2;
  const Real elen = e.norm();
  if (elen < Real(1e-6)) return out;
  const Real invElen = Real(1) / elen;
  Vector3 n1, n2;
  seedNormals(x, n1, n2);
  const Vector3 d0 = elen * n1;
  const Vector3 d1 = elen * n2;
  const Vector3 d2 = (p0 - p3).dot(e) * invElen * n1 + (p1 - p3).dot(e) * invElen * n2;
  const Vector3 d3 = (p2 - p0).dot(e) * invElen * n1 + (p2 - p1).dot(e) * invElen * n2;
  n1.normalize();
  n2.normalize();
  Real dot = n1.dot(n2);
  if (dot < -1) dot = -1;
  if (dot > 1) dot = 1;
  const Real phi = std::acos(dot);
  Real lambda =
      w0 * d0.squaredNorm() + w1 * d1.squaredNorm() + w2 * d2.squaredNorm() + w3 * d3.squaredNorm();
  if (lambda == 0) return out;
  lambda = (phi - c.restAngle) / lambda * c.stiffness;
  if (n1.cross(n2).dot(e) > 0) lambda = -lambda;
  out.positions[2] = -w0 * lambda * d0;
  out.positions[3] = -w1 * lambda * d1;
  out.positions[0] = -w2 * lambda * d2;
  out.positions[1] = -w3 * lambda * d3;
  return out;
}

std::vector<DihedralBendingConstraint> clothDihedralConstraints(const Scene& scene) {
  std::vector<DihedralBendingConstraint> constraints;
  const int cloth = scene.simulation.clothSimulationMethod;
  if (cloth < 1 || cloth > 4 || scene.simulation.clothBendingMethod != 1) return constraints;
  for (const TriangleModelDesc& model : scene.triangleModels)
    for (const EdgeStencil& stencil : interiorEdgeStencils(model.mesh)) {
      DihedralBendingConstraint c;
      const std::array<int, 4> local = {stencil.edge[0], stencil.edge[1], stencil.opposite[0],
                                        stencil.opposite[1]};
      for (std::size_t i = 0; i < 4; ++i)
        c.particles[i] = model.firstParticle + local[i];
      std::array<Vector3, 4> rest;
      const bool anyDynamic = restPositions(scene, c.particles, rest);
      c.seedForm = femCutoffFor(scene.simulation) > 0;
      if (c.seedForm) {
        c.restAngle = seedDihedralRestAngle(rest);
        if (std::isnan(c.restAngle)) continue;
      } else {
        c.restAngle = dihedralAngle(rest);
        if (!anyDynamic || std::isnan(c.restAngle)) continue;
      }
      c.stiffness = clothBendingStiffnessFor(scene.simulation);
      constraints.push_back(c);
    }
  return constraints;
}

void solveDihedralBending(const std::vector<DihedralBendingConstraint>& constraints,
                          ParticleStates& particles, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin, n = std::min(end, constraints.size()); k < n; ++k) {
    const DihedralBendingConstraint& c = constraints[k];
    std::array<Vector3, 4> x;
    std::array<Real, 4> w;
    gatherParticles(particles, c.particles, x, w);
    const BendingCorrection d =
        c.seedForm ? seedDihedralBendingPbd(x, w, c) : dihedralBendingPbd(x, w, c);
    applyCorrections(particles, c.particles, d.positions);
  }
}

}  // namespace pbd
