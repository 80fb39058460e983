// Surface meshes written as files (the seed's exportOBJ / exportPLY): Wavefront OBJ with the
// shortest text that reads back to the same doubles, or binary little-endian PLY with float64
// coordinates and int32 indices (both read back by mesh_loader.h).
#pragma once

#include <array>
#include <ostream>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

void writeObj(std::ostream& out, const std::vector<Vector3>& vertices,
              const std::vector<std::array<int, 3>>& triangles);
void writePly(std::ostream& out, const std::vector<Vector3>& vertices,
              const std::vector<std::array<int, 3>>& triangles);

}  // namespace pbd
