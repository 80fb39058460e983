// OBJ and TetGen readers: the accepted forms and the located errors.
#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <string>

#include "common/text_assertions.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

// Writes `content` to a file in the test's temporary folder; the name includes the test name,
// so tests running in parallel never share a file.
std::string writeFile(const std::string& name, const std::string& content) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string path =
      ::testing::TempDir() + "pbd_" + test->test_suite_name() + "_" + test->name() + "_" + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

using pbd::test::containsAll;

template <class Load>
std::string errorOf(Load load) {
  try {
    load();
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError)";
}

using Triangle = std::array<int, 3>;

// ---- OBJ ------------------------------------------------------------------------------------

TEST(ObjLoader, ReadsAllFaceFormsAndIgnoresOtherStatements) {
  const std::string path = writeFile("forms.obj",
                                     "# comment\r\n"
                                     "mtllib x.mtl\n"
                                     "o thing\n"
                                     "g group\n"
                                     "s off\n"
                                     "usemtl steel\n"
                                     "v 0 0 0\n"
                                     "v 1 0 0 1.0\n"  // optional w
                                     "v 1 1 0   # trailing comment\n"
                                     "v 0 1 0\n"
                                     "vt 0 0\n"
                                     "vn 0 0 1\n"
                                     "f 1 2 3\n"
                                     "f 1/1 3/1 4/1\n"
                                     "f 1//1 2//1 4//1\n"
                                     "f 2/1/1 3/1/1 4/1/1\r\n");
  const TriangleMesh mesh = loadObj(path);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[2], Vector3(1, 1, 0));
  ASSERT_EQ(mesh.triangles.size(), 4u);
  EXPECT_EQ(mesh.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (Triangle{0, 1, 3}));
  EXPECT_EQ(mesh.triangles[3], (Triangle{1, 2, 3}));
}

TEST(ObjLoader, NegativeIndicesCountBackFromTheLastVertexSoFar) {
  const std::string path = writeFile("negative.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                     "f -3 -2 -1\n"
                                     "v 0 0 1\n"
                                     "f -4/1 -1/1 -3/1\n");
  const TriangleMesh mesh = loadObj(path);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (Triangle{0, 3, 1}));
}

