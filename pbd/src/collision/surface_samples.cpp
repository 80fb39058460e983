#include "pbd/collision/surface_samples.h"

#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace pbd {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The generation below follows scripts/make-models step by step, in double precision, so the
// points equal the models' vertices bit for bit (then converted to Real).
using Point = std::array<double, 3>;

Point normalized(const Point& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

std::vector<Vector3> toReal(const std::vector<Point>& points) {
  std::vector<Vector3> out;
  out.reserve(points.size());
  for (const Point& p : points)
    out.emplace_back(static_cast<Real>(p[0]), static_cast<Real>(p[1]), static_cast<Real>(p[2]));
  return out;
}

}  // namespace

std::vector<Vector3> unitCubeVertices() {
  std::vector<Vector3> points;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        points.emplace_back(Real(x) - Real(0.5), Real(y) - Real(0.5), Real(z) - Real(0.5));
  return points;
}

std::vector<Vector3> unitIcosphereVertices(int subdivisions) {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Point> vertices;
  for (const Point& corner : std::vector<Point>{{-1, phi, 0},
                                                {1, phi, 0},
                                                {-1, -phi, 0},
                                                {1, -phi, 0},
                                                {0, -1, phi},
                                                {0, 1, phi},
                                                {0, -1, -phi},
                                                {0, 1, -phi},
                                                {phi, 0, -1},
                                                {phi, 0, 1},
                                                {-phi, 0, -1},
                                                {-phi, 0, 1}})
    vertices.push_back(normalized(corner));
  std::vector<std::array<int, 3>> triangles = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      const Point &va = vertices[std::size_t(a)], &vb = vertices[std::size_t(b)];
      vertices.push_back(
          normalized({(va[0] + vb[0]) / 2, (va[1] + vb[1]) / 2, (va[2] + vb[2]) / 2}));
      midpoints[key] = static_cast<int>(vertices.size()) - 1;
      return midpoints[key];
    };
    std::vector<std::array<int, 3>> refined;
    for (const auto& [a, b, c] : triangles) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      refined.push_back({a, ab, ca});
      refined.push_back({b, bc, ab});
      refined.push_back({c, ca, bc});
      refined.push_back({ab, bc, ca});
    }
    triangles = std::move(refined);
  }
  return toReal(vertices);
}

std::vector<Vector3> unitCylinderVertices(int segments) {
  std::vector<Point> vertices;
  for (const double y : {-0.5, 0.5})
    for (int k = 0; k < segments; ++k) {
      const double angle = 2 * kPi * k / segments;
      vertices.push_back({std::cos(angle), y, std::sin(angle)});
    }
  vertices.push_back({0.0, -0.5, 0.0});
  vertices.push_back({0.0, 0.5, 0.0});
  return toReal(vertices);
}

std::vector<Vector3> surfaceSamples(const RigidBodyDesc& body) {
  if (body.mesh) return body.mesh->vertices;
  const Vector3& size = body.collision.scale;
  std::vector<Vector3> points;
  Vector3 scale = Vector3::Ones();
  switch (body.collision.type) {
    case CollisionObjectType::Box:
      points = unitCubeVertices();
      scale = size;
      break;
    case CollisionObjectType::Sphere:
      points = unitIcosphereVertices();
      scale = Vector3::Constant(size.x());
      break;
    case CollisionObjectType::Cylinder:
      points = unitCylinderVertices();
      scale = Vector3(size.x(), size.y(), size.x());
      break;
    default:
      break;
  }
  for (Vector3& p : points)
    p = p.cwiseProduct(scale);
  return points;
}

}  // namespace pbd
