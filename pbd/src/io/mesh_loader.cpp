#include "pbd/io/mesh_loader.h"

#include <array>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "pbd/io/input_checks.h"
#include "pbd/io/number_text.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

using Tokens = std::vector<std::string>;

// A text file read line by line: '#' starts a comment, blank lines are skipped, and every
// error names the file and the current line.
class TokenizedFile {
 public:
  /// Reads `text`; `path` names it in messages.
  TokenizedFile(const std::string& text, const std::string& path) : path_(path), stream_(text) {}

  /// The tokens of the next non-empty line; false at the end of the file.
  bool next(Tokens& tokens) {
    std::string line;
    while (std::getline(stream_, line)) {
      ++lineNumber_;
      const std::size_t comment = line.find('#');
      if (comment != std::string::npos) line.erase(comment);
      std::istringstream words(line);
      tokens.clear();
      for (std::string word; words >> word;)
        tokens.push_back(word);
      if (!tokens.empty()) return true;
    }
    return false;
  }

  [[noreturn]] void fail(const std::string& message) const {
    failFile("line " + std::to_string(lineNumber_) + ": " + message);
  }
  [[noreturn]] void failFile(const std::string& message) const {
    throw SceneError(SceneDiagnostic{path_, "", message});
  }

  Real real(const std::string& token) const {
    const std::optional<double> value = parseReal(token);
    if (!value || !std::isfinite(static_cast<Real>(*value)))
      fail("expected a finite number, got '" + token + "'");
    return static_cast<Real>(*value);
  }

  /// A finite number rounded once to single precision, as `stof` reads it.
  Real single(const std::string& token) const {
    real(token);  // the same checks and messages as a full-precision number
    const char* begin = token.data();
    if (*begin == '+') ++begin;
    float value = 0;
    const auto result = std::from_chars(begin, token.data() + token.size(), value);
    if (result.ec != std::errc() || !std::isfinite(value))
      fail("expected a finite single-precision number, got '" + token + "'");
    return static_cast<Real>(value);
  }

  int integer(const std::string& token) const {
    const std::optional<std::int64_t> value = parseInteger(token);
    if (!value || *value > INT_MAX || *value < INT_MIN)
      fail("expected an integer, got '" + token + "'");
    return static_cast<int>(*value);
  }

 private:
  std::string path_;
  std::istringstream stream_;
  int lineNumber_ = 0;
};

// ---- OBJ ------------------------------------------------------------------------------------

bool isIgnoredObjStatement(const std::string& keyword) {
  static const char* const kIgnored[] = {"vt", "vn", "vp", "o", "g", "s", "usemtl", "mtllib"};
  for (const char* ignored : kIgnored)
    if (keyword == ignored) return true;
  return false;
}

Vector3 readObjVertex(const TokenizedFile& file, const Tokens& tokens, ObjPrecision precision) {
  // "v x y z [w]"; some exporters append r g b, which are numbers as well and ignored.
  if (tokens.size() < 4 || tokens.size() > 8) file.fail("expected 'v x y z [w]'");
  for (std::size_t i = 4; i < tokens.size(); ++i)
    file.real(tokens[i]);
  if (precision == ObjPrecision::Single)
    return Vector3(file.single(tokens[1]), file.single(tokens[2]), file.single(tokens[3]));
  return Vector3(file.real(tokens[1]), file.real(tokens[2]), file.real(tokens[3]));
}

// One vertex reference of a face: "i", "i/t", "i//n" or "i/t/n"; negative i counts back from
// the last vertex defined so far. Returns the zero-based vertex index.
int readObjVertexReference(const TokenizedFile& file, const std::string& reference,
                           std::size_t vertexCount) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (std::size_t slash; (slash = reference.find('/', start)) != std::string::npos;) {
    parts.push_back(reference.substr(start, slash - start));
    start = slash + 1;
  }
  parts.push_back(reference.substr(start));
  const bool validForm = parts.size() <= 3 && !parts[0].empty() &&
                         !(parts.size() == 2 && parts[1].empty()) &&
                         !(parts.size() == 3 && parts[2].empty());
  if (!validForm) file.fail("bad face vertex '" + reference + "' (expected i, i/t, i//n or i/t/n)");
  for (std::size_t i = 1; i < parts.size(); ++i)
    if (!parts[i].empty()) file.integer(parts[i]);

  const int given = file.integer(parts[0]);
  const long count = static_cast<long>(vertexCount);
  const long index = given > 0 ? given - 1L : count + given;
  if (given == 0 || index < 0 || index >= count) {
    file.fail("vertex index " + std::to_string(given) + " out of range (" +
              std::to_string(vertexCount) + " vertices defined so far)");
  }
  return static_cast<int>(index);
}

