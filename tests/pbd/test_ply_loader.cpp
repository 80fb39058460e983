// The PLY reader (pbd/src/io/ply_loader.cpp): ASCII and both binary byte orders give the same
// mesh as the OBJ of the same geometry; properties and elements pbdval does not use are read
// past; polygons become fans; malformed files are errors naming the file and the place.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/text_assertions.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

const std::string kDataDir = PBDVAL_TEST_DATA_DIR;

// A unit square (a quad) and a triangle over it, with normals and colours PBD does not use, and
// an `edge` element after the faces.
const char* const kAsciiPly = R"(ply
format ascii 1.0
comment test data
element vertex 5
property float x
property float y
property float z
property float nx
property uchar red
element face 2
property uchar intensity
property list uchar int vertex_indices
element edge 1
property int vertex1
property int vertex2
end_header
0 0 0 0 255
1 0 0 0 255
1 1 0 0 255
0 1 0 0 255
0.5 0.5 2 1 7
9 4 0 1 2 3
9 3 0 1 4
0 1
)";

// The same geometry as OBJ.
const char* const kObj = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 0.5 2
f 1 2 3 4
f 1 2 5
)";

void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    EXPECT_EQ(a.vertices[i], b.vertices[i]) << i;
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t i = 0; i < a.triangles.size(); ++i)
    EXPECT_EQ(a.triangles[i], b.triangles[i]) << i;
}

/// Appends `value` as `T` in the given byte order.
template <class T>
void put(std::string& out, T value, bool bigEndian) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  const std::uint16_t probe = 1;
  char first;
  std::memcpy(&first, &probe, 1);
  const bool hostLittle = first == 1;
  if (bigEndian == hostLittle) std::reverse(raw, raw + sizeof(T));
  out.append(raw, sizeof(T));
}

/// kAsciiPly's content in binary: float x y z, double nx, uchar red; faces with a ushort count
/// and uint indices; the edge element with two ints.
std::string binaryPly(bool bigEndian) {
  std::string out = std::string("ply\nformat ") +
                    (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float "
                    "z\nproperty double nx\nproperty uchar red\nelement face 2\nproperty uchar "
                    "intensity\nproperty list ushort uint vertex_indices\nelement edge 1\nproperty "
                    "int vertex1\nproperty int vertex2\nend_header\n";
  const float xyz[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 2}};
  for (const auto& v : xyz) {
    for (float c : v)
      put<float>(out, c, bigEndian);
    put<double>(out, 0.25, bigEndian);
    put<std::uint8_t>(out, 255, bigEndian);
  }
  put<std::uint8_t>(out, 9, bigEndian);
  put<std::uint16_t>(out, 4, bigEndian);
  for (std::uint32_t i : {0u, 1u, 2u, 3u})
    put<std::uint32_t>(out, i, bigEndian);
  put<std::uint8_t>(out, 9, bigEndian);
  put<std::uint16_t>(out, 3, bigEndian);
  for (std::uint32_t i : {0u, 1u, 4u})
    put<std::uint32_t>(out, i, bigEndian);
  put<std::int32_t>(out, 0, bigEndian);
  put<std::int32_t>(out, 1, bigEndian);
  return out;
}

std::string errorOf(const std::string& bytes) {
  try {
    parsePly(bytes, "mesh.ply");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError)";
}

TEST(PlyLoader, AsciiAndBothBinaryOrdersEqualTheObj) {
  const TriangleMesh obj = parseObj(kObj, "mesh.obj");
  ASSERT_EQ(obj.triangles.size(), 3u);  // the quad's fan and the triangle
  expectSameMesh(parsePly(kAsciiPly, "mesh.ply"), obj);
  // The coordinates are exact in float (0, 0.5, 1, 2): the binary files read back exactly.
  expectSameMesh(parsePly(binaryPly(false), "mesh.ply"), obj);
  expectSameMesh(parsePly(binaryPly(true), "mesh.ply"), obj);
  // Windows line ends in the header are accepted.
  std::string crlf = kAsciiPly;
  for (std::size_t at = crlf.find('\n'); at != std::string::npos; at = crlf.find('\n', at + 2))
    crlf.insert(at, "\r");
  expectSameMesh(parsePly(crlf, "mesh.ply"), obj);
}

