// The order in which PositionBasedDynamics 2.2.2 (the seed) reports the contacts of one body's
// mesh vertices against another body's SDF (docs/seed.md#vertex-trees), reproduced so that the
// `seed` contact model solves its contacts in the seed's Gauss–Seidel order.
//
// The seed walks a kd-tree of the vertices depth first, first child first, and reports the
// contacts of each leaf in the leaf's order. The leaves partition the tree's index list in
// order, so the report order is the tree's final index list:
//   1. vertices as the seed holds them: the OBJ read in single precision, times `scale`;
//   2. its principal frame: Mirtich's volume integration of that mesh (the seed's
//      VolumeIntegration, same operation order: the frame of a body with equal principal
//      moments — a sphere, a cube — is decided by round-off, so only the same arithmetic gives
//      the same frame), eigenvectors of the inertia tensor (Eigen's SelfAdjointEigenSolver,
//      negated if left-handed), composed with the body's initial rotation;
//   3. the vertices in that frame, relative to the centre of mass;
//   4. the kd-tree: the indices 0…n−1; a cell of more than 10 points is sorted (std::sort)
//      along the longest side of the cell's box and halved at n/2; the two child cells are the
//      box split at the mid-point of the two middle coordinates (the root cell is the points'
//      bounding box).
// rank[v] is vertex v's position in that list: contacts of one direction sorted by rank come
// out in the seed's order. (Pruning by bounding spheres drops no contact, so it does not
// change the order.) The particles of a cloth or a solid are reported the same way, by a
// kd-tree over their world positions at the start (step 4 alone: the seed's PointCloudBSH of a
// particle model is built once, when its collision object is added, and only refitted after).
#pragma once

#include <vector>

#include "pbd/math/types.h"
#include "pbd/model/mesh.h"

namespace pbd {

/// The seed's report rank of every vertex of `scaledMesh` (the body's mesh after `scale`,
/// scene frame), for a body of `density` with initial pose (`translation`, `rotation`).
std::vector<int> seedVertexReportRank(const TriangleMesh& scaledMesh, const Vector3& scale,
                                      const Vector3& translation, const Quaternion& rotation,
                                      Real density);

/// The seed's report rank of a particle model's particles, from their positions when the model's
/// collision object was made (the scene's start: the seed builds the kd-tree of step 4 over them
/// once and only refits it as the particles move).
std::vector<int> seedPointReportRank(const std::vector<Vector3>& points);

}  // namespace pbd
