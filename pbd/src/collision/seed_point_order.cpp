// Auto-vectorisation changes the round-off of this file's arithmetic (GCC -O3), and the
// principal frame of a body with equal moments depends on every bit (see the header): compile
// it without, like the seed (built -O0 for the recordings; -O2 gives the same bits).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-tree-vectorize")
#endif

#include "pbd/collision/seed_point_order.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace pbd {
namespace {

// The seed's types (Eigen::DontAlign, double): the same Eigen expressions on the same types take
// the same code paths, so the results agree bit for bit.
using SeedVector = Eigen::Matrix<double, 3, 1, Eigen::DontAlign>;
using SeedMatrix = Eigen::Matrix<double, 3, 3, Eigen::DontAlign>;
using SeedQuaternion = Eigen::Quaternion<double, Eigen::DontAlign>;
using SeedBox = Eigen::AlignedBox<double, 3>;

constexpr unsigned kSeedLeafSize = 10;  // PointCloudBSH's maximum points per leaf

/// Mirtich's polyhedral mass properties ("Fast and accurate computation of polyhedral mass
/// properties", JGT 1996) in the operation order of the seed's Utilities::VolumeIntegration:
/// vertices relative to their mean, unit face normals, projection, face and volume integrals.
class SeedVolumeIntegration {
 public:
  SeedVolumeIntegration(const std::vector<SeedVector>& vertices,
                        const std::vector<std::array<int, 3>>& triangles)
      : triangles_(triangles) {
    SeedVector mean = SeedVector::Zero();
    for (const SeedVector& v : vertices)
      mean += v;
    mean /= static_cast<double>(vertices.size());
    mean_ = mean;
    vertices_.reserve(vertices.size());
    for (const SeedVector& v : vertices)
      vertices_.push_back(v - mean);
    for (const auto& t : triangles_) {
      const SeedVector& a = vertices_[std::size_t(t[0])];
      const SeedVector& b = vertices_[std::size_t(t[1])];
      const SeedVector& c = vertices_[std::size_t(t[2])];
      const SeedVector d1 = b - a;
      const SeedVector d2 = c - a;
      SeedVector n = d1.cross(d2);
      if (n.isZero(1.e-10))
        n.setZero();
      else
        n.normalize();
      normals_.push_back(n);
      weights_.push_back(-n.dot(a));
    }
  }

  /// The inertia tensor about the centre of mass (scene axes) for `density`.
  SeedMatrix inertia(double density) {
    volumeIntegrals();
    const double mass = density * T0_;
    SeedVector r(T1_[0] / T0_, T1_[1] / T0_, T1_[2] / T0_);
    SeedMatrix theta;
    theta(0, 0) = density * (T2_[1] + T2_[2]);
    theta(1, 1) = density * (T2_[2] + T2_[0]);
    theta(2, 2) = density * (T2_[0] + T2_[1]);
    theta(0, 1) = theta(1, 0) = -density * TP_[0];
    theta(1, 2) = theta(2, 1) = -density * TP_[1];
    theta(2, 0) = theta(0, 2) = -density * TP_[2];
    theta(0, 0) -= mass * (r[1] * r[1] + r[2] * r[2]);
    theta(1, 1) -= mass * (r[2] * r[2] + r[0] * r[0]);
    theta(2, 2) -= mass * (r[0] * r[0] + r[1] * r[1]);
    theta(0, 1) = theta(1, 0) += mass * r[0] * r[1];
    theta(1, 2) = theta(2, 1) += mass * r[1] * r[2];
    theta(2, 0) = theta(0, 2) += mass * r[2] * r[0];
    centerOfMass_ = r + mean_;
    return theta;
  }
  const SeedVector& centerOfMass() const { return centerOfMass_; }

