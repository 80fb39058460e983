// The analytic signed distance functions (collision/analytic_shapes.h) and CollisionShape:
// values at points whose distance is known in closed form (inside, outside, on the surface),
// gradients against central differences, and the shape options (invertSDF, thicknessSDF).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "common/scene_fixtures.h"
#include "common/tolerances.h"
#include "pbd/collision/collision_shape.h"

namespace pbd {
namespace {

// Closed-form values are a handful of additions, square roots and comparisons: exact to a few
// ulps of the O(1) coordinates.
const Real kValueTolerance = 16 * kEpsilon;

struct KnownDistance {
  Vector3 point;
  Real distance;
};

void expectDistances(const std::function<DistanceSample(const Vector3&)>& shape,
                     const std::vector<KnownDistance>& cases, const char* name) {
  for (const KnownDistance& c : cases)
    EXPECT_NEAR(shape(c.point).distance, c.distance, kValueTolerance)
        << name << " at " << c.point.transpose();
}

/// ∇φ against central differences, and |∇φ| = 1 (φ is a Euclidean distance), at random points
/// of [−range, range]³ at least `margin` away from the sets where φ is not differentiable
/// (`kink(x)` returns the distance to them).
void expectGradients(const std::function<DistanceSample(const Vector3&)>& shape, Real range,
                     const std::function<Real(const Vector3&)>& kink, const char* name) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-double(range), double(range));
  const Real step = test::finiteDifferenceStep();
  // Away from the kinks the third derivatives are at most ~1/margin² (curvatures of 1/ρ), so
  // the central-difference truncation step²/6 · 1/margin² stays below the tolerance.
  const Real margin = Real(0.1);
  int tested = 0;
  while (tested < 200) {
    const Vector3 x(Real(coordinate(random)), Real(coordinate(random)), Real(coordinate(random)));
    if (kink(x) < margin) continue;
    ++tested;
    const DistanceSample s = shape(x);
    Vector3 numeric;
    for (int axis = 0; axis < 3; ++axis) {
      Vector3 e = Vector3::Zero();
      e(axis) = step;
      numeric(axis) = (shape(x + e).distance - shape(x - e).distance) / (2 * step);
    }
    EXPECT_LE((s.gradient - numeric).norm(), test::finiteDifferenceTolerance())
        << name << " at " << x.transpose();
    EXPECT_NEAR(s.gradient.norm(), Real(1), kValueTolerance) << name << " at " << x.transpose();
  }
}

TEST(AnalyticShapes, SphereMatchesItsFormula) {
  auto f = [](const Vector3& x) { return sdf::sphere(x, Real(0.5)); };
  expectDistances(f,
                  {{Vector3(1, 0, 0), Real(0.5)},
                   {Vector3(0, Real(0.2), 0), Real(-0.3)},
                   {Vector3(Real(0.3), Real(0.4), 0), Real(0)},
                   {Vector3(0, 0, 0), Real(-0.5)},
                   {Vector3(2, 2, 1), Real(2.5)}},
                  "sphere");
  expectGradients(
      f, 1, [](const Vector3& x) { return x.norm(); }, "sphere");
}

TEST(AnalyticShapes, BoxMatchesItsFormula) {
  const Vector3 half(1, Real(0.5), Real(0.25));
  auto f = [&](const Vector3& x) { return sdf::box(x, half); };
  expectDistances(f,
                  {{Vector3(2, 0, 0), 1},                                     // face
                   {Vector3(2, Real(1.5), 0), std::sqrt(Real(2))},            // edge
                   {Vector3(-2, Real(1.5), Real(1.25)), std::sqrt(Real(3))},  // corner
                   {Vector3(Real(0.5), 0, 0), Real(-0.25)},                   // inside: nearest z
                   {Vector3(Real(0.9), 0, 0), Real(-0.1)},                    // inside: nearest x
                   {Vector3(1, Real(0.2), Real(0.1)), 0}},                    // on the surface
                  "box");
  // Not differentiable on the medial surfaces inside (|x_i| − b_i = |x_j| − b_j) and on the
  // coordinate planes through the box outside the faces' extent, where sgn(x) flips.
  auto kink = [&](const Vector3& x) {
    const Vector3 q = x.cwiseAbs() - half;
    Real d = std::numeric_limits<Real>::infinity();
    if ((q.array() < 0).all()) {
      d = std::min({std::abs(q.x() - q.y()), std::abs(q.y() - q.z()), std::abs(q.x() - q.z())});
    }
    return std::min({d, x.cwiseAbs().minCoeff(), q.cwiseAbs().minCoeff()});
  };
  expectGradients(f, 2, kink, "box");
}

