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
      for (int i = 0; i < nx; ++i) solid.mesh.vertices.push_back(Vector3(h * i, -h * j, h * k));
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
  for (const Vector3& v : solid.mesh.vertices) scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.solidSimulationMethod = solidMethod;
  return scene;
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
