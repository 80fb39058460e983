#include "pbd/model/mesh.h"

#include <algorithm>
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
  return edgesOf(triangles);
}

std::vector<std::array<int, 2>> uniqueEdges(const std::vector<std::array<int, 4>>& tetrahedra) {
  return edgesOf(tetrahedra);
}

std::vector<EdgeStencil> interiorEdgeStencils(const TriangleMesh& mesh) {
  // Edge (sorted) → its rank of first appearance and the opposite vertices of its triangles.
  std::map<std::pair<int, int>, std::vector<int>> opposites;
  std::vector<std::pair<int, int>> order;
  for (const auto& t : mesh.triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      auto [it, inserted] = opposites.try_emplace(key);
      if (inserted) order.push_back(key);
      it->second.push_back(t[(k + 2) % 3]);
    }
  std::vector<EdgeStencil> stencils;
  for (const auto& key : order) {
    const std::vector<int>& opposite = opposites[key];
    if (opposite.size() == 2) stencils.push_back({{key.first, key.second}, {opposite[0], opposite[1]}});
  }
  return stencils;
}

}  // namespace pbd
