// The largest edge strain |ℓ/ℓ₀ − 1| of a deformable model in a world against its rest state in
// the Scene, shared by the particle-constraint tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "pbd/model/world.h"

namespace pbd::test {

/// max |ℓ/ℓ₀ − 1| over the edges of the first tet model's tets.
inline Real maxTetEdgeStretch(const World& world, const Scene& scene) {
  Real worst = 0;
  for (const auto& t : scene.tetModels[0].mesh.tetrahedra)
    for (std::size_t a = 0; a < 4; ++a)
      for (std::size_t b = a + 1; b < 4; ++b) {
        const auto i = std::size_t(t[a]), j = std::size_t(t[b]);
        const Real rest = (scene.particles[i].position - scene.particles[j].position).norm();
        const Real now =
            (world.bodies.particles.position[i] - world.bodies.particles.position[j]).norm();
        worst = std::max(worst, std::abs(now / rest - 1));
      }
  return worst;
}

/// max |ℓ/ℓ₀ − 1| over the edges of the first triangle model's triangles.
inline Real maxTriangleEdgeStretch(const World& world, const Scene& scene) {
  Real worst = 0;
  for (const std::array<int, 3>& t : scene.triangleModels[0].mesh.triangles)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto a = std::size_t(t[k]), b = std::size_t(t[(k + 1) % 3]);
      const Real rest = (scene.particles[a].position - scene.particles[b].position).norm();
      const Real now =
          (world.bodies.particles.position[a] - world.bodies.particles.position[b]).norm();
      worst = std::max(worst, std::abs(now / rest - 1));
    }
  return worst;
}

}  // namespace pbd::test
