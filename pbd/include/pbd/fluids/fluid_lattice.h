// The lattice a fluid block is filled with (fluids/fluid_model.h, fluidBlockParticles): its
// size per axis, so that the scene reader can refuse a block of too many particles before
// generating them.
#pragma once

#include <array>

#include "pbd/math/types.h"
#include "pbd/model/scene.h"

namespace pbd {

/// Particles per axis in `block` at spacing 2r: floor(extent / 2r) (to 1e-9 relative), 0 for
/// an extent below 2r; capped at 2^30 per axis.
std::array<long long, 3> fluidBlockLatticeSize(const AxisAlignedBox& block, Real particleRadius);

}  // namespace pbd
