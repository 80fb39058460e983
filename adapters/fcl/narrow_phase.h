// Internal to the distance oracle (includes FCL): the signed distance of two placed geometries,
// choosing FCL's most exact routine for the pair (docs/fcl-oracle.md, "Algorithms").
#pragma once

#include "adapters/fcl/fcl_geometry.h"

namespace pbdval::fcl_oracle {

/// A body's geometry and the pose of its geometry frame in the world.
struct PlacedBody {
  const BodyGeometry& body;
  fcl::Transform3d pose;
};

/// Both bodies must have a geometry. Throws std::runtime_error when FCL fails on the pair
/// (after the MPR fallback for convex pairs).
PairDistance pairDistance(const PlacedBody& a, const PlacedBody& b, double gjkTolerance);

}  // namespace pbdval::fcl_oracle
