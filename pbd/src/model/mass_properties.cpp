#include "pbd/model/mass_properties.h"

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

namespace pbd {
namespace {

// Inertia about the centre of mass from the second moment Σ = ∫ρ x xᵀ dV (about the origin).
Matrix3 inertiaFromSecondMoment(const Matrix3& secondMomentAboutOrigin, Real mass,
                                const Vector3& centerOfMass) {
  const Matrix3 sigma = secondMomentAboutOrigin - mass * centerOfMass * centerOfMass.transpose();
  return sigma.trace() * Matrix3::Identity() - sigma;
}

SolidMoments diagonalMoments(Real volume, Real density, const Vector3& principal) {
  SolidMoments m;
  m.volume = volume;
  m.mass = density * volume;
  m.inertia = principal.asDiagonal();
  return m;
}

}  // namespace

SolidMoments integrateSolid(const TriangleMesh& mesh, Real density) {
  // Canonical tetrahedron covariance, scaled by 120 (see the header).
  Matrix3 canonical;
  canonical << 2, 1, 1, 1, 2, 1, 1, 1, 2;

  Real sixVolume = 0;                     // Σ det(A)
  Vector3 firstMoment = Vector3::Zero();  // Σ det(A) (a + b + c)  (= 24 ∫ x dV)
  Matrix3 second = Matrix3::Zero();       // Σ det(A) A C Aᵀ       (= 120 ∫ x xᵀ dV)
  for (const auto& tri : mesh.triangles) {
    Matrix3 edges;
    edges.col(0) = mesh.vertices[static_cast<std::size_t>(tri[0])];
    edges.col(1) = mesh.vertices[static_cast<std::size_t>(tri[1])];
    edges.col(2) = mesh.vertices[static_cast<std::size_t>(tri[2])];
    const Real det = edges.determinant();
    sixVolume += det;
    firstMoment += det * (edges.col(0) + edges.col(1) + edges.col(2));
    second += det * edges * canonical * edges.transpose();
  }

  SolidMoments m;
  m.volume = sixVolume / 6;
  m.mass = density * m.volume;
  if (sixVolume == 0) return m;
  // ∫ x dV over a tetrahedron (0,a,b,c) = V (a + b + c)/4 = det/24 (a + b + c).
  m.centerOfMass = firstMoment / (Real(4) * sixVolume);
  const Matrix3 secondAboutOrigin = density * second / Real(120);
  m.inertia = inertiaFromSecondMoment(secondAboutOrigin, m.mass, m.centerOfMass);
  return m;
}

SolidMoments sphereMoments(Real radius, Real density) {
  const Real volume = Real(4) / 3 * Real(EIGEN_PI) * radius * radius * radius;
  const Real moment = Real(2) / 5 * density * volume * radius * radius;
  return diagonalMoments(volume, density, Vector3::Constant(moment));
}

SolidMoments boxMoments(const Vector3& fullExtents, Real density) {
  const Real volume = fullExtents.prod();
  const Real mass = density * volume;
  const Vector3 sq = fullExtents.cwiseProduct(fullExtents);
  return diagonalMoments(volume, density,
                         mass / 12 * Vector3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()));
}

SolidMoments cylinderMoments(Real radius, Real height, Real density) {
  const Real volume = Real(EIGEN_PI) * radius * radius * height;
  const Real mass = density * volume;
  const Real axial = mass * radius * radius / 2;
  const Real transverse = mass * (3 * radius * radius + height * height) / 12;
  return diagonalMoments(volume, density, Vector3(transverse, axial, transverse));
}

MassProperties toPrincipal(const SolidMoments& moments) {
  MassProperties p;
  p.mass = moments.mass;
  p.centerOfMass = moments.centerOfMass;
  const Matrix3& inertia = moments.inertia;

  const Real scale = inertia.diagonal().cwiseAbs().maxCoeff();
  const Real offDiagonal =
      std::max({std::abs(inertia(0, 1)), std::abs(inertia(0, 2)), std::abs(inertia(1, 2))});
  // Already diagonal to round-off (64 ulps of the largest moment): keep the scene axes.
  if (offDiagonal <= 64 * kEpsilon * scale) {
    p.principalInertia = inertia.diagonal();
    p.principalRotation = Quaternion::Identity();
    return p;
  }

  const Eigen::SelfAdjointEigenSolver<Matrix3> solver(inertia);
  const Matrix3 vectors = solver.eigenvectors();
  const Vector3 values = solver.eigenvalues();

  // Assign eigenvectors to scene axes greedily by the largest |component|, so that a body
  // that is almost axis-aligned keeps almost the identity rotation.
  Matrix3 rotation;
  Vector3 principal;
  std::array<bool, 3> usedColumn{false, false, false};
  std::array<bool, 3> usedAxis{false, false, false};
  for (int pick = 0; pick < 3; ++pick) {
    int bestColumn = 0, bestAxis = 0;
    Real best = -1;
    for (int c = 0; c < 3; ++c) {
      if (usedColumn[static_cast<std::size_t>(c)]) continue;
      for (int a = 0; a < 3; ++a) {
        if (usedAxis[static_cast<std::size_t>(a)]) continue;
        if (std::abs(vectors(a, c)) > best) {
          best = std::abs(vectors(a, c));
          bestColumn = c;
          bestAxis = a;
        }
      }
    }
    usedColumn[static_cast<std::size_t>(bestColumn)] = true;
    usedAxis[static_cast<std::size_t>(bestAxis)] = true;
    const Real sign = vectors(bestAxis, bestColumn) < 0 ? Real(-1) : Real(1);
    rotation.col(bestAxis) = sign * vectors.col(bestColumn);
    principal(bestAxis) = values(bestColumn);
  }
  if (rotation.determinant() < 0) rotation.col(2) = -rotation.col(2);

  p.principalInertia = principal;
  p.principalRotation = Quaternion(rotation).normalized();
  return p;
}

std::vector<Real> lumpedMasses(const TriangleMesh& mesh, Real arealDensity) {
  std::vector<Real> masses(mesh.vertices.size(), Real(0));
  for (const auto& t : mesh.triangles) {
    const Vector3& a = mesh.vertices[std::size_t(t[0])];
    const Real area =
        (mesh.vertices[std::size_t(t[1])] - a).cross(mesh.vertices[std::size_t(t[2])] - a).norm() /
        2;
    for (int v : t)
      masses[std::size_t(v)] += arealDensity * area / 3;
  }
  return masses;
}

std::vector<Real> lumpedMasses(const TetMesh& mesh, Real density) {
  std::vector<Real> masses(mesh.vertices.size(), Real(0));
  for (const auto& t : mesh.tetrahedra) {
    const Vector3& a = mesh.vertices[std::size_t(t[0])];
    const Real volume = std::abs((mesh.vertices[std::size_t(t[1])] - a)
                                     .cross(mesh.vertices[std::size_t(t[2])] - a)
                                     .dot(mesh.vertices[std::size_t(t[3])] - a)) /
                        6;
    for (int v : t)
      masses[std::size_t(v)] += density * volume / 4;
  }
  return masses;
}

}  // namespace pbd
