// The LineModels block (pbdval's extension, docs/scene-format.md#linemodels): every key of
// tests/data/scenes/every_key.json's two rods, lumped masses and frames against closed forms,
// the scene writer's round trip, located errors for bad values, and the warning for rod_* keys
// in a scene without rods.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/text_assertions.h"
#include "pbd/constraints/cosserat_rod.h"
#include "pbd/io/scene_loader.h"
#include "pbd/io/scene_writer.h"

namespace pbd {
namespace {

const std::string kDataDir = PBDVAL_TEST_DATA_DIR;
const std::string kInline = kDataDir + "/scenes/inline.json";
const Real kPi = Real(EIGEN_PI);

std::string errorOf(const std::string& json) {
  try {
    parseScene(json, kInline);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no SceneError)";
}

TEST(LineModels, EveryKeyAndTheParticlesAfterTheTetModels) {
  const LoadedScene loaded = loadScene(kDataDir + "/scenes/every_key.json");
  const Scene& scene = loaded.scene;
  ASSERT_EQ(scene.lineModels.size(), 2u);
  const LineModelDesc& rod = scene.lineModels[0];
  EXPECT_EQ(rod.id, 9);
  EXPECT_EQ(rod.jsonPath, "LineModels[0]");
  EXPECT_EQ(rod.firstParticle, 13);  // after the 9 cloth and 4 tet particles
  EXPECT_EQ(rod.firstSegment, 0);
  EXPECT_EQ(rod.staticParticles, (std::vector<int>{0}));
  EXPECT_EQ(rod.staticSegments, (std::vector<int>{0}));
  EXPECT_EQ(*rod.radius, Real(0.01));
  EXPECT_EQ(*rod.density, Real(7800));
  EXPECT_EQ(*rod.youngsModulus, Real(2e11));
  EXPECT_EQ(*rod.shearModulus, Real(8e10));
  EXPECT_EQ(rod.shearFactor, Real(0.9));
  EXPECT_TRUE(rod.usesModuli());
  // Lumped masses ρπr²ℓ/2 per segment end: segments of 0.5 and √0.5 m; particle 0 is static.
  const Real perLength = 7800 * kPi * Real(1e-4);
  const Real l1 = Real(0.5), l2 = std::sqrt(Real(0.5));
  EXPECT_EQ(scene.particles[13].mass, 0);
  // A few roundings of products and sums: 16 ulps.
  EXPECT_NEAR(scene.particles[14].mass, perLength * (l1 + l2) / 2, 16 * kEpsilon);
  EXPECT_NEAR(scene.particles[15].mass, perLength * l2 / 2, 16 * kEpsilon);
  // Segment 0 static (w_q = 0); segment 1: w_q = 1/(4 I), I = ½ m r², m = ρπr²ℓ.
  EXPECT_EQ(rod.segmentInverseMass(0), 0);
  EXPECT_NEAR(rod.segmentInverseMass(1) * 4 * Real(0.5) * perLength * l2 * Real(1e-4), 1,
              16 * kEpsilon);

  const LineModelDesc& helix = scene.lineModels[1];
  EXPECT_EQ(helix.firstParticle, 16);
  EXPECT_EQ(helix.firstSegment, 2);
  EXPECT_FALSE(helix.usesModuli());
  // 4 points, 1.5 turns: φ = iπ, at (3 + ½ cos φ, 4 − ½ i, 5 + ½ sin φ) (sin π rounds to 1e-16).
  ASSERT_EQ(helix.points.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const Vector3 expected(3 + Real(0.5) * std::cos(i * kPi), 4 - Real(0.5) * i, 5);
    EXPECT_LT((helix.points[std::size_t(i)] - expected).norm(), 32 * kEpsilon) << i;
    EXPECT_EQ(scene.particles[16 + std::size_t(i)].mass, 1);  // the seed's mass without density
    EXPECT_EQ(helix.segmentInverseMass(std::size_t(std::min(i, 2))), 1);
  }
  // Every frame's d₃ is its segment's tangent (a normalisation's round-off).
  for (const LineModelDesc& m : scene.lineModels)
    for (std::size_t k = 0; k < m.segmentCount(); ++k)
      EXPECT_LT(
          (rodTangentDirector(m.frames[k]) - (m.points[k + 1] - m.points[k]).normalized()).norm(),
          16 * kEpsilon);
  // The constraints: 2 + 3 stretch–shear, 1 + 2 bend–twist; the XPBD rod's moduli as EA, κGA,
  // EI, GJ (I = πr⁴/4, J = πr⁴/2), the helix with the Simulation block's rod_* fractions.
  const RodConstraints rods = rodConstraints(scene);
  ASSERT_EQ(rods.stretchShear.size(), 5u);
  ASSERT_EQ(rods.bendTwist.size(), 3u);
  const Real area = kPi * Real(1e-4), inertia = kPi * Real(1e-8) / 4;
  EXPECT_NEAR(rods.stretchShear[0].stiffness.z() / (Real(2e11) * area), 1, 16 * kEpsilon);
  EXPECT_NEAR(rods.stretchShear[0].stiffness.x() / (Real(0.9) * Real(8e10) * area), 1,
              16 * kEpsilon);
  EXPECT_NEAR(rods.bendTwist[0].stiffness.x() / (Real(2e11) * inertia), 1, 16 * kEpsilon);
  EXPECT_NEAR(rods.bendTwist[0].stiffness.z() / (Real(8e10) * 2 * inertia), 1, 16 * kEpsilon);
  EXPECT_EQ(rods.stretchShear[2].stiffness, Vector3(Real(0.8), Real(0.7), Real(0.9)));
  EXPECT_EQ(rods.bendTwist[1].stiffness, Vector3(Real(0.4), Real(0.3), Real(0.2)));
  EXPECT_FALSE(rods.bendTwist[1].xpbd);
}

TEST(LineModels, WrittenSceneLoadsToTheSameRods) {
  const Scene a = loadScene(kDataDir + "/scenes/every_key.json").scene;
  const LoadedScene b = parseScene(writeSceneJson(a), kInline);
  ASSERT_EQ(b.scene.lineModels.size(), a.lineModels.size());
  for (std::size_t m = 0; m < a.lineModels.size(); ++m) {
    const LineModelDesc& x = a.lineModels[m];
    const LineModelDesc& y = b.scene.lineModels[m];
    EXPECT_EQ(x.points, y.points);  // doubles are written with round-trip precision
    EXPECT_EQ(x.staticSegments, y.staticSegments);
    EXPECT_EQ(x.density, y.density);
    EXPECT_EQ(x.youngsModulus, y.youngsModulus);
    EXPECT_EQ(x.shearFactor, y.shearFactor);
  }
  ASSERT_EQ(b.scene.particles.size(), a.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    EXPECT_EQ(b.scene.particles[i].mass, a.particles[i].mass) << i;
}

TEST(LineModels, BadValuesAreLocatedErrors) {
  const std::pair<std::string, std::vector<std::string>> cases[] = {
      {R"({"LineModels": [{"points": [[0, 0, 0]]}]})",
       {"LineModels[0].points: expected at least 2 points"}},
      {R"({"LineModels": [{"id": 1}]})", {"LineModels[0]: missing key \"points\""}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0]], "helix": {}}]})",
       {"LineModels[0].helix: give either \"points\" or \"helix\""}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [0, 0, 0]]}]})",
       {"LineModels[0].points: segment 0", "zero length"}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0], [0, 0, 0]]}]})",
       {"LineModels[0].points: segments 0 and 1 point in opposite directions"}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0]], "staticSegments": [1]}]})",
       {"LineModels[0].staticSegments[0]: expected a segment index in [0, 0] (the model has 1 "
        "segments), got 1"}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0]], "staticParticles": [0, 2]}]})",
       {"LineModels[0].staticParticles[1]: expected a point index in [0, 1]"}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0]], "radius": 0}]})",
       {"LineModels[0].radius: expected a number > 0, got 0"}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0]], "radius": 0.1,
           "youngsModulus": 1e9}]})",
       {"LineModels[0].youngsModulus:", "\"youngsModulus\" and \"shearModulus\" go together"}},
      {R"({"LineModels": [{"points": [[0, 0, 0], [1, 0, 0]], "density": 1000}]})",
       {"LineModels[0].density:", "needs the rod's \"radius\""}},
      {R"({"LineModels": [{"helix": {"radius": 1, "pitch": 1, "turns": 2}}]})",
       {"LineModels[0].helix: missing required key \"points\""}},
      {R"({"LineModels": [{"helix": {"radius": -1, "pitch": 1, "turns": 2, "points": 5}}]})",
       {"LineModels[0].helix.radius: expected a number > 0"}},
  };
  for (const auto& [json, parts] : cases) {
    const std::string error = errorOf(json);
    for (const std::string& part : parts)
      EXPECT_NE(error.find(part), std::string::npos) << json << "\n" << error;
  }
}

TEST(LineModels, RodSettingsWithoutRodsAreIgnoredWithAWarning) {
  const LoadedScene loaded =
      parseScene(R"({"Simulation": {"rod_twistingStiffness": 0.3}})", kInline);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_EQ(loaded.warnings[0].jsonPath, "Simulation.rod_twistingStiffness");
  EXPECT_TRUE(
      pbd::test::containsAll(loaded.warnings[0].message, {"ignored: the scene has no LineModels"}));
  // With a rod: no warning, and the value is used.
  const LoadedScene used = parseScene(
      R"({"Simulation": {"rod_twistingStiffness": 0.3},
          "LineModels": [{"points": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}]})",
      kInline);
  EXPECT_TRUE(used.warnings.empty());
  EXPECT_EQ(rodConstraints(used.scene).bendTwist.at(0).stiffness.z(), Real(0.3));
}

}  // namespace
}  // namespace pbd
