#include "pbd/collision/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <utility>

namespace pbd {
namespace {

constexpr int kLeafSize = 4;
constexpr int kMaxDepth = 64;

using Box = Eigen::AlignedBox<Real, 3>;

/// Merges vertices with bitwise-equal coordinates and renumbers the triangles.
void weld(const TriangleMesh& mesh, std::vector<Vector3>& vertices,
          std::vector<std::array<int, 3>>& triangles) {
  std::map<std::array<Real, 3>, int> indexOf;
  std::vector<int> remap(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vector3& v = mesh.vertices[i];
    const auto [it, inserted] = indexOf.emplace(std::array<Real, 3>{v.x(), v.y(), v.z()},
                                                static_cast<int>(vertices.size()));
    if (inserted) vertices.push_back(v);
    remap[i] = it->second;
  }
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    for (int index : t)
      if (index < 0 || static_cast<std::size_t>(index) >= mesh.vertices.size())
        throw std::invalid_argument("MeshDistance: triangle index out of range");
    triangles.push_back({remap[static_cast<std::size_t>(t[0])],
                         remap[static_cast<std::size_t>(t[1])],
                         remap[static_cast<std::size_t>(t[2])]});
  }
}

/// The interior angle at `corner` of the triangle (corner, next, previous).
Real cornerAngle(const Vector3& corner, const Vector3& next, const Vector3& previous) {
  const Vector3 a = next - corner, b = previous - corner;
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh) {
  weld(mesh, vertices_, triangles_);
  if (triangles_.empty()) throw std::invalid_argument("MeshDistance: the mesh has no triangles");
  computePseudonormals();
  buildTree();
}

void MeshDistance::computePseudonormals() {
  faceNormals_.resize(triangles_.size());
  vertexNormals_.assign(vertices_.size(), Vector3::Zero());
  std::map<std::pair<int, int>, Vector3> edgeSum;
  for (std::size_t f = 0; f < triangles_.size(); ++f) {
    const auto& t = triangles_[f];
    const Vector3 &a = vertices_[std::size_t(t[0])], &b = vertices_[std::size_t(t[1])],
                  &c = vertices_[std::size_t(t[2])];
    const Vector3 normal = (b - a).cross(c - a);
    const Real length = normal.norm();
    faceNormals_[f] = length > 0 ? Vector3(normal / length) : Vector3::Zero();
    const Vector3* corners[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k) {
      const Real angle = cornerAngle(*corners[k], *corners[(k + 1) % 3], *corners[(k + 2) % 3]);
      vertexNormals_[std::size_t(t[std::size_t(k)])] += angle * faceNormals_[f];
      const int u = t[std::size_t(k)], v = t[std::size_t((k + 1) % 3)];
      auto [it, inserted] =
          edgeSum.emplace(std::make_pair(std::min(u, v), std::max(u, v)), Vector3::Zero());
      it->second += faceNormals_[f];
    }
  }
  edgeNormals_.resize(triangles_.size());
  for (std::size_t f = 0; f < triangles_.size(); ++f) {
    const auto& t = triangles_[f];
    for (int k = 0; k < 3; ++k) {
      const int u = t[std::size_t(k)], v = t[std::size_t((k + 1) % 3)];
      edgeNormals_[f][std::size_t(k)] = edgeSum[{std::min(u, v), std::max(u, v)}];
    }
  }
}

void MeshDistance::buildTree() {
  const std::size_t n = triangles_.size();
  std::vector<Vector3> centroids(n);
  std::vector<Box> boxes(n);
  for (std::size_t f = 0; f < n; ++f) {
    Box box;
    box.setEmpty();
    for (int index : triangles_[f])
      box.extend(vertices_[std::size_t(index)]);
    boxes[f] = box;
    centroids[f] = box.center();
  }
  triangleOrder_.resize(n);
  for (std::size_t f = 0; f < n; ++f)
    triangleOrder_[f] = static_cast<int>(f);

  struct Pending {
    int node, first, count, depth;
  };
  nodes_.clear();
  nodes_.emplace_back();
  std::vector<Pending> pending{{0, 0, static_cast<int>(n), 0}};
  while (!pending.empty()) {
    const Pending p = pending.back();
    pending.pop_back();
    Box box;
    box.setEmpty();
    for (int i = p.first; i < p.first + p.count; ++i)
      box.extend(boxes[std::size_t(triangleOrder_[std::size_t(i)])]);
    nodes_[std::size_t(p.node)].box = box;
    nodes_[std::size_t(p.node)].firstTriangle = p.first;
    nodes_[std::size_t(p.node)].triangleCount = p.count;
    if (p.count <= kLeafSize || p.depth + 1 >= kMaxDepth) continue;
    Eigen::Index axis;
    box.sizes().maxCoeff(&axis);
    const auto begin = triangleOrder_.begin() + p.first;
    const auto middle = begin + p.count / 2;
    std::nth_element(begin, middle, begin + p.count, [&](int a, int b) {
      const Real ca = centroids[std::size_t(a)](axis), cb = centroids[std::size_t(b)](axis);
      return ca < cb || (ca == cb && a < b);
    });
    const int child = static_cast<int>(nodes_.size());
    nodes_[std::size_t(p.node)].child = child;
    nodes_.emplace_back();
    nodes_.emplace_back();
    pending.push_back({child, p.first, p.count / 2, p.depth + 1});
    pending.push_back({child + 1, p.first + p.count / 2, p.count - p.count / 2, p.depth + 1});
  }
}

void MeshDistance::testTriangle(int triangle, const Vector3& p, Query& best) const {
  const auto& t = triangles_[std::size_t(triangle)];
  const Vector3 &a = vertices_[std::size_t(t[0])], &b = vertices_[std::size_t(t[1])],
                &c = vertices_[std::size_t(t[2])];
  // Voronoi regions of the triangle (Ericson 2005, §5.1.5).
  const Vector3 ab = b - a, ac = c - a, ap = p - a;
  Vector3 q;
  Feature feature;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  const Vector3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  const Vector3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  const Real vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
  if (d1 <= 0 && d2 <= 0) {
    q = a, feature = Feature::VertexA;
  } else if (d3 >= 0 && d4 <= d3) {
    q = b, feature = Feature::VertexB;
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    q = a + (d1 / (d1 - d3)) * ab, feature = Feature::EdgeAB;
  } else if (d6 >= 0 && d5 <= d6) {
    q = c, feature = Feature::VertexC;
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    q = a + (d2 / (d2 - d6)) * ac, feature = Feature::EdgeCA;
  } else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    q = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), feature = Feature::EdgeBC;
  } else {
    const Real scale = 1 / (va + vb + vc);
    q = a + ab * (vb * scale) + ac * (vc * scale), feature = Feature::Face;
  }
  const Real squared = (p - q).squaredNorm();
  if (squared < best.squaredDistance) best = {squared, triangle, feature, q};
}

