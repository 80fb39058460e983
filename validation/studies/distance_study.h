// `pbdval distance` (docs/cli.md#distance): how far the PBD library's signed-distance collision
// detection is from FCL's exact distances.
//
// Pair study. For every pair of collision shapes and N random relative poses near contact
// (exact distance within [−band/4, band]), the PBD distance is what its collision detection
// sees — the smallest signed distance of either body's surface samples (mesh vertices, the
// seed's vertex side) in the other body's SDF — and the reference is FCL's exact signed
// distance of the two shapes (validation/measure/oracle). Error = PBD − exact: positive where
// vertex sampling misses the closest features (edges, faces), negative where an SDF is
// conservative.
//
// Grid study. For a type-5 (grid SDF) shape, the SDF value at random points outside the mesh
// near its surface against FCL's exact point-to-mesh distance, at several resolutionSDF values;
// the order p of max error ∝ cellSizeᵖ is fitted by least squares on log-log.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pbd/model/scene.h"

namespace pbdval {

struct DistanceStudyOptions {
  int samples = 200;       ///< poses per pair (points per resolution for grids)
  std::uint64_t seed = 1;  ///< of the pseudo-random poses: same seed, same numbers
  double band = 0.2;       ///< m: keep poses with exact distance in [−band/4, band]
  std::vector<int> gridResolutions = {8, 16, 32, 64};
};

struct PairErrors {
  std::string shapeA, shapeB;  ///< "box", "RigidBodies[2] (sphere)", ...
  int samples = 0;
  double maxAbsError = 0, rmsError = 0, meanError = 0;  ///< m
};

struct GridErrors {
  std::string shape;
  std::vector<int> resolutions;
  std::vector<double> cellSizes;  ///< m, the largest cell edge
  std::vector<double> maxAbsErrors, rmsErrors;
  double order = 0, rSquared = 0;
  int samples = 0;
};

struct DistanceStudy {
  std::vector<PairErrors> pairs;
  std::vector<GridErrors> grids;
  std::vector<std::string> notes;  ///< shapes skipped (no FCL geometry, no samples), ...
};

/// The built-in shape set: sphere, box, cylinder, torus (analytic, with its mesh for FCL), and
/// a grid SDF of a non-convex mesh (cases/models/torus.obj), as rigid bodies at the origin.
std::vector<pbd::RigidBodyDesc> builtInShapes(const std::string& modelsFolder);

/// Every body with a collision object of the scenes.
std::vector<pbd::RigidBodyDesc> shapesOfScenes(const std::vector<pbd::Scene>& scenes);

DistanceStudy runDistanceStudy(const std::vector<pbd::RigidBodyDesc>& shapes,
                               const DistanceStudyOptions& options);

/// The study as JSON text (docs/cli.md#distance).
std::string distanceStudyJson(const DistanceStudy& study, const DistanceStudyOptions& options);

}  // namespace pbdval
