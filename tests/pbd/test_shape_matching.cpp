// Shape matching of tets (constraints/shape_matching.h), solidSimulationMethod 5: a rigidly moved
// cluster needs no correction; a deformed cluster with stiffness 1 is projected exactly onto its
// rest shape moved by the best-fit rotation, computed independently here by Horn's quaternion
// method (the largest eigenvector of a symmetric 4 × 4 matrix, no SVD); an inverted cluster is
// rotated, not reflected; the correction is linear in k and divided by the cluster count; the
// corrections conserve Σ m_i x_i (and the momentum up to the seed's 10⁻⁶ in the weights); static
// particles are not moved; in the world: clusters for method 5 only with counts of the tets per
// vertex, and a block hanging from static particles that stays bounded and stretches less with
// more iterations.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/tet_blocks.h"
#include "pbd/constraints/shape_matching.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

// A generic tet (no symmetry), positively oriented.
const std::array<Vector3, 4> kTet = {
    Vector3(Real(0.1), Real(-0.2), Real(0.3)), Vector3(Real(1.2), Real(0.1), Real(-0.1)),
    Vector3(Real(0.3), Real(0.9), Real(0.2)), Vector3(Real(0.2), Real(0.1), Real(1.1))};
const std::array<Real, 4> kInverseMasses = {1, 2, Real(0.5), Real(0.25)};

ShapeMatchingConstraint constraintFor(const std::array<Real, 4>& w = kInverseMasses) {
  ShapeMatchingConstraint c;
  c.particles = {0, 1, 2, 3};
  c.restOffsets = shapeMatchingRestOffsets(kTet, w);
  return c;
}

Vector3 weightedSum(const std::array<Vector3, 4>& v, const std::array<Real, 4>& w) {
  Vector3 s = Vector3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    s += shapeMatchingWeight(w[i]) * v[i];
  return s;
}

Real totalWeight(const std::array<Real, 4>& w) {
  Real s = 0;
  for (Real wi : w)
    s += shapeMatchingWeight(wi);
  return s;
}

// Horn (1987): the rotation R maximising Σ m_i p_i · R q_i is the unit quaternion of the largest
// eigenvalue of N(M), M = Σ m_i q_i p_iᵀ.
Matrix3 hornRotation(const std::array<Vector3, 4>& q, const std::array<Vector3, 4>& p,
                     const std::array<Real, 4>& w) {
  Matrix3 m = Matrix3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    m += shapeMatchingWeight(w[i]) * q[i] * p[i].transpose();
  const Real sxx = m(0, 0), sxy = m(0, 1), sxz = m(0, 2), syx = m(1, 0), syy = m(1, 1),
             syz = m(1, 2), szx = m(2, 0), szy = m(2, 1), szz = m(2, 2);
  Eigen::Matrix<Real, 4, 4> n;
  n << sxx + syy + szz, syz - szy, szx - sxz, sxy - syx,  //
      syz - szy, sxx - syy - szz, sxy + syx, szx + sxz,   //
      szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy,  //
      sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<Real, 4, 4>> eigen(n);
  const Eigen::Matrix<Real, 4, 1> v = eigen.eigenvectors().col(3);  // ascending eigenvalues
  return Quaternion(v(0), v(1), v(2), v(3)).normalized().toRotationMatrix();
}

std::array<Vector3, 4> mapped(const Matrix3& a, const Vector3& t) {
  std::array<Vector3, 4> x;
  for (std::size_t i = 0; i < 4; ++i)
    x[i] = a * kTet[i] + t;
  return x;
}

Matrix3 matrix(Real a, Real b, Real c, Real d, Real e, Real f, Real g, Real h, Real i) {
  Matrix3 m;
  m << a, b, c, d, e, f, g, h, i;
  return m;
}

