// Mesh file readers: Wavefront OBJ (triangles; polygons are fan-triangulated) and TetGen
// .node/.ele. They throw SceneError naming the file and line on malformed input.
#pragma once

#include <string>

#include "pbd/model/mesh.h"

namespace pbd {

TriangleMesh loadObj(const std::string& path);
TetMesh loadTetGen(const std::string& nodePath, const std::string& elePath);

}  // namespace pbd
