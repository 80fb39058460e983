#include "pbd/model/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace pbd {
namespace {

template <std::size_t N>
std::vector<std::array<int, 2>> edgesOf(const std::vector<std::array<int, N>>& elements) {
  std::set<std::pair<int, int>> seen;
  std::vector<std::array<int, 2>> edges;
  for (const auto& element : elements)
    for (std::size_t i = 0; i < N; ++i)
      for (std::size_t j = i + 1; j < N; ++j) {
        const int a = element[i], b = element[j];
        if (seen.insert({std::min(a, b), std::max(a, b)}).second) edges.push_back({a, b});
      }
  return edges;
}

}  // namespace

std::vector<std::array<int, 2>> uniqueEdges(const std::vector<std::array<int, 3>>& triangles) {
  // The seed's IndexedFaceMesh::buildNeighbors: per triangle the sides (t₀, t₁), (t₁, t₂),
  // (t₂, t₀), a side's first appearance fixing its orientation.
  std::set<std::pair<int, int>> seen;
  std::vector<std::array<int, 2>> edges;
  for (const auto& t : triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      if (seen.insert({std::min(a, b), std::max(a, b)}).second) edges.push_back({a, b});
    }
  return edges;
}

std::vector<std::array<int, 2>> uniqueEdges(const std::vector<std::array<int, 4>>& tetrahedra) {
  return edgesOf(tetrahedra);
}

std::vector<EdgeStencil> interiorEdgeStencils(const TriangleMesh& mesh) {
  // Edge (sorted) → its rank of first appearance, its orientation then (the seed's
  // IndexedFaceMesh::buildNeighbors keeps the first triangle's (t_k, t_k+1)) and the opposite
  // vertices of its triangles.
  std::map<std::pair<int, int>, std::vector<int>> opposites;
  std::vector<std::pair<int, int>> order;  // as first seen
  for (const auto& t : mesh.triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      auto [it, inserted] = opposites.try_emplace(key);
      if (inserted) order.push_back({a, b});
      it->second.push_back(t[(k + 2) % 3]);
    }
  std::vector<EdgeStencil> stencils;
  for (const auto& edge : order) {
    const std::vector<int>& opposite =
        opposites[{std::min(edge.first, edge.second), std::max(edge.first, edge.second)}];
    if (opposite.size() == 2)
      stencils.push_back({{edge.first, edge.second}, {opposite[0], opposite[1]}});
  }
  return stencils;
}

std::vector<std::array<int, 3>> boundaryFaces(const TetMesh& mesh) {
  // The faces of a tet (x₀, x₁, x₂, x₃) of positive volume, each turned away from the vertex it
  // lacks: (1,2,3), (0,3,2), (0,1,3), (0,2,1); a tet of negative volume flips them.
  static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  std::map<std::array<int, 3>, int> count;
  std::vector<std::array<int, 3>> faces;
  for (const auto& t : mesh.tetrahedra) {
    const Vector3& x0 = mesh.vertices[std::size_t(t[0])];
    const Real volume = (mesh.vertices[std::size_t(t[1])] - x0)
                            .cross(mesh.vertices[std::size_t(t[2])] - x0)
                            .dot(mesh.vertices[std::size_t(t[3])] - x0);
    for (const auto& f : kFaces) {
      std::array<int, 3> face = {t[std::size_t(f[0])], t[std::size_t(f[1])], t[std::size_t(f[2])]};
      if (volume < 0) std::swap(face[1], face[2]);
      std::array<int, 3> key = face;
      std::sort(key.begin(), key.end());
      if (++count[key] == 1) faces.push_back(face);
    }
  }
  std::vector<std::array<int, 3>> boundary;
  for (const auto& face : faces) {
    std::array<int, 3> key = face;
    std::sort(key.begin(), key.end());
    if (count[key] == 1) boundary.push_back(face);
  }
  return boundary;
}

bool tetBarycentric(const std::array<Vector3, 4>& tet, const Vector3& point,
                    std::array<Real, 4>& weights) {
  Matrix3 edges;
  edges.col(0) = tet[1] - tet[0];
  edges.col(1) = tet[2] - tet[0];
  edges.col(2) = tet[3] - tet[0];
  const Real determinant = edges.determinant();
  const Real scale = edges.colwise().norm().prod();
  if (!(std::abs(determinant) > kEpsilon * scale)) return false;
  const Vector3 local = edges.inverse() * (point - tet[0]);
  weights = {1 - local.sum(), local.x(), local.y(), local.z()};
  return true;
}

std::vector<BarycentricAttachment> attachToTets(const TetMesh& mesh,
                                                const std::vector<Vector3>& points) {
  std::vector<BarycentricAttachment> attachments;
  attachments.reserve(points.size());
  for (const Vector3& point : points) {
    BarycentricAttachment best;
    Real bestInside = -std::numeric_limits<Real>::infinity();
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t) {
      std::array<Vector3, 4> corners;
      for (std::size_t i = 0; i < 4; ++i)
        corners[i] = mesh.vertices[std::size_t(mesh.tetrahedra[t][i])];
      std::array<Real, 4> weights;
      if (!tetBarycentric(corners, point, weights)) continue;
      const Real inside = *std::min_element(weights.begin(), weights.end());
      if (inside > bestInside) {
        bestInside = inside;
        best = {int(t), weights};
        if (inside >= 0) break;  // contained: the first containing tet
      }
    }
    if (best.tet < 0) return {};
    attachments.push_back(best);
  }
  return attachments;
}

TetMesh tetLattice(int nx, int ny, int nz, const Vector3& step, const Vector3& origin) {
  TetMesh mesh;
  const auto index = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        mesh.vertices.push_back(
            origin + Vector3(Real(i) * step.x(), Real(j) * step.y(), Real(k) * step.z()));
  constexpr std::array<std::array<int, 3>, 6> kAxisOrders = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        for (const std::array<int, 3>& order : kAxisOrders) {
          std::array<int, 3> corner = {0, 0, 0};
          std::array<int, 4> tet;
          tet[0] = index(i, j, k);
          for (std::size_t axis = 0; axis < 3; ++axis) {
            corner[std::size_t(order[axis])] = 1;
            tet[axis + 1] = index(i + corner[0], j + corner[1], k + corner[2]);
          }
          const auto at = [&](std::size_t v) { return mesh.vertices[std::size_t(tet[v])]; };
          if ((at(1) - at(0)).cross(at(2) - at(0)).dot(at(3) - at(0)) < 0)
            std::swap(tet[2], tet[3]);
          mesh.tetrahedra.push_back(tet);
        }
  return mesh;
}

TriangleMesh triangleGrid(int nx, int nz, Real spacing, const Vector3& origin) {
  TriangleMesh mesh;
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i)
      mesh.vertices.push_back(origin + spacing * Vector3(Real(i), 0, Real(k)));
  for (int k = 0; k + 1 < nz; ++k)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = k * nx + i, b = a + 1, c = a + nx, d = c + 1;
      // Counter-clockwise seen from +y: (x, z) → normal (b − a) × (c − a) = x̂ × ẑ = −ŷ, so
      // the triangles are listed a, c, b and b, c, d.
      mesh.triangles.push_back({a, c, b});
      mesh.triangles.push_back({b, c, d});
    }
  return mesh;
}

}  // namespace pbd
