// The reader of Discregrid's `.csdf` grids (pbd/io/discregrid_file.h): a grid written here in
// Discregrid's own global numbering (its CubicLagrangeDiscreteGrid::indexToNodePosition and the
// cell table of addFunction, rewritten from their description) must come back node for node; a
// grid written by the original's Discregrid must match pbdval's own sampling of the same mesh;
// and damaged files are errors naming the file.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "pbd/collision/distance_grid.h"
#include "pbd/collision/mesh_distance.h"
#include "pbd/io/discregrid_file.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"
#include "pbd/io/scene_writer.h"

namespace pbd {
namespace {

const std::string kDataDir = PBDVAL_TEST_DATA_DIR;
/// tests/data/seed_reference/sdf/torus_8.csdf: cases/models/torus.obj's distance on 8³ cells
/// over its box padded by 0.1, written by the original's Discregrid (README there).
const std::string kTorusGrid = kDataDir + "/seed_reference/sdf/torus_8.csdf";

/// A complete cubic polynomial: the 32-node serendipity cell reproduces it exactly.
double cubic(double x, double y, double z) {
  return 0.3 + x - 2 * y + 0.5 * z + x * y - z * z + 0.2 * x * x * x + x * y * z;
}

template <typename T>
void append(std::string& bytes, const T& value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

/// A .csdf of `cubic` over [lo, hi] with n cells, in Discregrid's global numbering: corners
/// (x fastest), then two nodes per x edge (x fastest, then y, then z), per y edge (y fastest,
/// then z, then x), per z edge (z fastest, then x, then y). `fields` copies of the field.
std::string discregridBytes(const std::array<double, 3>& lo, const std::array<double, 3>& hi,
                            const std::array<std::uint32_t, 3>& n, std::uint64_t fields = 1) {
  const std::uint64_t nx = n[0], ny = n[1], nz = n[2];
  const std::uint64_t nv = (nx + 1) * (ny + 1) * (nz + 1);
  const std::uint64_t nex = nx * (ny + 1) * (nz + 1), ney = (nx + 1) * ny * (nz + 1);
  const std::uint64_t nez = (nx + 1) * (ny + 1) * nz;
  double h[3];
  for (int a = 0; a < 3; ++a)
    h[a] = (hi[std::size_t(a)] - lo[std::size_t(a)]) / double(n[std::size_t(a)]);
  const auto at = [&](double i, double j, double k) {
    return cubic(lo[0] + h[0] * i, lo[1] + h[1] * j, lo[2] + h[2] * k);
  };
  std::vector<double> nodes;
  for (std::uint64_t k = 0; k <= nz; ++k)
    for (std::uint64_t j = 0; j <= ny; ++j)
      for (std::uint64_t i = 0; i <= nx; ++i)
        nodes.push_back(at(double(i), double(j), double(k)));
  for (std::uint64_t k = 0; k <= nz; ++k)
    for (std::uint64_t j = 0; j <= ny; ++j)
      for (std::uint64_t i = 0; i < nx; ++i)
        for (int s = 0; s < 2; ++s)
          nodes.push_back(at(double(i) + (1 + s) / 3.0, double(j), double(k)));
  for (std::uint64_t i = 0; i <= nx; ++i)
    for (std::uint64_t k = 0; k <= nz; ++k)
      for (std::uint64_t j = 0; j < ny; ++j)
        for (int s = 0; s < 2; ++s)
          nodes.push_back(at(double(i), double(j) + (1 + s) / 3.0, double(k)));
  for (std::uint64_t j = 0; j <= ny; ++j)
    for (std::uint64_t i = 0; i <= nx; ++i)
      for (std::uint64_t k = 0; k < nz; ++k)
        for (int s = 0; s < 2; ++s)
          nodes.push_back(at(double(i), double(j), double(k) + (1 + s) / 3.0));
  EXPECT_EQ(nodes.size(), nv + 2 * (nex + ney + nez));

  std::string bytes;
  for (double v : lo)
    append(bytes, v);
  for (double v : hi)
    append(bytes, v);
  for (std::uint32_t v : n)
    append(bytes, v);
  for (double v : h)
    append(bytes, v);
  for (double v : h)
    append(bytes, 1 / v);
  append(bytes, std::uint64_t(nx * ny * nz));
  append(bytes, fields);
  append(bytes, fields);
  for (std::uint64_t f = 0; f < fields; ++f) {
    append(bytes, std::uint64_t(nodes.size()));
    for (double v : nodes)
      append(bytes, v);
  }
  append(bytes, fields);
  for (std::uint64_t f = 0; f < fields; ++f) {
    append(bytes, std::uint64_t(nx * ny * nz));
    for (std::uint64_t k = 0; k < nz; ++k)
      for (std::uint64_t j = 0; j < ny; ++j)
        for (std::uint64_t i = 0; i < nx; ++i) {
          std::array<std::uint32_t, 32> c{};
          const auto corner = [&](std::uint64_t a, std::uint64_t b, std::uint64_t d) {
            return std::uint32_t((nx + 1) * (ny + 1) * d + (nx + 1) * b + a);
          };
          c[0] = corner(i, j, k), c[1] = corner(i + 1, j, k), c[2] = corner(i, j + 1, k);
          c[3] = corner(i + 1, j + 1, k), c[4] = corner(i, j, k + 1);
          c[5] = corner(i + 1, j, k + 1), c[6] = corner(i, j + 1, k + 1);
          c[7] = corner(i + 1, j + 1, k + 1);
          const auto xEdge = [&](std::uint64_t b, std::uint64_t d) {
            return std::uint32_t(nv + 2 * (nx * (ny + 1) * d + nx * b + i));
          };
          const auto yEdge = [&](std::uint64_t a, std::uint64_t d) {
            return std::uint32_t(nv + 2 * nex + 2 * (ny * (nz + 1) * a + ny * d + j));
          };
          const auto zEdge = [&](std::uint64_t a, std::uint64_t b) {
            return std::uint32_t(nv + 2 * (nex + ney) + 2 * (nz * (nx + 1) * b + nz * a + k));
          };
          const std::uint32_t edges[12] = {
              xEdge(j, k), xEdge(j, k + 1), xEdge(j + 1, k), xEdge(j + 1, k + 1),
              yEdge(i, k), yEdge(i + 1, k), yEdge(i, k + 1), yEdge(i + 1, k + 1),
              zEdge(i, j), zEdge(i, j + 1), zEdge(i + 1, j), zEdge(i + 1, j + 1)};
          for (int e = 0; e < 12; ++e) {
            c[std::size_t(8 + 2 * e)] = edges[e];
            c[std::size_t(9 + 2 * e)] = edges[e] + 1;
          }
          for (std::uint32_t v : c)
            append(bytes, v);
        }
  }
  append(bytes, fields);
  for (std::uint64_t f = 0; f < fields; ++f) {
    append(bytes, std::uint64_t(nx * ny * nz));
    for (std::uint32_t l = 0; l < nx * ny * nz; ++l)
      append(bytes, l);
  }
  return bytes;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string errorOf(const std::string& bytes, const std::string& name = "grid.csdf") {
  try {
    parseDiscregridGrid(bytes, name);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

TEST(DiscregridFile, AGridInDiscregridsNumberingIsReadNodeForNode) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the file's doubles are compared exactly";
  const std::array<double, 3> lo = {-0.5, 0.25, -1.0}, hi = {1.0, 1.25, 1.5};
  const DistanceGrid grid = parseDiscregridGrid(discregridBytes(lo, hi, {3, 4, 5}), "cubic");
  ASSERT_EQ(grid.cells(), Vector3i(3, 4, 5));
  const Vector3 min(static_cast<Real>(lo[0]), static_cast<Real>(lo[1]), static_cast<Real>(lo[2]));
  const Vector3 max(static_cast<Real>(hi[0]), static_cast<Real>(hi[1]), static_cast<Real>(hi[2]));
  const Vector3 spacing = (max - min).cwiseQuotient(Vector3(3, 4, 5));
  // Every node holds the polynomial at its own position in pbdval's layout; 1e-12: the two
  // node positions are computed in different orders (a few ulps of coordinates ≤ 1.5).
  for (std::size_t k = 0; k < grid.nodes().size(); ++k) {
    const Vector3 p =
        DistanceGrid::nodePosition(min, spacing, grid.cells(), GridInterpolation::CubicLagrange, k);
    ASSERT_NEAR(grid.nodes()[k], cubic(p.x(), p.y(), p.z()), 1e-12) << "node " << k;
  }
  // And the interpolant reproduces the cubic inside every cell; 1e-12: round-off of the
  // 32-term sum of O(1) values.
  for (int s = 0; s < 200; ++s) {
    const Vector3 p(Real(-0.5 + 1.5 * std::fmod(0.37 * s, 1.0)),
                    Real(0.25 + std::fmod(0.61 * s + 0.1, 1.0)),
                    Real(-1 + 2.5 * std::fmod(0.23 * s + 0.7, 1.0)));
    EXPECT_NEAR(grid.value(p), cubic(p.x(), p.y(), p.z()), 1e-12);
  }
}

TEST(DiscregridFile, OnlyTheFirstFieldIsKeptFromAGridOfSeveral) {
  const std::array<double, 3> lo = {0, 0, 0}, hi = {1, 1, 1};
  const DistanceGrid one = parseDiscregridGrid(discregridBytes(lo, hi, {2, 2, 2}, 1), "one");
  const DistanceGrid two = parseDiscregridGrid(discregridBytes(lo, hi, {2, 2, 2}, 2), "two");
  EXPECT_EQ(one.nodes(), two.nodes());
}

TEST(DiscregridFile, TheOriginalsTorusGridMatchesPbdvalsOwnSamplingOfTheMesh) {
  if (sizeof(Real) != sizeof(double)) GTEST_SKIP() << "the grid is compared to 1e-12";
  const DistanceGrid file = readDiscregridGrid(kTorusGrid);
  ASSERT_EQ(file.cells(), Vector3i(8, 8, 8));
  const TriangleMesh torus = loadObj(std::string(PBDVAL_SOURCE_DIR) + "/cases/models/torus.obj");
  const MeshDistance distance(torus);
  const DistanceGrid ours = DistanceGrid::sample(
      file.domainMin(), file.domainMax(), file.cells(),
      [&](const Vector3& p) { return distance.signedDistance(p); },
      GridInterpolation::CubicLagrange);
  ASSERT_EQ(file.nodes().size(), ours.nodes().size());
  // Both are the exact point–triangle distance evaluated in double at the same node; 1e-12 m is
  // far above their round-off (~1e-16 of distances ≤ 2 m) and far below a node misplaced by a
  // third of a cell (~0.1 m).
  for (std::size_t k = 0; k < ours.nodes().size(); ++k)
    ASSERT_NEAR(file.nodes()[k], ours.nodes()[k], 1e-12) << "node " << k;
}

TEST(DiscregridFile, ATruncatedFileIsAnErrorNamingTheFileAndTheOffset) {
  const std::string bytes = fileBytes(kTorusGrid);
  ASSERT_GT(bytes.size(), 1000u);
  for (std::size_t length :
       {std::size_t(0), std::size_t(20), std::size_t(50), std::size_t(100), std::size_t(130),
        bytes.size() / 3, bytes.size() / 2, bytes.size() - 1}) {
    const std::string message = errorOf(bytes.substr(0, length), "torus_8.csdf");
    EXPECT_EQ(message.rfind("torus_8.csdf: Discregrid grid (.csdf): truncated", 0), 0u)
        << length << ": " << message;
    EXPECT_NE(message.find("of " + std::to_string(length) + ")"), std::string::npos) << message;
  }
}

TEST(DiscregridFile, TrailingBytesAreAnError) {
  const std::string message = errorOf(fileBytes(kTorusGrid) + "x");
  EXPECT_NE(message.find("1 bytes after the cell map"), std::string::npos) << message;
}

/// The byte offset of the first cell's first node index in a single-field file of `nodeCount`
/// nodes: the 124-byte header, the node table (2 counts + values), the cell table's 2 counts.
std::size_t firstCellOffset(std::size_t nodeCount) {
  return 124 + 16 + 8 * nodeCount + 16;
}

TEST(DiscregridFile, ACorruptCellTableIsAnError) {
  const std::string good = discregridBytes({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  const std::size_t nodeCount =
      DistanceGrid::nodeCount(Vector3i(2, 2, 2), GridInterpolation::CubicLagrange);
  std::string outOfRange = good;
  const std::uint32_t huge = 1000000;
  std::memcpy(&outOfRange[firstCellOffset(nodeCount)], &huge, 4);
  EXPECT_NE(errorOf(outOfRange).find("cell 0 names node 1000000 of " + std::to_string(nodeCount)),
            std::string::npos)
      << errorOf(outOfRange);
  // The first cell's corner 7 (the grid's centre, shared with the seven other cells) named as
  // its corner 0: the centre node now gets two values.
  std::string swapped = good;
  std::memcpy(&swapped[firstCellOffset(nodeCount) + 7 * 4], &good[firstCellOffset(nodeCount)], 4);
  EXPECT_NE(errorOf(swapped).find("different value"), std::string::npos) << errorOf(swapped);
}

TEST(DiscregridFile, AReducedGridIsAnErrorSayingPbdvalNeedsEveryCell) {
  std::string bytes = discregridBytes({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  const std::uint32_t discarded = 0xFFFFFFFFu;
  std::memcpy(&bytes[bytes.size() - 4], &discarded, 4);  // the last cell's map entry
  EXPECT_NE(errorOf(bytes).find("cell 7 was discarded"), std::string::npos) << errorOf(bytes);
}

TEST(DiscregridFile, ABadHeaderIsAnError) {
  std::string bytes = discregridBytes({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  const std::uint32_t zero = 0;
  std::memcpy(&bytes[48], &zero, 4);
  EXPECT_NE(errorOf(bytes).find("resolution 0: expected 1 to 512 cells per axis"),
            std::string::npos)
      << errorOf(bytes);
  bytes = discregridBytes({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  const double backwards = -1;
  std::memcpy(&bytes[24], &backwards, 8);  // max x below min x
  EXPECT_NE(errorOf(bytes).find("min < max"), std::string::npos) << errorOf(bytes);
}

TEST(DiscregridFile, TheSceneLoaderUsesTheFilesGridAndTheWriterKeepsTheFile) {
  const std::string scene = kDataDir + "/seed_reference/scenes/inline.json";
  const LoadedScene loaded = parseScene(
      R"({"RigidBodies": [{"geometryFile": "../../../../cases/models/torus.obj",
      "collisionObjectType": 5, "collisionObjectFileName": "../sdf/torus_8.csdf"}]})",
      scene);
  const CollisionObjectDesc& c = loaded.scene.rigidBodies[0].collision;
  ASSERT_TRUE(c.discregridGrid);
  EXPECT_EQ(c.resolutionSDF, Vector3i(8, 8, 8));
  EXPECT_EQ(c.fileName, "") << "other engines use the geometry";
  EXPECT_NE(c.discregridFile.find("torus_8.csdf"), std::string::npos);
  EXPECT_NE(writeSceneJson(loaded.scene).find("torus_8.csdf"), std::string::npos);
}

TEST(DiscregridFile, ADamagedGridNamesTheSceneKeyAndTheFile) {
  const std::string path = ::testing::TempDir() + "pbdval_truncated.csdf";
  {
    std::ofstream out(path, std::ios::binary);
    const std::string bytes = fileBytes(kTorusGrid);
    out << bytes.substr(0, bytes.size() / 2);
  }
  try {
    parseScene(R"({"RigidBodies": [{"geometryFile": "../../../../cases/models/torus.obj",
      "collisionObjectType": 5, "collisionObjectFileName": ")" +
                   path + R"("}]})",
               kDataDir + "/seed_reference/scenes/inline.json");
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("RigidBodies[0].collisionObjectFileName"), std::string::npos) << message;
    EXPECT_NE(message.find(path + ": Discregrid grid (.csdf): truncated"), std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace pbd