 private:
  void projectionIntegrals(std::size_t f) {
    P1 = Pa = Pb = Paa = Pab = Pbb = Paaa = Paab = Pabb = Pbbb = 0.0;
    for (int i = 0; i < 3; i++) {
      const SeedVector& v0 = vertices_[std::size_t(triangles_[f][std::size_t(i)])];
      const SeedVector& v1 = vertices_[std::size_t(triangles_[f][std::size_t((i + 1) % 3)])];
      const double a0 = v0[A], b0 = v0[B], a1 = v1[A], b1 = v1[B];
      const double da = a1 - a0, db = b1 - b0;
      const double a0_2 = a0 * a0, a0_3 = a0_2 * a0, a0_4 = a0_3 * a0;
      const double b0_2 = b0 * b0, b0_3 = b0_2 * b0, b0_4 = b0_3 * b0;
      const double a1_2 = a1 * a1, a1_3 = a1_2 * a1;
      const double b1_2 = b1 * b1, b1_3 = b1_2 * b1;
      const double C1 = a1 + a0;
      const double Ca = a1 * C1 + a0_2, Caa = a1 * Ca + a0_3, Caaa = a1 * Caa + a0_4;
      const double Cb = b1 * (b1 + b0) + b0_2, Cbb = b1 * Cb + b0_3, Cbbb = b1 * Cbb + b0_4;
      const double Cab = 3 * a1_2 + 2 * a1 * a0 + a0_2, Kab = a1_2 + 2 * a1 * a0 + 3 * a0_2;
      const double Caab = a0 * Cab + 4 * a1_3, Kaab = a1 * Kab + 4 * a0_3;
      const double Cabb = 4 * b1_3 + 3 * b1_2 * b0 + 2 * b1 * b0_2 + b0_3;
      const double Kabb = b1_3 + 2 * b1_2 * b0 + 3 * b1 * b0_2 + 4 * b0_3;
      P1 += db * C1;
      Pa += db * Ca;
      Paa += db * Caa;
      Paaa += db * Caaa;
      Pb += da * Cb;
      Pbb += da * Cbb;
      Pbbb += da * Cbbb;
      Pab += db * (b1 * Cab + b0 * Kab);
      Paab += db * (b1 * Caab + b0 * Kaab);
      Pabb += da * (a1 * Cabb + a0 * Kabb);
    }
    P1 /= 2.0;
    Pa /= 6.0;
    Paa /= 12.0;
    Paaa /= 20.0;
    Pb /= -6.0;
    Pbb /= -12.0;
    Pbbb /= -20.0;
    Pab /= 24.0;
    Paab /= 60.0;
    Pabb /= -60.0;
  }

  void faceIntegrals(std::size_t f) {
    projectionIntegrals(f);
    const double w = weights_[f];
    const SeedVector n = normals_[f];
    const double k1 = (n[C] == 0) ? 0 : 1 / n[C];
    const double k2 = k1 * k1, k3 = k2 * k1, k4 = k3 * k1;
    auto sqr = [](double x) { return x * x; };
    auto cube = [](double x) { return x * x * x; };
    Fa = k1 * Pa;
    Fb = k1 * Pb;
    Fc = -k2 * (n[A] * Pa + n[B] * Pb + w * P1);
    Faa = k1 * Paa;
    Fbb = k1 * Pbb;
    Fcc = k3 * (sqr(n[A]) * Paa + 2 * n[A] * n[B] * Pab + sqr(n[B]) * Pbb +
                w * (2 * (n[A] * Pa + n[B] * Pb) + w * P1));
    Faaa = k1 * Paaa;
    Fbbb = k1 * Pbbb;
    Fccc = -k4 * (cube(n[A]) * Paaa + 3 * sqr(n[A]) * n[B] * Paab + 3 * n[A] * sqr(n[B]) * Pabb +
                  cube(n[B]) * Pbbb +
                  3 * w * (sqr(n[A]) * Paa + 2 * n[A] * n[B] * Pab + sqr(n[B]) * Pbb) +
                  w * w * (3 * (n[A] * Pa + n[B] * Pb) + w * P1));
    Faab = k1 * Paab;
    Fbbc = -k2 * (n[A] * Pabb + n[B] * Pbbb + w * Pbb);
    Fcca = k3 * (sqr(n[A]) * Paaa + 2 * n[A] * n[B] * Paab + sqr(n[B]) * Pabb +
                 w * (2 * (n[A] * Paa + n[B] * Pab) + w * Pa));
  }

  void volumeIntegrals() {
    T0_ = T1_[0] = T1_[1] = T1_[2] = T2_[0] = T2_[1] = T2_[2] = TP_[0] = TP_[1] = TP_[2] = 0;
    for (std::size_t i = 0; i < triangles_.size(); ++i) {
      const SeedVector& n = normals_[i];
      const double nx = std::abs(n[0]), ny = std::abs(n[1]), nz = std::abs(n[2]);
      if (nx > ny && nx > nz)
        C = 0;
      else
        C = (ny > nz) ? 1 : 2;
      A = (C + 1) % 3;
      B = (A + 1) % 3;
      faceIntegrals(i);
      T0_ += n[0] * ((A == 0) ? Fa : ((B == 0) ? Fb : Fc));
      T1_[A] += n[A] * Faa;
      T1_[B] += n[B] * Fbb;
      T1_[C] += n[C] * Fcc;
      T2_[A] += n[A] * Faaa;
      T2_[B] += n[B] * Fbbb;
      T2_[C] += n[C] * Fccc;
      TP_[A] += n[A] * Faab;
      TP_[B] += n[B] * Fbbc;
      TP_[C] += n[C] * Fcca;
    }
    for (int k = 0; k < 3; ++k) {
      T1_[k] /= 2;
      T2_[k] /= 3;
      TP_[k] /= 2;
    }
  }

