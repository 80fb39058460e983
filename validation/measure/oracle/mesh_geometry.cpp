#include "validation/measure/oracle/mesh_geometry.h"

#include <algorithm>
#include <cmath>

namespace pbdval {

using pbd::Real;
using pbd::Vector3;

namespace {

double boundingBoxDiagonal(const std::vector<Vector3>& vertices) {
  if (vertices.empty()) return 0;
  Vector3 lower = vertices.front(), upper = vertices.front();
  for (const Vector3& v : vertices) {
    lower = lower.cwiseMin(v);
    upper = upper.cwiseMax(v);
  }
  return (upper - lower).norm();
}

/// Solid angle subtended by triangle (a, b, c) seen from the origin, signed by orientation.
double solidAngle(const Vector3& a, const Vector3& b, const Vector3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
  return 2 * std::atan2(numerator, denominator);
}

}  // namespace

bool isConvex(const pbd::TriangleMesh& mesh, double relativeTolerance) {
  const double tolerance = relativeTolerance * boundingBoxDiagonal(mesh.vertices);
  for (const auto& triangle : mesh.triangles) {
    const Vector3& a = mesh.vertices[triangle[0]];
    const Vector3 normal = (mesh.vertices[triangle[1]] - a).cross(mesh.vertices[triangle[2]] - a);
    const double length = normal.norm();
    if (length <= tolerance * tolerance) continue;  // degenerate: no plane
    for (const Vector3& v : mesh.vertices) {
      if (normal.dot(v - a) > tolerance * length) return false;
    }
  }
  return true;
}

double windingNumber(const pbd::TriangleMesh& mesh, const Vector3& point) {
  double total = 0;
  for (const auto& triangle : mesh.triangles) {
    total += solidAngle(mesh.vertices[triangle[0]] - point, mesh.vertices[triangle[1]] - point,
                        mesh.vertices[triangle[2]] - point);
  }
  return total / (4 * M_PI);
}

std::vector<std::vector<int>> vertexNeighbours(const pbd::TriangleMesh& mesh) {
  std::vector<std::vector<int>> neighbours(mesh.vertices.size());
  for (const auto& triangle : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      neighbours[triangle[corner]].push_back(triangle[(corner + 1) % 3]);
      neighbours[triangle[corner]].push_back(triangle[(corner + 2) % 3]);
    }
  }
  for (std::vector<int>& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return neighbours;
}

double torusSignedDistance(const Vector3& point, double majorRadius, double minorRadius) {
  const double radial = std::hypot(double(point.x()), double(point.z())) - majorRadius;
  return std::hypot(radial, double(point.y())) - minorRadius;
}

double torusDeviation(const pbd::TriangleMesh& mesh, double majorRadius, double minorRadius) {
  double deviation = 0;
  const auto record = [&](const Vector3& p) {
    deviation = std::max(deviation, std::abs(torusSignedDistance(p, majorRadius, minorRadius)));
  };
  for (const Vector3& v : mesh.vertices) {
    record(v);
  }
  for (const auto& triangle : mesh.triangles) {
    const Vector3& a = mesh.vertices[triangle[0]];
    const Vector3& b = mesh.vertices[triangle[1]];
    const Vector3& c = mesh.vertices[triangle[2]];
    record((a + b + c) / Real(3));
    record((a + b) / Real(2));
    record((b + c) / Real(2));
    record((c + a) / Real(2));
  }
  return deviation;
}

}  // namespace pbdval
