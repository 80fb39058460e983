// Mesh export (validation/io/mesh_export.h, pbd/model/mesh.h, pbd/io/mesh_writer.h): a tet mesh's
// boundary is closed and turned outwards, barycentric attachment carries points exactly through
// any affine map of the tets (barycentric coordinates are affine invariant), the exported files
// read back to the placed geometry, and frames fall on the frame-rate grid.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "pbd/io/mesh_loader.h"
#include "pbd/io/mesh_writer.h"
#include "pbd/io/scene_loader.h"
#include "tests/validation/fixtures.h"
#include "validation/io/mesh_export.h"
#include "validation/measure/mechanics.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;

/// The unit cube split into five positively oriented tets (corner k at (k&1, k>>1&1, k>>2&1)).
pbd::TetMesh cubeTets() {
  pbd::TetMesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.vertices.push_back(Vector3(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  mesh.tetrahedra = {{0, 1, 3, 5}, {0, 3, 2, 6}, {0, 5, 6, 4}, {3, 6, 5, 7}, {0, 3, 6, 5}};
  return mesh;
}

TEST(MeshExport, TetBoundaryIsTheCubesTwelveOutwardTriangles) {
  const pbd::TetMesh cube = cubeTets();
  const auto faces = pbd::boundaryFaces(cube);
  ASSERT_EQ(faces.size(), 12u);  // two per side; the central tet's faces are all interior
  double area = 0;
  Vector3 closure = Vector3::Zero();  // Σ of area vectors: zero for a closed surface
  for (const auto& f : faces) {
    const Vector3 a = cube.vertices[std::size_t(f[0])], b = cube.vertices[std::size_t(f[1])],
                  c = cube.vertices[std::size_t(f[2])];
    const Vector3 normal = (b - a).cross(c - a) / 2;
    area += normal.norm();
    closure += normal;
    EXPECT_GT(normal.dot((a + b + c) / 3 - Vector3(0.5, 0.5, 0.5)), 0);  // outwards
  }
  EXPECT_NEAR(area, 6, 1e-14);
  EXPECT_LT(closure.norm(), 1e-14);
}

TEST(MeshExport, AttachedPointsFollowAnyAffineMapExactly) {
  const pbd::TetMesh cube = cubeTets();
  const std::vector<Vector3> points = {Vector3(0.5, 0.5, 0.5), Vector3(0.1, 0.2, 0.9),
                                       Vector3(1, 1, 1), Vector3(1.3, -0.2, 0.5)};  // last: outside
  const auto attached = pbd::attachToTets(cube, points);
  ASSERT_EQ(attached.size(), points.size());
  for (std::size_t i = 0; i < 3; ++i)  // inside or on the surface: every weight ≥ 0
    for (double w : attached[i].weights)
      EXPECT_GE(w, -1e-15);
  Matrix3 map;
  map << 1.2, 0.3, -0.1, 0.0, 0.8, 0.4, 0.2, -0.5, 1.1;
  const Vector3 shift(3, -1, 2);
  for (std::size_t i = 0; i < points.size(); ++i) {
    Vector3 carried = Vector3::Zero(), atRest = Vector3::Zero();
    double sum = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const Vector3& x =
          cube.vertices[std::size_t(cube.tetrahedra[std::size_t(attached[i].tet)][k])];
      carried += attached[i].weights[k] * (map * x + shift);
      atRest += attached[i].weights[k] * x;
      sum += attached[i].weights[k];
    }
    EXPECT_NEAR(sum, 1, 1e-14);
    EXPECT_LT((atRest - points[i]).norm(), 1e-14) << i;
    EXPECT_LT((carried - (map * points[i] + shift)).norm(), 1e-13) << i;
  }
}

TEST(MeshExport, WrittenMeshesReadBackToTheSameGeometry) {
  pbd::TriangleMesh mesh;
  mesh.vertices = {Vector3(0.1, 1.0 / 3, -2), Vector3(1e-7, 5, 6), Vector3(-1, 0, 1e5)};
  mesh.triangles = {{0, 1, 2}};
  std::ostringstream obj, ply;
  pbd::writeObj(obj, mesh.vertices, mesh.triangles);
  pbd::writePly(ply, mesh.vertices, mesh.triangles);
  for (const pbd::TriangleMesh& back :
       {pbd::parseObj(obj.str(), "mesh.obj"), pbd::parsePly(ply.str(), "mesh.ply")}) {
    ASSERT_EQ(back.vertices.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i)
      EXPECT_EQ(back.vertices[i], mesh.vertices[i]);  // exact
    EXPECT_EQ(back.triangles, mesh.triangles);
  }
}

class MeshExporterRun : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("pbdval-mesh-export-" + std::to_string(::getpid()));
    fs::remove_all(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_;
};

TEST_F(MeshExporterRun, FramesFallOnTheGridAndBodiesArePlacedByTheirPose) {
  // A box body (cases/models/cube.obj scaled by (1, 2, 3)), a cloth of 3 × 3 vertices and one
  // tet: one file per surface per frame and format.
  const std::string json = std::string(R"({"RigidBodies": [{"id": 7, "geometryFile": ")") +
                           PBDVAL_SOURCE_DIR + R"(/cases/models/cube.obj", "scale": [1, 2, 3]}],
      "TriangleModels": [{"geometryFile": ")" +
                           PBDVAL_SOURCE_DIR + R"(/tests/data/meshes/plane_3x3.obj"}],
      "TetModels": [{"nodeFile": ")" +
                           PBDVAL_SOURCE_DIR + R"(/tests/data/meshes/tet.node", "eleFile": ")" +
                           PBDVAL_SOURCE_DIR + R"(/tests/data/meshes/tet.ele"}]})";
  const pbd::Scene scene = pbd::parseScene(json, PBDVAL_SOURCE_DIR "/cases/inline.json", {}).scene;
  MeshExportOptions options;
  options.directory = (folder_ / "meshes").string();
  options.obj = true;
  options.ply = true;
  options.framesPerSecond = 10;
  MeshExporter exporter(scene, options);
  // States every 25 ms for 0.5 s: frames at 0, 0.1, …, 0.5 s.
  const Quaternion turn = test::turn(Vector3(1, 1, 0), 0.7);
  for (int k = 0; k <= 20; ++k) {
    State state = initialState(scene);
    state.time = 0.025 * k;
    state.bodies[0].position = Vector3(1, 2, 3) * state.time;
    state.bodies[0].rotation = k == 20 ? turn : Quaternion::Identity();
    for (ParticleState& p : state.particles)
      p.position.y() -= state.time;
    exporter.onState(state);
  }
  EXPECT_EQ(exporter.frames(), 6u);
  EXPECT_EQ(exporter.files(), 6u * 3 * 2);  // frames × surfaces × formats
  for (const char* name :
       {"body7_00005.obj", "body7_00005.ply", "cloth0_00003.obj", "solid0_00000.ply"})
    EXPECT_TRUE(fs::is_regular_file(folder_ / "meshes" / name)) << name;
  EXPECT_FALSE(fs::exists(folder_ / "meshes" / "body7_00006.obj"));
  // The last frame's box: p + R (v − c) with p = (0.5, 1, 1.5).
  const pbd::TriangleMesh box =
      pbd::loadSurfaceMesh((folder_ / "meshes" / "body7_00005.ply").string());
  const pbd::RigidBodyDesc& body = scene.rigidBodies[0];
  ASSERT_EQ(box.vertices.size(), body.mesh->vertices.size());
  for (std::size_t i = 0; i < box.vertices.size(); ++i) {
    const Vector3 expected =
        Vector3(0.5, 1, 1.5) + turn * (body.mesh->vertices[i] - body.massProperties.centerOfMass);
    EXPECT_LT((box.vertices[i] - expected).norm(), 1e-14) << i;
  }
  // The cloth at frame 3 (t = 0.3 s, reached by the state at 0.3 s): lowered by 0.3 m.
  const pbd::TriangleMesh cloth =
      pbd::loadSurfaceMesh((folder_ / "meshes" / "cloth0_00003.obj").string());
  ASSERT_EQ(cloth.vertices.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i)
    EXPECT_NEAR(cloth.vertices[i].y(), scene.particles[i].position.y() - 0.3, 1e-15);
  // The tet without a visual mesh: its four boundary faces.
  EXPECT_EQ(
      pbd::loadSurfaceMesh((folder_ / "meshes" / "solid0_00000.obj").string()).triangles.size(),
      4u);
}

TEST_F(MeshExporterRun, BadOptionsAreErrors) {
  const pbd::Scene scene = test::emptyScene();
  MeshExportOptions options;
  options.directory = (folder_ / "x").string();
  options.obj = true;
  options.framesPerSecond = 0;
  EXPECT_THROW(MeshExporter(scene, options), std::invalid_argument);
  options.framesPerSecond = 25;
  options.obj = false;
  EXPECT_THROW(MeshExporter(scene, options), std::invalid_argument);
  // A file where the folder should be.
  fs::create_directories(folder_);
  std::ofstream(folder_ / "file") << "x";
  options.obj = true;
  options.directory = (folder_ / "file" / "meshes").string();
  EXPECT_THROW(MeshExporter(scene, options), std::runtime_error);
}

}  // namespace
}  // namespace pbdval
