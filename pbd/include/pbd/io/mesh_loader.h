// Mesh file readers: Wavefront OBJ and Stanford PLY (ASCII and binary of either byte order;
// polygons of both are fan-triangulated) and TetGen .node/.ele. They throw SceneError naming the
// file and the line, element or item on malformed input.
#pragma once

#include <string>

#include "pbd/model/mesh.h"

namespace pbd {

TriangleMesh loadObj(const std::string& path, ObjPrecision precision = ObjPrecision::Double);
TriangleMesh loadPly(const std::string& path);
/// OBJ or PLY by the extension (case-insensitive): ".ply" is PLY, anything else OBJ.
/// OBJ coordinates are read with `objPrecision`; PLY's as the file stores them.
TriangleMesh loadSurfaceMesh(const std::string& path,
                             ObjPrecision objPrecision = ObjPrecision::Double);
TetMesh loadTetGen(const std::string& nodePath, const std::string& elePath);

/// The same readers on the files' text; the names are used in messages.
TriangleMesh parseObj(const std::string& text, const std::string& sourceName,
                      ObjPrecision precision = ObjPrecision::Double);
TriangleMesh parsePly(const std::string& bytes, const std::string& sourceName);
TetMesh parseTetGen(const std::string& nodeText, const std::string& eleText,
                    const std::string& nodeName, const std::string& eleName);

}  // namespace pbd
