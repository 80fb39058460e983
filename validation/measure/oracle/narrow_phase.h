// Internal to the distance oracle (includes FCL): the signed distance of two placed geometries,
// choosing FCL's most exact routine for the pair (docs/fcl-oracle.md, "Algorithms").
#pragma once

#include "validation/measure/oracle/fcl_geometry.h"

namespace pbdval::fcl_oracle {

/// A body's geometry and the pose of its geometry frame in the world.
struct PlacedBody {
  const BodyGeometry& body;
  fcl::Transform3d pose;
};

/// Both bodies must have a geometry.
PairDistance pairDistance(const PlacedBody& a, const PlacedBody& b,
                          const DistanceOracleOptions& tolerances);

}  // namespace pbdval::fcl_oracle
