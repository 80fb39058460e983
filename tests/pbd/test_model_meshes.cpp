// The project's model files (cases/models) integrated as solids, against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pbd/io/mesh_loader.h"
#include "pbd/model/mass_properties.h"

namespace pbd {
namespace {

const Real kPi = Real(EIGEN_PI);

TriangleMesh model(const std::string& name) {
  return loadObj(std::string(PBDVAL_SOURCE_DIR) + "/cases/models/" + name);
}

Real maxOffDiagonal(const Matrix3& m) {
  return std::max({std::abs(m(0, 1)), std::abs(m(0, 2)), std::abs(m(1, 2)), std::abs(m(1, 0)),
                   std::abs(m(2, 0)), std::abs(m(2, 1))});
}

TEST(ModelMeshes, CubeIsTheUnitCubeExactly) {
  const TriangleMesh mesh = model("cube.obj");
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  const Real density = 3;
  const SolidMoments m = integrateSolid(mesh, density);
  // Coordinates are ±0.5 (dyadic), so every product and sum is exact; only the final
  // divisions by 6, 24 and 120 round, one ulp each: 4 ulps of slack.
  const Real ulps = 4 * kEpsilon;
  EXPECT_NEAR(m.volume, 1, ulps);
  EXPECT_NEAR(m.mass, density, ulps * density);
  EXPECT_NEAR(m.centerOfMass.norm(), 0, ulps);
  // Unit cube: I = m (1² + 1²) / 12 = m / 6 about every axis.
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(m.inertia(i, i), density / 6, ulps * density);
  EXPECT_LE(maxOffDiagonal(m.inertia), ulps * density);
}

// The regular n-gon prism inscribed in the cylinder of radius R, height H (axis y).
struct PrismClosedForm {
  Real volume, axialMoment, transverseMoment;  // moments about the centre of mass
};

PrismClosedForm regularPrism(int n, Real radius, Real height, Real density) {
  const Real theta = 2 * kPi / n;
  // Area of the n-gon: n triangles (centre, two rim vertices) of area R² sin θ / 2.
  const Real area = n * radius * radius * std::sin(theta) / 2;
  // Polar moment of one such triangle about the centre: (A/6)(|p|² + |q|² + p·q)
  // = R⁴ sin θ (2 + cos θ)/12.
  const Real polar = n * std::pow(radius, Real(4)) * std::sin(theta) * (2 + std::cos(theta)) / 12;
  // A regular polygon (n ≥ 3) has an isotropic in-plane second moment: ∫x² = ∫z² = J/2.
  return {area * height, density * height * polar,
          density * (height * polar / 2 + area * std::pow(height, Real(3)) / 12)};
}

TEST(ModelMeshes, CylinderMatchesTheRegular32GonPrism) {
  const TriangleMesh mesh = model("cylinder.obj");
  EXPECT_EQ(mesh.vertices.size(), 66u);  // 2 rims of 32, 2 cap centres
  EXPECT_EQ(mesh.triangles.size(), 128u);
  const Real density = 2;
  const SolidMoments m = integrateSolid(mesh, density);
  const PrismClosedForm expected = regularPrism(32, 1, 1, density);
  // The rim coordinates are cos/sin rounded to Real (½ ulp each), summed over 128 tetrahedra:
  // 512 ulps (1e-13 in double) is far above that round-off and far below any modelling error.
  const Real relative = 512 * kEpsilon;
  EXPECT_NEAR(m.volume, expected.volume, relative * expected.volume);
  EXPECT_NEAR(m.mass, density * expected.volume, relative * m.mass);
  EXPECT_NEAR(m.centerOfMass.norm(), 0, relative);
  EXPECT_NEAR(m.inertia(1, 1), expected.axialMoment, relative * expected.axialMoment);
  EXPECT_NEAR(m.inertia(0, 0), expected.transverseMoment, relative * expected.transverseMoment);
  EXPECT_NEAR(m.inertia(2, 2), expected.transverseMoment, relative * expected.transverseMoment);
  EXPECT_LE(maxOffDiagonal(m.inertia), relative * expected.axialMoment);
}

TEST(ModelMeshes, CylinderLiesWithinTheDiscretisationBoundOfTheTrueCylinder) {
  // The 32-gon prism contains the cylinder of radius cos(π/32) (its apothem) and is contained
  // in the cylinder of radius 1; volume and moments about the common centre are integrals of
  // non-negative functions, hence monotone under inclusion.
  const Real density = 1, height = 1;
  const Real inner = std::cos(kPi / 32), outer = 1;
  const auto volume = [&](Real r) { return kPi * r * r * height; };
  const auto axial = [&](Real r) { return density * volume(r) * r * r / 2; };
  const auto transverse = [&](Real r) {
    return density * volume(r) * (3 * r * r + height * height) / 12;
  };
  const SolidMoments m = integrateSolid(model("cylinder.obj"), density);
  EXPECT_GT(m.volume, volume(inner));
  EXPECT_LT(m.volume, volume(outer));
  EXPECT_GT(m.inertia(1, 1), axial(inner));
  EXPECT_LT(m.inertia(1, 1), axial(outer));
  for (int i : {0, 2}) {
    EXPECT_GT(m.inertia(i, i), transverse(inner));
    EXPECT_LT(m.inertia(i, i), transverse(outer));
  }
  // The bound is tight: the prism lacks 1 − sin x / x = x²/6 − x⁴/120 + … of the volume, with
  // x = 2π/n; 1e-4 covers the x⁴/120 ≈ 1.2e-5 term left out here.
  EXPECT_NEAR(m.volume / volume(outer), 1 - std::pow(2 * kPi / 32, Real(2)) / 6, 1e-4);
}

TEST(ModelMeshes, IcosphereHasIsotropicInertia) {
  const TriangleMesh mesh = model("sphere.obj");
  EXPECT_EQ(mesh.vertices.size(), 642u);    // 10·4³ + 2
  EXPECT_EQ(mesh.triangles.size(), 1280u);  // 20·4³
  // The generator normalised every vertex in double: |v| = 1 to a few ulps of rounding.
  for (const Vector3& v : mesh.vertices)
    EXPECT_NEAR(v.norm(), 1, 4 * kEpsilon);
  const SolidMoments m = integrateSolid(mesh, 1);
  // Icosahedral symmetry makes the inertia tensor a multiple of the identity; it is broken only
  // by the rounding of the vertex coordinates (½ ulp) and the summation over 1280 tetrahedra:
  // 512 ulps relative (1e-13 in double) bounds both.
  const Real scale = m.inertia.trace() / 3;
  const Real tolerance = 512 * kEpsilon * scale;
  EXPECT_LE(maxOffDiagonal(m.inertia), tolerance);
  EXPECT_NEAR(m.inertia(0, 0), m.inertia(1, 1), tolerance);
  EXPECT_NEAR(m.inertia(1, 1), m.inertia(2, 2), tolerance);
  EXPECT_LE(m.centerOfMass.norm(), 512 * kEpsilon);
}

TEST(ModelMeshes, IcosphereLiesBetweenItsInscribedBallAndTheUnitBall) {
  const TriangleMesh mesh = model("sphere.obj");
  // Inscribed ball: the smallest distance from the centre to a face plane.
  Real inner = 1;
  for (const auto& t : mesh.triangles) {
    const Vector3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vector3& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Vector3& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    inner = std::min(inner, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  const SolidMoments m = integrateSolid(mesh, 1);
  // Ball of radius r: V = 4π r³/3, ∫ r² dV = 4π r⁵/5 = trace(I)/2. Both integrands are
  // non-negative, so both are monotone under inclusion (the polyhedron is convex, contains the
  // inscribed ball and is contained in the unit ball).
  const auto volume = [](Real r) { return 4 * kPi * std::pow(r, Real(3)) / 3; };
  const auto radialMoment = [](Real r) { return 4 * kPi * std::pow(r, Real(5)) / 5; };
  EXPECT_GT(inner, 0.98);  // sanity: three subdivisions are fine
  EXPECT_GT(m.volume, volume(inner));
  EXPECT_LT(m.volume, volume(1));
  EXPECT_GT(m.inertia.trace() / 2, radialMoment(inner));
  EXPECT_LT(m.inertia.trace() / 2, radialMoment(1));
}

}  // namespace
}  // namespace pbd
