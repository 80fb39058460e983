// How a grid signed distance field (collisionObjectType 5) is interpolated between its nodes:
// `Simulation.distanceGrid` (an extension of the seed's format; docs/contacts.md#grid-sdfs).
// The formulas are in pbd/collision/distance_grid.h.
#pragma once

#include <cstdint>

namespace pbd {

enum class GridInterpolation : std::uint8_t {
  /// The seed's (Discregrid's cubic Lagrange grid): 32-node serendipity cells, C⁰, over the
  /// collision mesh's box padded by 0.1 (in the mesh's own units) on every side.
  CubicLagrange,
  /// pbdval's tricubic Catmull-Rom grid: C¹, over the mesh's box padded by 10 % of its size
  /// (at least twice the contact tolerance).
  CatmullRom,
};

/// "cubicLagrange" or "catmullRom", the names the scene format uses.
const char* gridInterpolationName(GridInterpolation interpolation);

}  // namespace pbd