TEST(AnalyticShapes, CylinderMatchesItsFormula) {
  auto f = [](const Vector3& x) { return sdf::cylinder(x, 1, 1); };  // r 1, half height 1
  expectDistances(f,
                  {{Vector3(2, 0, 0), 1},
                   {Vector3(0, 3, 0), 2},
                   {Vector3(0, 0, -2), 1},
                   {Vector3(2, 2, 0), std::sqrt(Real(2))},
                   {Vector3(Real(0.5), 0, 0), Real(-0.5)},
                   {Vector3(0, Real(0.8), 0), Real(-0.2)},
                   {Vector3(Real(0.6), Real(-1), Real(0.8)), 0}},
                  "cylinder");
  auto kink = [](const Vector3& x) {
    const Real rho = std::hypot(x.x(), x.z());
    const Real qr = rho - 1, qy = std::abs(x.y()) - 1;
    Real d = std::min({rho, std::abs(x.y()), std::abs(qr), std::abs(qy)});
    if (qr < 0 && qy < 0) d = std::min(d, std::abs(qr - qy));
    return d;
  };
  expectGradients(f, 2, kink, "cylinder");
}

TEST(AnalyticShapes, TorusMatchesItsFormula) {
  auto f = [](const Vector3& x) { return sdf::torus(x, 2, Real(0.5)); };
  expectDistances(f,
                  {{Vector3(2, 0, 0), Real(-0.5)},
                   {Vector3(3, 0, 0), Real(0.5)},
                   {Vector3(0, 0, 0), Real(1.5)},
                   {Vector3(0, 1, -2), Real(0.5)},
                   {Vector3(0, 0, Real(2.5)), 0},
                   {Vector3(0, 0, Real(-1.5)), 0}},
                  "torus");
  auto kink = [](const Vector3& x) {
    const Real rho = std::hypot(x.x(), x.z());
    return std::min(rho, std::hypot(rho - 2, x.y()));  // the y axis and the centre circle
  };
  expectGradients(f, 3, kink, "torus");
}

TEST(AnalyticShapes, HollowShapesAreShellsOfThicknessTwiceTheParameter) {
  auto sphere = [](const Vector3& x) { return sdf::hollowSphere(x, 1, Real(0.1)); };
  expectDistances(sphere,
                  {{Vector3(1, 0, 0), Real(-0.1)},
                   {Vector3(0, 0, 0), Real(0.9)},
                   {Vector3(0, 2, 0), Real(0.9)},
                   {Vector3(0, Real(1.1), 0), 0},
                   {Vector3(0, Real(0.9), 0), 0}},
                  "hollow sphere");
  expectGradients(
      sphere, 2, [](const Vector3& x) { return std::min(x.norm(), std::abs(x.norm() - 1)); },
      "hollow sphere");
  const Vector3 half(1, 1, 1);
  auto box = [&](const Vector3& x) { return sdf::hollowBox(x, half, Real(0.1)); };
  expectDistances(box,
                  {{Vector3(0, 0, 0), Real(0.9)},
                   {Vector3(1, 0, 0), Real(-0.1)},
                   {Vector3(2, 0, 0), Real(0.9)},
                   {Vector3(0, 0, Real(-0.9)), 0}},
                  "hollow box");
}

RigidBodyDesc shapeBody(CollisionObjectType type, const Vector3& scale) {
  RigidBodyDesc body = test::boxBody(3, Vector3::Ones(), Vector3::Zero());
  body.collision.type = type;
  body.collision.scale = scale;
  return body;
}