void appendObjFace(const TokenizedFile& file, const Tokens& tokens, TriangleMesh& mesh) {
  if (tokens.size() < 4) file.fail("a face needs at least 3 vertices");
  std::vector<int> polygon;
  for (std::size_t i = 1; i < tokens.size(); ++i)
    polygon.push_back(readObjVertexReference(file, tokens[i], mesh.vertices.size()));
  for (std::size_t k = 1; k + 1 < polygon.size(); ++k)  // fan around the first vertex
    mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
}

// ---- TetGen ---------------------------------------------------------------------------------

// The first index of a TetGen list decides whether the file counts from 0 or from 1.
int detectBase(const TokenizedFile& file, int firstIndex) {
  if (firstIndex != 0 && firstIndex != 1) {
    file.fail("the first index must be 0 or 1, got " + std::to_string(firstIndex));
  }
  return firstIndex;
}

void expectConsecutiveIndex(const TokenizedFile& file, int index, int base, std::size_t position) {
  const long expected = base + static_cast<long>(position);
  if (index != expected) {
    file.fail("expected index " + std::to_string(expected) + ", got " + std::to_string(index));
  }
}

void expectEnd(TokenizedFile& file, std::size_t count, const char* what) {
  Tokens tokens;
  if (file.next(tokens)) {
    file.fail("unexpected data after the " + std::to_string(count) + " " + what +
              " announced in the header");
  }
}

/// The whole file; a folder, device or FIFO is refused with what it is.
std::string readWholeFile(const std::string& path) {
  const std::string problem = inputFileProblem(path, "mesh");
  if (!problem.empty()) throw SceneError(SceneDiagnostic{path, "", problem});
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw SceneError(SceneDiagnostic{path, "", "cannot open file"});
  std::ostringstream text;
  text << stream.rdbuf();
  return text.str();
}

// Reads a .node file; returns the index base (0 or 1).
int readTetGenNodes(const std::string& text, const std::string& path,
                    std::vector<Vector3>& vertices) {
  TokenizedFile file(text, path);
  Tokens tokens;
  if (!file.next(tokens)) file.failFile("empty file (expected the header 'n 3 nattr nmarkers')");
  if (tokens.size() > 4) file.fail("expected the header 'n 3 nattr nmarkers'");
  const int count = file.integer(tokens[0]);
  const int dimension = tokens.size() > 1 ? file.integer(tokens[1]) : 3;
  const int attributes = tokens.size() > 2 ? file.integer(tokens[2]) : 0;
  const int markers = tokens.size() > 3 ? file.integer(tokens[3]) : 0;
  if (count <= 0) file.fail("expected a positive number of nodes, got " + tokens[0]);
  if (dimension != 3) file.fail("expected dimension 3, got " + tokens[1]);
  if (attributes < 0) file.fail("expected a non-negative number of attributes");
  if (markers != 0 && markers != 1) file.fail("expected 0 or 1 boundary markers");

  const std::size_t fields = 4 + static_cast<std::size_t>(attributes + markers);
  int base = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
    if (!file.next(tokens)) {
      file.failFile("expected " + std::to_string(count) + " nodes, found " + std::to_string(i));
    }
    if (tokens.size() != fields) {
      file.fail("expected " + std::to_string(fields) + " values (index x y z, " +
                std::to_string(attributes) + " attributes, " + std::to_string(markers) +
                " markers), got " + std::to_string(tokens.size()));
    }
    const int index = file.integer(tokens[0]);
    if (i == 0) base = detectBase(file, index);
    expectConsecutiveIndex(file, index, base, i);
    vertices.emplace_back(file.real(tokens[1]), file.real(tokens[2]), file.real(tokens[3]));
    for (std::size_t k = 4; k < fields; ++k)
      file.real(tokens[k]);
  }
  expectEnd(file, static_cast<std::size_t>(count), "nodes");
  return base;
}

