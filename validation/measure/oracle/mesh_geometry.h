// Geometry of closed triangle meshes that FCL does not provide: convexity, inside tests
// (generalised winding number), vertex adjacency, and how far a mesh deviates from the analytic
// torus it stands for. Eigen only; used by the distance oracle.
#pragma once

#include <vector>

#include "pbd/model/mesh.h"

namespace pbdval {

/// True when every vertex lies on or behind the plane of every non-degenerate triangle, within
/// `relativeTolerance` times the diagonal of the mesh's bounding box.
bool isConvex(const pbd::TriangleMesh& mesh, double relativeTolerance = 1e-9);

/// The generalised winding number of `point` with respect to a closed, outward-oriented mesh:
/// 1 inside, 0 outside, ½ on the surface (Jacobson et al. 2013; solid angles by Van Oosterom
/// and Strackee 1983). O(triangles).
double windingNumber(const pbd::TriangleMesh& mesh, const pbd::Vector3& point);

/// For each vertex, the vertices sharing a triangle with it (sorted, without duplicates).
std::vector<std::vector<int>> vertexNeighbours(const pbd::TriangleMesh& mesh);

/// The signed distance to the seed's torus (axis y, major radius R, minor radius r).
double torusSignedDistance(const pbd::Vector3& point, double majorRadius, double minorRadius);

/// The largest |torusSignedDistance| over the vertices, edge midpoints and triangle centroids of
/// the mesh: how far the mesh deviates from the torus it represents (a lower bound on the
/// Hausdorff distance, tight for fine tessellations).
double torusDeviation(const pbd::TriangleMesh& mesh, double majorRadius, double minorRadius);

}  // namespace pbdval
