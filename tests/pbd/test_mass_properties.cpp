// Mass properties against closed forms.
#include <gtest/gtest.h>

#include "pbd/model/mass_properties.h"

namespace pbd {
namespace {

// A closed box mesh [-e/2, e/2]^3 with outward-facing triangles, built independently of any
// file, so volume integration can be checked against m = ρ a b c, I = m (b² + c²)/12, ...
TriangleMesh boxMesh(const Vector3& e, const Vector3& offset) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.push_back(offset + Vector3((i & 1 ? 0.5 : -0.5) * e.x(),
                                             (i & 2 ? 0.5 : -0.5) * e.y(),
                                             (i & 4 ? 0.5 : -0.5) * e.z()));
  }
  // Faces as quads (outward normals), each split into two triangles.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

TEST(MassProperties, BoxMeshMatchesClosedForm) {
  const Vector3 extents(1.0, 2.0, 3.0);
  const Real density = 7.5;
  const SolidMoments closed = boxMoments(extents, density);
  const SolidMoments mesh = integrateSolid(boxMesh(extents, Vector3(0.3, -1.0, 2.0)), density);
  // Exact arithmetic on a box gives exact results; 1e3 ulps covers the summation round-off.
  const Real tol = 1e3 * kEpsilon;
  EXPECT_NEAR(mesh.volume, 6.0, tol * 6);
  EXPECT_NEAR(mesh.mass, closed.mass, tol * closed.mass);
  EXPECT_TRUE(mesh.centerOfMass.isApprox(Vector3(0.3, -1.0, 2.0), tol));
  EXPECT_TRUE(mesh.inertia.isApprox(closed.inertia, tol)) << mesh.inertia;
}

TEST(MassProperties, RotatedBoxHasItsPrincipalAxesRecovered) {
  const Vector3 extents(1.0, 2.0, 3.0);
  TriangleMesh mesh = boxMesh(extents, Vector3::Zero());
  const Quaternion rotation(AngleAxis(0.7, Vector3(1, 2, 3).normalized()));
  for (auto& v : mesh.vertices)
    v = rotation * v;
  const MassProperties p = toPrincipal(integrateSolid(mesh, 2.0));
  const SolidMoments closed = boxMoments(extents, 2.0);
  // The principal moments are distinct, so the principal frame is the box frame up to axis
  // signs, which toPrincipal chooses; compare the reconstructed world inertia instead.
  const Matrix3 reconstructed = p.principalRotation.toRotationMatrix() *
                                p.principalInertia.asDiagonal() *
                                p.principalRotation.toRotationMatrix().transpose();
  const Matrix3 expected =
      rotation.toRotationMatrix() * closed.inertia * rotation.toRotationMatrix().transpose();
  // An eigendecomposition of a well-conditioned 3×3 matrix: ~10³ ε relative.
  EXPECT_TRUE(reconstructed.isApprox(expected, 1e3 * kEpsilon)) << reconstructed << "\n"
                                                                << expected;
  EXPECT_NEAR(p.principalInertia.sum(), closed.inertia.trace(),
              1e3 * kEpsilon * closed.inertia.trace());
}

TEST(MassProperties, DiagonalInertiaKeepsIdentityFrame) {
  const MassProperties p = toPrincipal(boxMoments(Vector3(1, 2, 3), 1.0));
  EXPECT_TRUE(p.principalRotation.isApprox(Quaternion::Identity()));
}

TEST(MassProperties, InsideOutMeshHasNegativeVolume) {
  TriangleMesh mesh = boxMesh(Vector3::Ones(), Vector3::Zero());
  for (auto& t : mesh.triangles)
    std::swap(t[1], t[2]);
  EXPECT_LT(integrateSolid(mesh, 1.0).volume, 0.0);
}

}  // namespace
}  // namespace pbd