Real signedVolume(const std::array<Vector3, 4>& p) {
  return (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6;
}

// Round-off of a few dozen O(1) operations (the SVD's included): 1000 ε.
const Real kRoundOff = 1000 * kEpsilon;

TEST(ShapeMatching, RigidlyMovedClusterNeedsNoCorrection) {
  const ShapeMatchingConstraint c = constraintFor();
  for (const Quaternion& q :
       {Quaternion::Identity(), Quaternion(AngleAxis(Real(1.9), Vector3(0, 1, 0))),
        Quaternion(AngleAxis(Real(3.1), Vector3(1, Real(0.2), Real(-3)).normalized())),
        Quaternion(AngleAxis(Real(-0.7), Vector3(Real(0.4), 1, Real(0.3)).normalized()))}) {
    const auto x = mapped(q.toRotationMatrix(), Vector3(-5, 4, Real(0.5)));
    for (const Vector3& dx : shapeMatchingPbd(x, kInverseMasses, c))
      EXPECT_LT(dx.norm(), 10 * kRoundOff);  // positions O(5): 10× the O(1) round-off
  }
}

TEST(ShapeMatching, DeformedClusterIsProjectedOntoTheBestFitRotationOfItsRestShape) {
  const ShapeMatchingConstraint c = constraintFor();
  const Quaternion q(AngleAxis(Real(2.3), Vector3(Real(-0.4), 1, Real(0.3)).normalized()));
  std::array<Vector3, 4> x =
      mapped(q * matrix(Real(1.3), Real(0.2), Real(-0.1), Real(0.05), Real(0.8), Real(0.25),
                        Real(-0.2), Real(0.1), Real(1.1)),
             Vector3(1, -2, Real(0.5)));
  x[2] += Vector3(Real(0.1), Real(-0.05), Real(0.15));
  // The independent fit: centre, offsets, Horn's rotation.
  const Vector3 centre = weightedSum(x, kInverseMasses) / totalWeight(kInverseMasses);
  std::array<Vector3, 4> p;
  for (std::size_t i = 0; i < 4; ++i)
    p[i] = x[i] - centre;
  const Matrix3 r = hornRotation(c.restOffsets, p, kInverseMasses);
  const std::array<Vector3, 4> d = shapeMatchingPbd(x, kInverseMasses, c);
  for (std::size_t i = 0; i < 4; ++i) {
    const Vector3 goal = centre + r * c.restOffsets[i];
    // Horn's eigenvector is accurate to round-off over the eigenvalue gap (O(1) here).
    EXPECT_LT((x[i] + d[i] - goal).norm(), kRoundOff) << i;
    x[i] += d[i];
  }
  // The projected cluster is rigid: a second projection does nothing.
  for (const Vector3& dx : shapeMatchingPbd(x, kInverseMasses, c))
    EXPECT_LT(dx.norm(), kRoundOff);
  // The library's rotation is Horn's.
  Matrix3 a = Matrix3::Zero();
  for (std::size_t i = 0; i < 4; ++i)
    a += shapeMatchingWeight(kInverseMasses[i]) * p[i] * c.restOffsets[i].transpose();
  EXPECT_LT((shapeMatchingRotation(a) - r).norm(), kRoundOff);
}

TEST(ShapeMatching, InvertedClusterIsRotatedNotReflected) {
  const ShapeMatchingConstraint c = constraintFor();
  // The mirror image of the rest tet (z ↦ −z), slightly deformed: det A < 0.
  std::array<Vector3, 4> x =
      mapped(matrix(1, Real(0.1), 0, 0, Real(1.1), 0, 0, 0, -1), Vector3(0, 1, 0));
  ASSERT_LT(signedVolume(x), 0);
  const std::array<Vector3, 4> d = shapeMatchingPbd(x, kInverseMasses, c);
  for (std::size_t i = 0; i < 4; ++i)
    x[i] += d[i];
  // With k = 1 the result is the rest shape rigidly moved: the rest volume, positive.
  EXPECT_NEAR(signedVolume(x), signedVolume(kTet), kRoundOff);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t j = i + 1; j < 4; ++j)
      EXPECT_NEAR((x[i] - x[j]).norm(), (kTet[i] - kTet[j]).norm(), kRoundOff);
}

TEST(ShapeMatching, CorrectionIsLinearInStiffnessAndDividedByTheClusterCount) {
  const auto x = mapped(matrix(Real(1.2), Real(0.1), 0, 0, Real(0.9), Real(0.1), Real(0.05), 0, 1),
                        Vector3::Zero());
  ShapeMatchingConstraint full = constraintFor();
  ShapeMatchingConstraint scaled = full;
  scaled.stiffness = Real(0.3);
  scaled.clusterCounts = {1, 2, 3, 4};
  const std::array<Vector3, 4> d1 = shapeMatchingPbd(x, kInverseMasses, full);
  const std::array<Vector3, 4> d2 = shapeMatchingPbd(x, kInverseMasses, scaled);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_LT((d2[i] - Real(0.3) * d1[i] / Real(i + 1)).norm(), kRoundOff) << i;
}

