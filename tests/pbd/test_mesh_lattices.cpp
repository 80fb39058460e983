// The generated meshes of pbd/model/mesh.h: tetLattice (Kuhn tets) and triangleGrid. Checked
// against the box they fill: every tet positive with a sixth of its cell's volume, the volumes
// summing to the box's, the mesh conforming (its boundary is exactly the box's surface, two
// triangles per boundary square: an unmatched interior face would add boundary triangles), and the
// sheet's area and orientation.
#include <gtest/gtest.h>

#include <set>

#include "pbd/model/mesh.h"

namespace pbd {
namespace {

Real signedVolume(const TetMesh& mesh, const std::array<int, 4>& t) {
  const auto at = [&](int k) { return mesh.vertices[std::size_t(t[std::size_t(k)])]; };
  return (at(1) - at(0)).cross(at(2) - at(0)).dot(at(3) - at(0)) / 6;
}

TEST(TetLattice, FillsItsBoxWithPositiveConformingKuhnTets) {
  // Steps 0.5, −0.25, 0.125 (dyadic: positions and products are exact), one negative.
  const int nx = 4, ny = 3, nz = 5;
  const Vector3 step(0.5, -0.25, 0.125), origin(1, 2, 3);
  const TetMesh mesh = tetLattice(nx, ny, nz, step, origin);
  const int cx = nx - 1, cy = ny - 1, cz = nz - 1;
  ASSERT_EQ(mesh.vertices.size(), std::size_t(nx * ny * nz));
  ASSERT_EQ(mesh.tetrahedra.size(), std::size_t(6 * cx * cy * cz));
  EXPECT_EQ(mesh.vertices[std::size_t((2 * ny + 1) * nx + 3)], origin + Vector3(1.5, -0.25, 0.25));
  const Real cell = std::abs(step.x() * step.y() * step.z());
  Real total = 0;
  for (const auto& t : mesh.tetrahedra) {
    const Real v = signedVolume(mesh, t);
    EXPECT_EQ(v, cell / 6);  // every Kuhn tet is a sixth of its cube (one rounding each side)
    total += v;
  }
  // A sum of n = 144 terms of cell / 6 (not dyadic): at most n roundings of the running sum.
  EXPECT_NEAR(total, cell * cx * cy * cz, Real(mesh.tetrahedra.size()) * kEpsilon * total);
  EXPECT_EQ(boundaryFaces(mesh).size(), std::size_t(4 * (cx * cy + cy * cz + cz * cx)));
  // Every boundary triangle lies on one of the six faces of the box.
  for (const auto& f : boundaryFaces(mesh)) {
    bool onAFace = false;
    for (int axis = 0; axis < 3; ++axis)
      for (Real side : {origin[axis], mesh.vertices.back()[axis]}) {
        bool all = true;
        for (int v : f)
          all = all && mesh.vertices[std::size_t(v)][axis] == side;
        onAFace = onAFace || all;
      }
    EXPECT_TRUE(onAFace);
  }
}

TEST(TriangleGrid, IsAnUpwardFacingSheetOfTheGivenSize) {
  const TriangleMesh mesh = triangleGrid(5, 3, Real(0.25), Vector3(0, 1, 0));
  ASSERT_EQ(mesh.vertices.size(), 15u);
  ASSERT_EQ(mesh.triangles.size(), std::size_t(2 * 4 * 2));
  Real area = 0;
  for (const auto& t : mesh.triangles) {
    const Vector3 a = mesh.vertices[std::size_t(t[0])], b = mesh.vertices[std::size_t(t[1])],
                  c = mesh.vertices[std::size_t(t[2])];
    const Vector3 n = (b - a).cross(c - a);
    EXPECT_GT(n.y(), 0);
    EXPECT_EQ(n.x(), 0);
    EXPECT_EQ(n.z(), 0);
    area += n.norm() / 2;
  }
  EXPECT_EQ(area, Real(1.0 * 0.5));  // 4 × 2 cells of 0.25 m
  EXPECT_EQ(uniqueEdges(mesh.triangles).size(), std::size_t(4 * 3 + 2 * 5 + 4 * 2));
}

}  // namespace
}  // namespace pbd