TEST(ObjLoader, PolygonsAreFanTriangulated) {
  const std::string path = writeFile("polygons.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 0.5 0\n"
                                     "f 1 2 3 4\n"
                                     "f 1 2 3 4 5\n");
  const TriangleMesh mesh = loadObj(path);
  ASSERT_EQ(mesh.triangles.size(), 5u);
  EXPECT_EQ(mesh.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (Triangle{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[3], (Triangle{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[4], (Triangle{0, 3, 4}));
}

TEST(ObjLoader, ErrorsNameTheFileAndLine) {
  const std::string missing = ::testing::TempDir() + "pbd_no_such_file.obj";
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(missing); }), {missing, "cannot open"}));

  const std::string badNumber = writeFile("bad_number.obj", "v 0 0 0\nv 1 abc 0\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(badNumber); }),
                          {badNumber, "line 2", "expected a finite number", "'abc'"}));

  const std::string nanNumber = writeFile("nan.obj", "v 0 nan 0\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(nanNumber); }), {"line 1", "'nan'"}));

  const std::string shortVertex = writeFile("short_vertex.obj", "v 0 0\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(shortVertex); }), {"line 1", "v x y z"}));

  const std::string outOfRange = writeFile("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(outOfRange); }),
                          {outOfRange, "line 4", "vertex index 4 out of range", "3 vertices"}));

  const std::string zeroIndex = writeFile("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(zeroIndex); }), {"line 4", "vertex index 0"}));

  const std::string tooNegative = writeFile("negative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(tooNegative); }), {"line 3", "index -3"}));

  const std::string badForm = writeFile("form.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(badForm); }), {"line 4", "'1/1/1/1'"}));

  const std::string twoVertices = writeFile("edge.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(twoVertices); }), {"line 3", "at least 3"}));

  const std::string lines = writeFile("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(lines); }), {"line 3", "unsupported", "'l'"}));

  const std::string noFaces = writeFile("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_TRUE(containsAll(errorOf([&] { loadObj(noFaces); }), {noFaces, "no faces"}));
}

// ---- TetGen ---------------------------------------------------------------------------------

TEST(TetGenLoader, ReadsZeroBasedFiles) {
  const std::string node = writeFile("a.node",
                                     "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n"
                                     "4 1 1 1\n");
  const std::string ele = writeFile("a.ele", "2 4 0\n0 0 1 2 3\n1 1 2 3 4\n");
  const TetMesh mesh = loadTetGen(node, ele);
  ASSERT_EQ(mesh.vertices.size(), 5u);
  EXPECT_EQ(mesh.vertices[4], Vector3(1, 1, 1));
  ASSERT_EQ(mesh.tetrahedra.size(), 2u);
  EXPECT_EQ(mesh.tetrahedra[0], (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.tetrahedra[1], (std::array<int, 4>{1, 2, 3, 4}));
}

TEST(TetGenLoader, ReadsOneBasedFilesWithAttributesMarkersAndComments) {
  const std::string node = writeFile("b.node",
                                     "# Node count, 3 dim, 1 attribute, 1 boundary marker\n"
                                     "4  3  1  1\n"
                                     "   1    0 0 0   0.5  1\n"
                                     "   2    1 0 0   0.5  1   # a comment\n"
                                     "\n"
                                     "   3    0 1 0   0.5  0\n"
                                     "   4    0 0 1.5 0.5  1\n"
                                     "# Generated by tetgen\n");
  const std::string ele = writeFile("b.ele", "1 4 1\n1 4 3 2 1 7\n# trailing comment\n");
  const TetMesh mesh = loadTetGen(node, ele);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[3], Vector3(0, 0, 1.5));
  ASSERT_EQ(mesh.tetrahedra.size(), 1u);
  EXPECT_EQ(mesh.tetrahedra[0], (std::array<int, 4>{3, 2, 1, 0}));
}

TEST(TetGenLoader, ErrorsNameTheFileAndLine) {
  const std::string goodNode = writeFile("good.node",
                                         "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
                                         "4 0 0 1\n");
  const std::string goodEle = writeFile("good.ele", "1 4 0\n1 1 2 3 4\n");
  const auto error = [](const std::string& node, const std::string& ele) {
    return errorOf([&] { loadTetGen(node, ele); });
  };

  const std::string missing = ::testing::TempDir() + "pbd_no_such_file.node";
  EXPECT_TRUE(containsAll(error(missing, goodEle), {missing, "cannot open"}));

  const std::string gap = writeFile("gap.node", "3 3 0 0\n1 0 0 0\n3 1 0 0\n4 0 1 0\n");
  EXPECT_TRUE(containsAll(error(gap, goodEle), {gap, "line 3", "expected index 2, got 3"}));

  const std::string base2 = writeFile("base2.node", "1 3 0 0\n2 0 0 0\n");
  EXPECT_TRUE(containsAll(error(base2, goodEle), {"line 2", "first index must be 0 or 1"}));

  const std::string flat = writeFile("flat.node", "1 2 0 0\n1 0 0\n");
  EXPECT_TRUE(containsAll(error(flat, goodEle), {"line 1", "dimension 3"}));

  const std::string shortLine = writeFile("short.node", "2 3 0 0\n1 0 0 0\n2 1 0\n");
  EXPECT_TRUE(containsAll(error(shortLine, goodEle), {"line 3", "expected 4 values", "got 3"}));

  const std::string truncated = writeFile("truncated.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n");
  EXPECT_TRUE(containsAll(error(truncated, goodEle), {truncated, "expected 3 nodes, found 2"}));

  const std::string extra = writeFile("extra.node", "1 3 0 0\n1 0 0 0\n2 1 0 0\n");
  EXPECT_TRUE(containsAll(error(extra, goodEle), {"line 3", "unexpected data"}));

  const std::string badNumber = writeFile("number.node", "1 3 0 0\n1 0 x 0\n");
  EXPECT_TRUE(containsAll(error(badNumber, goodEle), {"line 2", "'x'"}));

  const std::string outOfRange = writeFile("range.ele", "1 4 0\n1 1 2 3 5\n");
  EXPECT_TRUE(containsAll(error(goodNode, outOfRange),
                          {outOfRange, "line 2", "node 5 out of range", "numbered from 1"}));

  const std::string zeroInOneBased = writeFile("zero.ele", "1 4 0\n1 0 1 2 3\n");
  EXPECT_TRUE(containsAll(error(goodNode, zeroInOneBased), {"line 2", "node 0 out of range"}));

  const std::string quadratic = writeFile("quadratic.ele", "1 10 0\n");
  EXPECT_TRUE(containsAll(error(goodNode, quadratic), {"line 1", "only linear tetrahedra"}));

  const std::string noTets = writeFile("empty.ele", "# nothing\n");
  EXPECT_TRUE(containsAll(error(goodNode, noTets), {noTets, "empty file"}));
}

}  // namespace
}  // namespace pbd