TEST(ShapeMatching, CorrectionsConserveTheWeightedCentreAndTheMomentum) {
  // Mass-proportional weights: m_i = 1/(w_i + 10⁻⁶) = (1/w_i)(1 − O(10⁻⁶ w_i)).
  const auto x = mapped(matrix(Real(1.2), Real(0.3), 0, Real(-0.1), Real(0.7), Real(0.1),
                               Real(0.05), Real(0.2), Real(1.4)),
                        Vector3(1, 2, 3));
  const std::array<Vector3, 4> d = shapeMatchingPbd(x, kInverseMasses, constraintFor());
  // Σ m_i Δx_i = 0 exactly (Σ m_i q_i = 0), to round-off of masses up to 4.
  EXPECT_LT(weightedSum(d, kInverseMasses).norm(), 10 * kRoundOff);
  Vector3 momentum = Vector3::Zero();
  Real scale = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    momentum += d[i] / kInverseMasses[i];
    scale += d[i].norm() / kInverseMasses[i];
  }
  // The physical momentum differs by Σ Δx_i 10⁻⁶/(w_i (w_i + 10⁻⁶)) ≤ 10⁻⁶ Σ |Δx_i|/w_i² ≤
  // 10⁻⁶ · 4 Σ |Δx_i|/w_i (w_i ≥ 0.25), plus round-off.
  EXPECT_LT(momentum.norm(), 4e-6 * scale + 10 * kRoundOff);
  EXPECT_GT(scale, Real(0.1));  // a real deformation was corrected
}

TEST(ShapeMatching, StaticParticlesAreNotMoved) {
  const std::array<Real, 4> w = {0, 1, 0, 1};
  const ShapeMatchingConstraint c = constraintFor(w);
  const auto x = mapped(matrix(Real(1.2), 0, 0, 0, Real(0.9), 0, 0, 0, Real(1.1)), Vector3::Zero());
  const std::array<Vector3, 4> d = shapeMatchingPbd(x, w, c);
  EXPECT_EQ(d[0], Vector3::Zero());
  EXPECT_EQ(d[2], Vector3::Zero());
  EXPECT_GT(d[1].norm(), Real(0.01));
  EXPECT_GT(d[3].norm(), Real(0.01));
}

// A block of nx × ny × nz vertices 0.25 m apart (x right, y down from 0, z depth), five tets per
// cell.

TEST(ShapeMatchingWorld, SolidsGetOneClusterPerTetFromMethodFiveOnly) {
  Scene scene = test::tetBlock(2, 2, 2, 5);
  for (int method : {0, 1, 2, 3, 4, 5, 6}) {
    scene.simulation.solidSimulationMethod = method;
    EXPECT_EQ(buildWorld(scene).constraints.shapeMatching.size(), method == 5 ? 5u : 0u) << method;
  }
  scene.simulation.solidSimulationMethod = 5;
  std::vector<ShapeMatchingConstraint> clusters = buildWorld(scene).constraints.shapeMatching;
  // The count of a vertex is the number of tets listing it.
  std::vector<int> tetsOf(8, 0);
  for (const auto& t : scene.tetModels[0].mesh.tetrahedra)
    for (int v : t)
      ++tetsOf[std::size_t(v)];
  for (const ShapeMatchingConstraint& c : clusters) {
    EXPECT_EQ(c.stiffness, Real(1));  // the seed's forced solid_stiffness
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_EQ(c.clusterCounts[i], Real(tetsOf[std::size_t(c.particles[i])]));
    EXPECT_LT((c.restOffsets[0] + c.restOffsets[1] + c.restOffsets[2] + c.restOffsets[3]).norm(),
              kRoundOff);  // equal masses: offsets from the centroid
  }
  scene.simulation.solid_stiffness = Real(0.4);
  EXPECT_EQ(buildWorld(scene).constraints.shapeMatching[0].stiffness, Real(0.4));
  // Tets of four static particles are left out: with 0, 1, 2, 4 static, tet {0, 1, 2, 4} is.
  for (int i : {0, 1, 2, 4})
    scene.particles[std::size_t(i)].mass = 0;
  EXPECT_EQ(buildWorld(scene).constraints.shapeMatching.size(), 4u);
}

TEST(ShapeMatchingWorld, HangingBlockStaysBoundedAndStretchesLessWithMoreIterations) {
  // A 0.25 × 1 × 0.25 m column of 2 × 5 × 2 vertices (1 kg each, 20 tets) hangs from its static
  // top face under gravity for 1 s, staying finite and within 2 m of the top (else −1). More
  // iterations, less stretch: PBD's stiffness is its iteration count.
  ASSERT_EQ(buildWorld(test::tetBlock(2, 5, 2, 5)).constraints.shapeMatching.size(), 20u);
  const Real one = test::hangingColumnStretch(5, 1), four = test::hangingColumnStretch(5, 4);
  std::printf("  shape matching: largest edge stretch in 1 s: %.3e (1 iteration), %.3e (4)\n",
              double(one), double(four));
  ASSERT_GE(four, 0);
  EXPECT_LT(four, one);
}

}  // namespace
}  // namespace pbd
