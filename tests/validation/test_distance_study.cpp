// pbdval distance: the study against what the geometry implies.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pbd/collision/surface_samples.h"
#include "validation/studies/distance_study.h"

namespace pbdval {
namespace {

std::vector<pbd::RigidBodyDesc> shapes() {
  return builtInShapes(std::string(PBDVAL_SOURCE_DIR) + "/cases/models");
}

// Two spheres of radius r, centres D apart: each SDF is exact and the surface samples lie on the
// sphere, so PBD's distance (the closest sample in the other SDF) is never below the exact
// D − 2r. A sample at angle α from the line of centres is √(D² + r² − 2Dr cos α) − r from the
// other sphere, so the error is at most √(D² + r² − 2Dr cos α) − (D − r) for the largest
// angular gap α between a direction and its nearest sample (computed here by brute force over
// random directions), largest at the smallest D of the study's band, D = 2r − band/4.
TEST(DistanceStudy, SphereSamplingErrorIsBoundedByTheSampleGap) {
  const pbd::RigidBodyDesc sphere = shapes()[0];
  ASSERT_EQ(sphere.collision.type, pbd::CollisionObjectType::Sphere);
  const double r = sphere.collision.scale.x();
  const std::vector<pbd::Vector3> samples = pbd::surfaceSamples(sphere);
  std::mt19937_64 random(7);
  std::normal_distribution<double> n(0, 1);
  double largestGap = 0;
  for (int k = 0; k < 20000; ++k) {
    const pbd::Vector3 d = pbd::Vector3(n(random), n(random), n(random)).normalized();
    double best = -1;
    for (const pbd::Vector3& s : samples)
      best = std::max(best, double(d.dot(s.normalized())));
    largestGap = std::max(largestGap, std::acos(std::min(1.0, best)));
  }
  DistanceStudyOptions options;
  options.samples = 100;
  options.gridResolutions = {};
  const DistanceStudy study = runDistanceStudy({sphere}, options);
  ASSERT_EQ(study.pairs.size(), 1u);
  const PairErrors& e = study.pairs[0];
  EXPECT_EQ(e.samples, 100);
  // The brute-force search may miss the largest gap by a little: 5 % on α.
  const double alpha = 1.05 * largestGap, d = 2 * r - options.band / 4;
  const double bound = std::sqrt(d * d + r * r - 2 * d * r * std::cos(alpha)) - (d - r);
  EXPECT_LE(e.maxAbsError, bound);
  EXPECT_GE(e.meanError, 0);  // an upper bound, never below the exact distance
}

// A grid SDF of a mesh converges to the mesh's exact distance as the cells shrink (at least
// first order: the mesh distance has kinks along its edges), and the fit says so. Cells must be
// smaller than the facets (≈ 0.08 m here) to be asymptotic: resolutions 16 to 64.
TEST(DistanceStudy, GridErrorFallsWithResolution) {
  DistanceStudyOptions options;
  options.samples = 80;
  options.gridResolutions = {16, 32, 64};
  const DistanceStudy study = runDistanceStudy({shapes()[4]}, options);
  ASSERT_EQ(study.grids.size(), 1u);
  const GridErrors& g = study.grids[0];
  EXPECT_EQ(g.samples, 80);
  EXPECT_GT(g.maxAbsErrors[0], g.maxAbsErrors[2]);
  EXPECT_GT(g.order, 0.9);
}

TEST(DistanceStudy, SameSeedSameNumbers) {
  DistanceStudyOptions options;
  options.samples = 20;
  options.gridResolutions = {};
  const auto all = shapes();
  const std::vector<pbd::RigidBodyDesc> two = {all[1], all[2]};
  const DistanceStudy a = runDistanceStudy(two, options), b = runDistanceStudy(two, options);
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t k = 0; k < a.pairs.size(); ++k)
    EXPECT_EQ(a.pairs[k].maxAbsError, b.pairs[k].maxAbsError);
}

}  // namespace
}  // namespace pbdval