MeshDistance::Query MeshDistance::closest(const Vector3& point) const {
  Query best{std::numeric_limits<Real>::infinity()};
  std::array<int, kMaxDepth + 1> stack{};
  int top = 0;
  stack[0] = 0;
  while (top >= 0) {
    const Node& node = nodes_[std::size_t(stack[std::size_t(top--)])];
    if (node.box.squaredExteriorDistance(point) >= best.squaredDistance) continue;
    if (node.child < 0) {
      for (int i = node.firstTriangle; i < node.firstTriangle + node.triangleCount; ++i)
        testTriangle(triangleOrder_[std::size_t(i)], point, best);
      continue;
    }
    // Visit the nearer child first: push it last.
    const int left = node.child, right = node.child + 1;
    const bool leftNearer = nodes_[std::size_t(left)].box.squaredExteriorDistance(point) <=
                            nodes_[std::size_t(right)].box.squaredExteriorDistance(point);
    stack[std::size_t(++top)] = leftNearer ? right : left;
    stack[std::size_t(++top)] = leftNearer ? left : right;
  }
  return best;
}

Vector3 MeshDistance::pseudonormal(int triangle, Feature feature) const {
  const auto f = std::size_t(triangle);
  const auto& t = triangles_[f];
  switch (feature) {
    case Feature::Face:
      return faceNormals_[f];
    case Feature::EdgeAB:
      return edgeNormals_[f][0];
    case Feature::EdgeBC:
      return edgeNormals_[f][1];
    case Feature::EdgeCA:
      return edgeNormals_[f][2];
    case Feature::VertexA:
      return vertexNormals_[std::size_t(t[0])];
    case Feature::VertexB:
      return vertexNormals_[std::size_t(t[1])];
    case Feature::VertexC:
      return vertexNormals_[std::size_t(t[2])];
  }
  return faceNormals_[f];
}

Real MeshDistance::closestPoint(const Vector3& point, Vector3& closestOnSurface) const {
  const Query q = closest(point);
  closestOnSurface = q.point;
  return std::sqrt(q.squaredDistance);
}

int MeshDistance::closestTriangle(const Vector3& point, Vector3& closestOnSurface) const {
  const Query q = closest(point);
  closestOnSurface = q.point;
  return q.triangle;
}

Real MeshDistance::signedDistance(const Vector3& point) const {
  const Query q = closest(point);
  const Real distance = std::sqrt(q.squaredDistance);
  const Real side = (point - q.point).dot(pseudonormal(q.triangle, q.feature));
  return side < 0 ? -distance : distance;
}

}  // namespace pbd
