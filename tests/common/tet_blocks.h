// Test scenes of tet solids shared by the solid-constraint tests: a block of nx × ny × nz
// vertices 0.25 m apart (each cube split into five tets), hanging downwards from y = 0, every
// vertex a 1 kg particle; and the largest edge strain of its tets in a world.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "common/edge_stretch.h"
#include "pbd/model/world.h"

namespace pbd::test {

inline Scene tetBlock(int nx, int ny, int nz, int solidMethod) {
  Scene scene;
  TetModelDesc solid;
  const auto index = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  const Real h = Real(0.25);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        solid.mesh.vertices.push_back(Vector3(h * i, -h * j, h * k));
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i) {
        std::array<int, 8> v;
        for (int c = 0; c < 8; ++c)
          v[std::size_t(c)] = index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        for (const std::array<int, 4>& t : std::vector<std::array<int, 4>>{
                 {0, 1, 2, 4}, {1, 3, 2, 7}, {1, 4, 5, 7}, {2, 4, 7, 6}, {1, 2, 4, 7}})
          solid.mesh.tetrahedra.push_back({v[std::size_t(t[0])], v[std::size_t(t[1])],
                                           v[std::size_t(t[2])], v[std::size_t(t[3])]});
      }
  scene.tetModels.push_back(solid);
  for (const Vector3& v : solid.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.solidSimulationMethod = solidMethod;
  return scene;
}

/// Appends a cube of cells³ cubic cells (edge `spacing`, lower corner `corner`) as a tet model
/// of 1 kg particles: every cell split into the six tets around its main diagonal (Kuhn), so
/// that neighbouring cells share their face diagonals (a conforming mesh, whose boundary is
/// the cube's surface), each tet positively oriented. Returns the model's index.
inline int appendTetCube(Scene& scene, const Vector3& corner, int cells, Real spacing) {
  TetModelDesc solid;
  const int n = cells + 1;
  const auto index = [&](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        solid.mesh.vertices.push_back(corner + spacing * Vector3(Real(i), Real(j), Real(k)));
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i) {
        std::array<int, 8> v;
        for (int c = 0; c < 8; ++c)
          v[std::size_t(c)] = index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        for (const std::array<int, 4>& t : std::vector<std::array<int, 4>>{{0, 1, 3, 7},
                                                                           {0, 1, 5, 7},
                                                                           {0, 2, 3, 7},
                                                                           {0, 2, 6, 7},
                                                                           {0, 4, 5, 7},
                                                                           {0, 4, 6, 7}}) {
          std::array<int, 4> tet{v[std::size_t(t[0])], v[std::size_t(t[1])], v[std::size_t(t[2])],
                                 v[std::size_t(t[3])]};
          const auto& p = solid.mesh.vertices;
          const Vector3 a = p[std::size_t(tet[1])] - p[std::size_t(tet[0])];
          const Vector3 b = p[std::size_t(tet[2])] - p[std::size_t(tet[0])];
          const Vector3 c = p[std::size_t(tet[3])] - p[std::size_t(tet[0])];
          if (a.cross(b).dot(c) < 0) std::swap(tet[2], tet[3]);
          solid.mesh.tetrahedra.push_back(tet);
        }
      }
  solid.id = static_cast<int>(scene.tetModels.size());
  solid.firstParticle = static_cast<int>(scene.particles.size());
  for (const Vector3& v : solid.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.tetModels.push_back(solid);
  return static_cast<int>(scene.tetModels.size()) - 1;
}

/// A 2 × 5 × 2 column (20 tets) of `solidMethod` hanging from its static top face for 1 s with
/// `iterations`: its largest edge strain over the run; fails the test (gtest ASSERTs in the
/// caller's view: returns a negative value) when a particle is not finite or leaves the ball of
/// 2 m around the top.
inline Real hangingColumnStretch(int solidMethod, int iterations) {
  Scene scene = tetBlock(2, 5, 2, solidMethod);
  scene.simulation.maxIterations = iterations;
  for (ParticleDesc& p : scene.particles)
    if (p.position.y() == 0) p.mass = 0;
  World world = buildWorld(scene);
  Real worst = 0;
  while (world.time < 1) {
    world.step();
    for (const Vector3& p : world.bodies.particles.position)
      if (!p.allFinite() || !(p.norm() < 2)) return -1;
    worst = std::max(worst, maxTetEdgeStretch(world, scene));
  }
  return worst;
}

}  // namespace pbd::test