void readTetGenElements(const std::string& text, const std::string& path, int nodeBase,
                        TetMesh& mesh) {
  TokenizedFile file(text, path);
  Tokens tokens;
  if (!file.next(tokens)) file.failFile("empty file (expected the header 'n 4 nattr')");
  if (tokens.size() > 3) file.fail("expected the header 'n 4 nattr'");
  const int count = file.integer(tokens[0]);
  const int nodesPerTet = tokens.size() > 1 ? file.integer(tokens[1]) : 4;
  const int attributes = tokens.size() > 2 ? file.integer(tokens[2]) : 0;
  if (count <= 0) file.fail("expected a positive number of tetrahedra, got " + tokens[0]);
  if (nodesPerTet != 4) {
    file.fail("only linear tetrahedra (4 nodes) are supported, got " + tokens[1]);
  }
  if (attributes < 0) file.fail("expected a non-negative number of attributes");

  const std::size_t fields = 5 + static_cast<std::size_t>(attributes);
  const long vertexCount = static_cast<long>(mesh.vertices.size());
  int base = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
    if (!file.next(tokens)) {
      file.failFile("expected " + std::to_string(count) + " tetrahedra, found " +
                    std::to_string(i));
    }
    if (tokens.size() != fields) {
      file.fail("expected " + std::to_string(fields) + " values (index a b c d, " +
                std::to_string(attributes) + " attributes), got " + std::to_string(tokens.size()));
    }
    const int index = file.integer(tokens[0]);
    if (i == 0) base = detectBase(file, index);
    expectConsecutiveIndex(file, index, base, i);
    std::array<int, 4> tet{};
    for (std::size_t k = 0; k < 4; ++k) {
      const int node = file.integer(tokens[k + 1]);
      const long zeroBased = static_cast<long>(node) - nodeBase;
      if (zeroBased < 0 || zeroBased >= vertexCount) {
        file.fail("node " + std::to_string(node) + " out of range (the .node file has " +
                  std::to_string(vertexCount) + " nodes, numbered from " +
                  std::to_string(nodeBase) + ")");
      }
      tet[k] = static_cast<int>(zeroBased);
    }
    for (std::size_t k = 5; k < fields; ++k)
      file.real(tokens[k]);
    mesh.tetrahedra.push_back(tet);
  }
  expectEnd(file, static_cast<std::size_t>(count), "tetrahedra");
}

}  // namespace

const char* objPrecisionName(ObjPrecision precision) {
  return precision == ObjPrecision::Single ? "single" : "double";
}

TriangleMesh loadObj(const std::string& path, ObjPrecision precision) {
  return parseObj(readWholeFile(path), path, precision);
}

TriangleMesh parseObj(const std::string& text, const std::string& sourceName,
                      ObjPrecision precision) {
  TokenizedFile file(text, sourceName);
  TriangleMesh mesh;
  Tokens tokens;
  while (file.next(tokens)) {
    const std::string& keyword = tokens[0];
    if (keyword == "v") {
      mesh.vertices.push_back(readObjVertex(file, tokens, precision));
    } else if (keyword == "f") {
      appendObjFace(file, tokens, mesh);
    } else if (!isIgnoredObjStatement(keyword)) {
      file.fail("unsupported statement '" + keyword + "' (only v and f are read)");
    }
  }
  if (mesh.triangles.empty()) file.failFile("no faces (a triangle mesh needs 'f' lines)");
  return mesh;
}

TetMesh loadTetGen(const std::string& nodePath, const std::string& elePath) {
  const std::string nodeText = readWholeFile(nodePath);
  return parseTetGen(nodeText, readWholeFile(elePath), nodePath, elePath);
}

TetMesh parseTetGen(const std::string& nodeText, const std::string& eleText,
                    const std::string& nodeName, const std::string& eleName) {
  TetMesh mesh;
  const int nodeBase = readTetGenNodes(nodeText, nodeName, mesh.vertices);
  readTetGenElements(eleText, eleName, nodeBase, mesh);
  return mesh;
}

}  // namespace pbd
