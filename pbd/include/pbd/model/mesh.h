// Indexed meshes as loaded from files (OBJ surfaces, TetGen volumes).
#pragma once

#include <array>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

/// A triangle surface. Triangles are counter-clockwise seen from outside for closed meshes.
struct TriangleMesh {
  std::vector<Vector3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// A tetrahedral volume mesh (TetGen .node/.ele), zero-based indices.
struct TetMesh {
  std::vector<Vector3> vertices;
  std::vector<std::array<int, 4>> tetrahedra;
};

}  // namespace pbd
