// Checks shared by every reader of input files (scenes, meshes; validation's results,
// baselines and CSV): what a path is when it is not a regular file, a nesting limit for JSON,
// and message text that is always valid UTF-8 (docs/scene-format.md#limits).
#pragma once

#include <string>
#include <string_view>

namespace pbd {

/// The deepest nesting of arrays and objects a JSON input may have. The project's files nest
/// at most 5 levels; 64 leaves room and keeps a hostile file (100 000 '[') from costing time
/// and memory.
inline constexpr int kMaxJsonDepth = 64;

/// `bytes` made safe to print and to store in JSON: bytes that are not part of well-formed
/// UTF-8, and control characters, are written as \xNN (a backslash is kept as it is).
std::string printableText(std::string_view bytes);

/// Why `path` cannot be read as an input file, or "" when it is a readable regular file (after
/// following symbolic links). `what` names the file: with "scene", "the scene is a folder, not
/// a file", "the scene is a FIFO, not a regular file", "cannot open the scene file (No such file
/// or directory)".
std::string inputFileProblem(const std::string& path, const std::string& what);

}  // namespace pbd