TEST(CollisionShape, UsesTheSeedsParametersPerType) {
  const Vector3 p(Real(0.3), Real(-0.7), Real(0.2));
  struct Case {
    CollisionObjectType type;
    Vector3 scale;
    DistanceSample expected;
  };
  const Real t = Real(0.1);  // thicknessSDF's default
  const Case cases[] = {
      {CollisionObjectType::Sphere, Vector3(2, 9, 9), sdf::sphere(p, 2)},
      {CollisionObjectType::Box, Vector3(2, 4, 6), sdf::box(p, Vector3(1, 2, 3))},
      {CollisionObjectType::Cylinder, Vector3(2, 4, 9), sdf::cylinder(p, 2, 2)},
      {CollisionObjectType::Torus, Vector3(2, Real(0.5), 9), sdf::torus(p, 2, Real(0.5))},
      {CollisionObjectType::HollowSphere, Vector3(2, 9, 9), sdf::hollowSphere(p, 2, t)},
      {CollisionObjectType::HollowBox, Vector3(2, 4, 6), sdf::hollowBox(p, Vector3(1, 2, 3), t)},
  };
  for (const Case& c : cases) {
    RigidBodyDesc body = shapeBody(c.type, c.scale);
    const CollisionShape shape = makeCollisionShape(body);
    EXPECT_EQ(shape.distance(p), c.expected.distance) << static_cast<int>(c.type);
    EXPECT_EQ(shape.gradient(p), c.expected.gradient) << static_cast<int>(c.type);
    // invertSDF swaps inside and outside: value and gradient change sign.
    body.collision.invertSDF = true;
    const CollisionShape inverted = makeCollisionShape(body);
    EXPECT_EQ(inverted.distance(p), -c.expected.distance) << static_cast<int>(c.type);
    EXPECT_EQ(inverted.gradient(p), -c.expected.gradient) << static_cast<int>(c.type);
  }
  // thicknessSDF acts on the hollow shapes only.
  RigidBodyDesc sphere = shapeBody(CollisionObjectType::Sphere, Vector3(2, 9, 9));
  sphere.collision.thicknessSDF = Real(0.4);
  EXPECT_EQ(makeCollisionShape(sphere).distance(p), sdf::sphere(p, 2).distance);
  sphere.collision.type = CollisionObjectType::HollowSphere;
  EXPECT_EQ(makeCollisionShape(sphere).distance(p), sdf::hollowSphere(p, 2, Real(0.4)).distance);
  // No shape: nothing is ever inside.
  EXPECT_TRUE(std::isinf(makeCollisionShape(shapeBody(CollisionObjectType::None, Vector3::Ones()))
                             .distance(Vector3::Zero())));
}

TEST(CollisionShape, ParametersThatDescribeNoShapeAreErrorsNamingTheBody) {
  auto message = [](const RigidBodyDesc& body) {
    try {
      makeCollisionShape(body);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(shapeBody(CollisionObjectType::Sphere, Vector3(0, 1, 1))),
            "RigidBodies[3]: collisionObjectScale: the components collisionObjectType 1 uses "
            "must be > 0");
  EXPECT_EQ(message(shapeBody(CollisionObjectType::Torus, Vector3(1, -1, 1))),
            "RigidBodies[3]: collisionObjectScale: the components collisionObjectType 4 uses "
            "must be > 0");
  EXPECT_EQ(message(shapeBody(CollisionObjectType::SignedDistanceField, Vector3::Ones())),
            "RigidBodies[3]: collisionObjectType 5 (signed distance field) needs a mesh: a "
            "geometryFile or a collisionObjectFileName");
  RigidBodyDesc hollow = shapeBody(CollisionObjectType::HollowBox, Vector3::Ones());
  hollow.collision.thicknessSDF = -1;
  EXPECT_EQ(message(hollow), "RigidBodies[3]: thicknessSDF must be >= 0");
}

}  // namespace
}  // namespace pbd
