// Mesh file readers: Wavefront OBJ (triangles; polygons are fan-triangulated) and TetGen
// .node/.ele. They throw SceneError naming the file and line on malformed input.
#pragma once

#include <string>

#include "pbd/model/mesh.h"

namespace pbd {

TriangleMesh loadObj(const std::string& path);
TetMesh loadTetGen(const std::string& nodePath, const std::string& elePath);

/// The same readers on the files' text; the names are used in messages.
TriangleMesh parseObj(const std::string& text, const std::string& sourceName);
TetMesh parseTetGen(const std::string& nodeText, const std::string& eleText,
                    const std::string& nodeName, const std::string& eleName);

}  // namespace pbd
