// Indexed meshes as loaded from files (OBJ surfaces, TetGen volumes).
#pragma once

#include <array>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

/// A triangle surface. Triangles are counter-clockwise seen from outside for closed meshes.
/// How OBJ vertex coordinates are read. PositionBasedDynamics 2.2.2 parses them with `stof`
/// (single precision, correctly rounded) and widens them to double: `Single` reproduces that
/// (the scene loader's default, `Simulation.objPrecision`); `Double` keeps every digit.
enum class ObjPrecision { Single, Double };

const char* objPrecisionName(ObjPrecision precision);

struct TriangleMesh {
  std::vector<Vector3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// A tetrahedral volume mesh (TetGen .node/.ele), zero-based indices.
struct TetMesh {
  std::vector<Vector3> vertices;
  std::vector<std::array<int, 4>> tetrahedra;
};

/// Every edge of the elements once, in the order it first appears, a pair's first appearance
/// fixing its orientation — the order of the seed's meshes: per triangle its sides
/// (t₀, t₁), (t₁, t₂), (t₂, t₀) (IndexedFaceMesh), per tet the vertex pairs (tᵢ, tⱼ) with i < j
/// (IndexedTetMesh).
std::vector<std::array<int, 2>> uniqueEdges(const std::vector<std::array<int, 3>>& triangles);
std::vector<std::array<int, 2>> uniqueEdges(const std::vector<std::array<int, 4>>& tetrahedra);

/// The bending stencil of an interior edge: the edge's vertices, then the opposite vertex of each
/// of its two triangles (in the order the triangles are listed).
struct EdgeStencil {
  std::array<int, 2> edge;
  std::array<int, 2> opposite;
};

/// One stencil per edge shared by exactly two triangles, edges in the order they first appear
/// (border edges and non-manifold edges, shared by three or more, have none).
std::vector<EdgeStencil> interiorEdgeStencils(const TriangleMesh& mesh);

/// The faces of a tet mesh that belong to one tet only, each turned outwards (its normal points
/// away from its tet's fourth vertex), in tet order; vertices index the tet mesh's.
std::vector<std::array<int, 3>> boundaryFaces(const TetMesh& mesh);

/// A point carried by a tet: x = Σ weights[i] · x_{tet[i]}.
struct BarycentricAttachment {
  int tet = -1;
  std::array<Real, 4> weights{0, 0, 0, 0};
};

/// Each point attached to the tet of `mesh` that contains it, or, outside the mesh, to the tet
/// it is least outside of (the largest smallest barycentric coordinate; the weights then
/// extrapolate). Degenerate tets are skipped; an empty result means the mesh has no usable tet.
/// O(points × tets).
std::vector<BarycentricAttachment> attachToTets(const TetMesh& mesh,
                                                const std::vector<Vector3>& points);

/// The barycentric coordinates of `point` in the tet (x₀, x₁, x₂, x₃); false when degenerate.
bool tetBarycentric(const std::array<Vector3, 4>& tet, const Vector3& point,
                    std::array<Real, 4>& weights);

/// A box of nx × ny × nz vertices at origin + (i step.x, j step.y, k step.z), vertex
/// (i, j, k) at index (k ny + j) nx + i, each cell split into the six Kuhn tets around its
/// diagonal from (i, j, k) to (i+1, j+1, k+1) (the paths along the three axes in every order),
/// each listed with positive volume. The same split in every cell makes the mesh conforming
/// (neighbouring cells share their face diagonals). A step component may be negative. (The
/// seed's BarDemo builds its bar in code too.) Requires nx, ny, nz ≥ 2.
TetMesh tetLattice(int nx, int ny, int nz, const Vector3& step,
                   const Vector3& origin = Vector3::Zero());

/// A flat sheet of nx × nz vertices at origin + (i spacing, 0, k spacing), vertex (i, k) at
/// index k nx + i, each cell split into two triangles facing +y. Requires nx, nz ≥ 2.
TriangleMesh triangleGrid(int nx, int nz, Real spacing, const Vector3& origin = Vector3::Zero());

}  // namespace pbd
