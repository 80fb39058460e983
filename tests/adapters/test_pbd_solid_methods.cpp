// The pbd engine's coverage of tet models: the seed's solid methods (0 to 6) all run, an
// unknown one (7) is reported unsupported naming the model, and FEM (2, 3) with a Poisson
// ratio outside the seed's [0, 0.49] is reported rather than silently accepted.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "adapters/pbd/pbd_engine.h"
#include "engines/selftest_engine.h"

namespace pbdval::test {
namespace {

pbd::Scene oneTetScene(int method) {
  pbd::Scene scene;
  scene.simulation.solidSimulationMethod = method;
  pbd::TetModelDesc solid;
  solid.jsonPath = "TetModels[0]";
  solid.mesh.vertices = {pbd::Vector3(0, 0, 0), pbd::Vector3(1, 0, 0), pbd::Vector3(0, 1, 0),
                         pbd::Vector3(0, 0, 1)};
  solid.mesh.tetrahedra = {{0, 1, 2, 3}};
  scene.tetModels.push_back(solid);
  for (const pbd::Vector3& v : solid.mesh.vertices)
    scene.particles.push_back({v, pbd::Vector3::Zero(), 1});
  return scene;
}

TEST(PbdSolidMethods, SeedSolidMethodsRunAndUnknownOnesAreReported) {
  PbdEngine engine;
  const Method& method = testRegistry().resolve("pbd");
  for (int solid : {0, 1, 2, 3, 4, 5, 6, 7}) {
    const std::vector<std::string> missing = engine.unsupported(oneTetScene(solid), method);
    if (solid == 7) {
      ASSERT_EQ(missing.size(), 1u) << solid;
      EXPECT_NE(missing[0].find("TetModels[0]"), std::string::npos);
      EXPECT_NE(missing[0].find("solidSimulationMethod " + std::to_string(solid)),
                std::string::npos);
    } else {
      EXPECT_TRUE(missing.empty()) << solid;
    }
  }
  engine.load(oneTetScene(3), method);
  EXPECT_EQ(engine.world().constraints.femTets.size(), 1u);
  engine.load(oneTetScene(4), method);
  EXPECT_EQ(engine.world().constraints.strainTets.size(), 1u);
  engine.load(oneTetScene(5), method);
  EXPECT_EQ(engine.world().constraints.shapeMatching.size(), 1u);
}

TEST(PbdSolidMethods, FemPoissonRatioOutsideTheSeedsRangeIsReported) {
  PbdEngine engine;
  const Method& method = testRegistry().resolve("pbd");
  for (int solid : {2, 3}) {
    pbd::Scene scene = oneTetScene(solid);
    scene.simulation.solid_poissonRatio = pbd::Real(0.5);
    const std::vector<std::string> missing = engine.unsupported(scene, method);
    ASSERT_EQ(missing.size(), 1u) << solid;
    EXPECT_EQ(missing[0],
              "TetModels[0]: FEM solid (solidSimulationMethod 2 or 3) with solid_poissonRatio "
              "outside [0, 0.49] [solid_poissonRatio 0.5]: the seed's FEM solve returns false for "
              "such a ν");
    scene.simulation.solid_poissonRatio = pbd::Real(0.49);
    EXPECT_TRUE(engine.unsupported(scene, method).empty()) << solid;
  }
  // Distances and volumes (method 1) do not use ν.
  pbd::Scene distances = oneTetScene(1);
  distances.simulation.solid_poissonRatio = pbd::Real(0.5);
  EXPECT_TRUE(engine.unsupported(distances, method).empty());
}

}  // namespace
}  // namespace pbdval::test
