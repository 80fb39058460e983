// Reader of Discregrid's binary grid files (`.csdf`, a CubicLagrangeDiscreteGrid saved by
// Discregrid's `save`, e.g. by its GenerateSDF tool), the grids PositionBasedDynamics reads for
// a `collisionObjectFileName` of collisionObjectType 5.
//
// The layout (native byte order, no padding; Discregrid writes each value's bytes as they are in
// memory, x86-64: little-endian, 8-byte size_t):
//   domain      6 × f64  (min x, y, z, then max x, y, z)
//   resolution  3 × u32  (cells per axis n)
//   cell size   3 × f64, its inverse 3 × f64
//   cell count  u64 (= n_x n_y n_z), field count u64
//   nodes       u64 field count, then per field: u64 count, f64 values
//   cells       u64 field count, then per field: u64 count, 32 × u32 node indices per cell
//   cell map    u64 field count, then per field: u64 count (= cell count), u32 per cell
// A cell's 32 nodes are its 8 corners (bit 0: +x, bit 1: +y, bit 2: +z), then the two nodes
// (at 1/3, then 2/3) of its 4 edges along x, along y, along z; the cell map sends a cell (x
// fastest) to its row of the cells table (Discregrid marks a discarded cell with 2³² − 1).
// The reader fills pbdval's own node layout (DistanceGrid, cubicLagrange) through the cells
// table, so it depends on Discregrid's local node order only, not on its global numbering.
//
// Field 0 is the distance (the seed interpolates field 0). Truncated, oversized or inconsistent
// files (a count that does not fit the file, a node index out of range, a shared node given two
// values, trailing bytes) and grids pbdval cannot represent (discarded cells or nodes) throw
// SceneError naming the file and the byte offset.
#pragma once

#include <string>

#include "pbd/collision/distance_grid.h"

namespace pbd {

/// The distance field (field 0) of the Discregrid grid file at `path`, as a cubic Lagrange
/// DistanceGrid over the file's domain and resolution.
DistanceGrid readDiscregridGrid(const std::string& path);

/// The same on the file's bytes; `sourceName` is used in messages.
DistanceGrid parseDiscregridGrid(const std::string& bytes, const std::string& sourceName);

}  // namespace pbd
