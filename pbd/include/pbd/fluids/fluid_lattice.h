// The lattice a fluid block is filled with (fluids/fluid_model.h, fluidBlockParticles): its
// size per axis, so that the scene reader can refuse a block of too many particles before
// generating them.
#pragma once

#include <algorithm>
#include <array>

#include "pbd/math/types.h"
#include "pbd/model/scene.h"

namespace pbd {

/// Relative slack when counting lattice cells: an extent within this fraction below a whole
/// number of spacings still holds that number. 1e-9 in double; in float the extent and 2r each
/// carry round-off of a few ε (0.5 / (2 · 0.025) is 9.99999985 in float), so 1024 ε = 1.2e-4
/// there, which tolerates coordinates up to ~1000 × the extent.
inline constexpr double kLatticeSlack = std::max(1e-9, 1024 * double(kEpsilon));

/// Particles per axis in `block` at spacing 2r: floor(extent / 2r) (to kLatticeSlack
/// relative), 0 for an extent below 2r; capped at 2^30 per axis.
std::array<long long, 3> fluidBlockLatticeSize(const AxisAlignedBox& block, Real particleRadius);

}  // namespace pbd