TEST(PlyLoader, FilesAreReadByTheirExtension) {
  const TriangleMesh ply = loadSurfaceMesh(kDataDir + "/meshes/triangle.ply");
  ASSERT_EQ(ply.vertices.size(), 3u);
  ASSERT_EQ(ply.triangles.size(), 1u);
  EXPECT_EQ(ply.triangles[0], (std::array<int, 3>{0, 1, 2}));
  EXPECT_EQ(ply.vertices[1], Vector3(1, 0, 0));
  // A scene's triangle model from the PLY: its particles are the file's vertices.
  const LoadedScene scene =
      parseScene(R"({"TriangleModels": [{"geometryFile": "../meshes/triangle.ply"}]})",
                 kDataDir + "/scenes/inline.json", LoadOptions{});
  ASSERT_EQ(scene.scene.particles.size(), 3u);
  EXPECT_EQ(scene.scene.particles[2].position, Vector3(0, 1, 0));
}

TEST(PlyLoader, MalformedFilesNameThePlace) {
  using test::containsAll;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_TRUE(containsAll(errorOf("solid\n"), {"mesh.ply", "header line 1"}));
  EXPECT_TRUE(containsAll(errorOf("ply\nformat ascii 1.0\nelement vertex 1\n"), {"no end_header"}));
  EXPECT_TRUE(containsAll(errorOf("ply\nformat utf8 1.0\nend_header\n"),
                          {"header line 2", "unknown format 'utf8'"}));
  EXPECT_TRUE(containsAll(errorOf("ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
                          {"header line 3", "a property before any element"}));
  EXPECT_TRUE(containsAll(errorOf("ply\nformat ascii 1.0\nelement face 1\nproperty list float int "
                                  "vertex_indices\nend_header\n3 0 1 2\n"),
                          {"count type must be an integer type"}));
  EXPECT_TRUE(containsAll(errorOf(header + vertices + "3 0 1 7\n"),
                          {"face 0: vertex index 7 out of range (the file has 3 vertices)"}));
  EXPECT_TRUE(containsAll(errorOf(header + vertices + "2 0 1\n"),
                          {"face 0: a face needs at least 3 vertices, got 2"}));
  EXPECT_TRUE(
      containsAll(errorOf(header + "0 0 0\n1 0 0\n"), {"vertex 2, x: the file ends early"}));
  EXPECT_TRUE(containsAll(errorOf(header + "0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n"),
                          {"vertex 0, z: expected a finite number, got 'zero'"}));
  EXPECT_TRUE(
      containsAll(errorOf(header + vertices + "3 0 1 2\n4 5 6\n"), {"after the last element"}));
  EXPECT_TRUE(containsAll(
      errorOf(
          "ply\nformat ascii 1.0\nelement vertex 100000000000\nproperty float x\nproperty float y\n"
          "property float z\nend_header\n0 0 0\n"),
      {"claims 100000000000 items; the file is too short"}));
  EXPECT_TRUE(containsAll(
      errorOf("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
              "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
              "3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n"),
      {"the face element comes before the vertex element"}));
  EXPECT_TRUE(containsAll(
      errorOf("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n"),
      {"needs scalar properties x, y and z"}));
  EXPECT_TRUE(containsAll(
      errorOf("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar float vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1e300\n"),
      {"vertex_indices must be of an integer type"}));
  // A binary file cut short, and a NaN coordinate.
  std::string cut = binaryPly(false);
  cut.resize(cut.size() - 5);
  EXPECT_TRUE(containsAll(errorOf(cut), {"the file ends early"}));
  std::string nan = binaryPly(true);
  const std::size_t firstValue = nan.find("end_header\n") + 11;
  nan[firstValue] = '\x7f';
  nan[firstValue + 1] = '\xc0';
  EXPECT_TRUE(containsAll(errorOf(nan), {"vertex 0, x: not a finite number"}));
}

}  // namespace
}  // namespace pbd