  const std::vector<std::array<int, 3>>& triangles_;
  std::vector<SeedVector> vertices_, normals_;
  std::vector<double> weights_;
  SeedVector mean_ = SeedVector::Zero(), centerOfMass_ = SeedVector::Zero();
  int A = 0, B = 1, C = 2;
  double P1 = 0, Pa = 0, Pb = 0, Paa = 0, Pab = 0, Pbb = 0, Paaa = 0, Paab = 0, Pabb = 0, Pbbb = 0;
  double Fa = 0, Fb = 0, Fc = 0, Faa = 0, Fbb = 0, Fcc = 0, Faaa = 0, Fbbb = 0, Fccc = 0, Faab = 0,
         Fbbc = 0, Fcca = 0;
  double T0_ = 0, T1_[3] = {0, 0, 0}, T2_[3] = {0, 0, 0}, TP_[3] = {0, 0, 0};
};

/// The seed's kd-tree construction over `points`: sorts `list` cell by cell.
void buildSeedKdTree(const std::vector<SeedVector>& points, const SeedBox& box, unsigned begin,
                     unsigned count, std::vector<unsigned>& list) {
  if (count <= kSeedLeafSize) return;
  int axis = 0;
  const SeedVector d = box.diagonal();
  if (d(1) >= d(0) && d(1) >= d(2))
    axis = 1;
  else if (d(2) >= d(0) && d(2) >= d(1))
    axis = 2;
  std::sort(list.begin() + begin, list.begin() + begin + count,
            [&](unsigned a, unsigned b) { return points[a](axis) < points[b](axis); });
  const unsigned half = count / 2;
  const double split =
      0.5 * (points[list[begin + half - 1]](axis) + points[list[begin + half]](axis));
  SeedBox left = box, right = box;
  left.max()(axis) = split;
  right.min()(axis) = split;
  buildSeedKdTree(points, left, begin, half, list);
  buildSeedKdTree(points, right, begin + half, count - half, list);
}

/// rank[i]: point i's position in the index list of the seed's kd-tree over `points` (the
/// root cell is the points' bounding box).
std::vector<int> seedKdTreeRank(const std::vector<SeedVector>& points) {
  const std::size_t n = points.size();
  std::vector<int> rank(n);
  if (n == 0) return rank;
  SeedBox box;
  box.setEmpty();
  for (const SeedVector& p : points)
    box.extend(p);
  std::vector<unsigned> list(n);
  std::iota(list.begin(), list.end(), 0u);
  buildSeedKdTree(points, box, 0, static_cast<unsigned>(n), list);
  for (std::size_t k = 0; k < n; ++k)
    rank[list[k]] = static_cast<int>(k);
  return rank;
}

}  // namespace

std::vector<int> seedVertexReportRank(const TriangleMesh& scaledMesh, const Vector3& scale,
                                      const Vector3& translation, const Quaternion& rotation,
                                      Real density) {
  const std::size_t n = scaledMesh.vertices.size();
  if (n == 0) return {};
  // 1. The mesh as the seed holds it: each file coordinate in single precision, times scale.
  const SeedVector seedScale(double(scale.x()), double(scale.y()), double(scale.z()));
  std::vector<SeedVector> vertices(n);
  for (std::size_t i = 0; i < n; ++i) {
    SeedVector fileVertex;
    for (int k = 0; k < 3; ++k)
      fileVertex(k) = double(float(double(scaledMesh.vertices[i](k)) / seedScale(k)));
    vertices[i] = fileVertex.cwiseProduct(seedScale);
  }
  // 2. The principal frame, composed with the initial rotation.
  SeedVolumeIntegration integration(vertices, scaledMesh.triangles);
  const SeedMatrix inertia = integration.inertia(double(density));
  Eigen::SelfAdjointEigenSolver<SeedMatrix> solver(inertia);
  SeedMatrix principal = solver.eigenvectors();
  if (principal.determinant() < 0.0) principal = -principal;
  const SeedQuaternion q(double(rotation.w()), double(rotation.x()), double(rotation.y()),
                         double(rotation.z()));
  const SeedMatrix initialRotation = q.matrix();
  // 3. The vertices in that frame about the centre of mass, through the initial world pose as
  // the seed computes them (the translation cancels but rounds).
  const SeedVector origin(double(translation.x()), double(translation.y()),
                          double(translation.z()));
  const SeedVector centerOfMass = initialRotation * integration.centerOfMass() + origin;
  principal = initialRotation * principal;
  std::vector<SeedVector> local(n);
  for (std::size_t i = 0; i < n; ++i) {
    const SeedVector world = initialRotation * vertices[i] + origin;
    local[i] = principal.transpose() * (world - centerOfMass);
  }
  // 4. The kd-tree's index list.
  return seedKdTreeRank(local);
}

std::vector<int> seedPointReportRank(const std::vector<Vector3>& points) {
  std::vector<SeedVector> seedPoints(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    seedPoints[i] = SeedVector(double(points[i].x()), double(points[i].y()), double(points[i].z()));
  return seedKdTreeRank(seedPoints);
}

}  // namespace pbd
