// The particles of one element of a particle constraint (an edge's bending stencil, a triangle,
// a tet): their rest positions read from the Scene by the builders, and their positions and
// inverse masses gathered for a solve and corrected after it. Shared by every family in
// constraints/; nothing allocates.
#pragma once

#include <array>
#include <cstddef>

#include "pbd/math/types.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"

namespace pbd {

/// The t = 0 positions of `indices` (global particle indices) from the Scene; false when every
/// one of them is static (mass 0), so that the element needs no constraint.
template <std::size_t N>
bool restPositions(const Scene& scene, const std::array<int, N>& indices,
                   std::array<Vector3, N>& rest) {
  bool anyDynamic = false;
  for (std::size_t i = 0; i < N; ++i) {
    const ParticleDesc& particle = scene.particles[std::size_t(indices[i])];
    rest[i] = particle.position;
    anyDynamic = anyDynamic || particle.mass > 0;
  }
  return anyDynamic;
}

/// The current positions and inverse masses of `indices`.
template <std::size_t N>
void gatherParticles(const ParticleStates& particles, const std::array<int, N>& indices,
                     std::array<Vector3, N>& positions, std::array<Real, N>& inverseMasses) {
  for (std::size_t i = 0; i < N; ++i) {
    positions[i] = particles.position[std::size_t(indices[i])];
    inverseMasses[i] = particles.inverseMass[std::size_t(indices[i])];
  }
}

/// Adds `corrections` to the positions of `indices`.
template <std::size_t N>
void applyCorrections(ParticleStates& particles, const std::array<int, N>& indices,
                      const std::array<Vector3, N>& corrections) {
  for (std::size_t i = 0; i < N; ++i)
    particles.position[std::size_t(indices[i])] += corrections[i];
}

}  // namespace pbd
