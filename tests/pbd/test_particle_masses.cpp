// Particle masses of deformable models (model/mass_properties.h, io/deformable_reader.cpp): with
// a `density` the masses are lumped from the elements, so a model's mass is ρ times its area or
// volume at every refinement; without one every vertex has mass 1, as in the seed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>

#include "common/text_assertions.h"
#include "common/tolerances.h"
#include "pbd/io/scene_loader.h"
#include "pbd/model/mass_properties.h"

namespace pbd {
namespace {

namespace fs = std::filesystem;

/// A unit square in the xz plane split into n × n cells of two triangles each, as an OBJ file.
std::string squareObj(int n) {
  std::ostringstream o;
  o.precision(17);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      o << "v " << Real(i) / n << " 0 " << Real(j) / n << "\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i + 1;  // OBJ indices are 1-based
      o << "f " << a << " " << a + n + 1 << " " << a + n + 2 << "\n";
      o << "f " << a << " " << a + n + 2 << " " << a + 1 << "\n";
    }
  return o.str();
}

class ParticleMasses : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() /
                 ("pbdval-particle-masses-" +
                  std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = directory_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  LoadedScene parse(const std::string& json) {
    return parseScene(json, (directory_ / "scene.json").string(), LoadOptions{});
  }
  std::string errorOf(const std::string& json) {
    try {
      parse(json);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "(no SceneError)";
  }

  fs::path directory_;
};

Real totalMass(const Scene& scene) {
  Real mass = 0;
  for (const ParticleDesc& p : scene.particles)
    mass += p.mass;
  return mass;
}

TEST_F(ParticleMasses, ClothMassIsDensityTimesAreaAtEveryRefinement) {
  // Scaled by (2, 1, 3) the square has the area 6 m²; ρ = 0.3 kg/m²: 1.8 kg.
  for (int n : {1, 2, 4, 8}) {
    const std::string obj = write("square" + std::to_string(n) + ".obj", squareObj(n));
    const Scene seed =
        parse(R"({"TriangleModels": [{"geometryFile": ")" + obj + R"(", "scale": [2, 1, 3]}]})")
            .scene;
    const Scene dense = parse(R"({"TriangleModels": [{"geometryFile": ")" + obj +
                              R"(", "scale": [2, 1, 3], "density": 0.3}]})")
                            .scene;
    const Real vertices = Real((n + 1) * (n + 1));
    EXPECT_EQ(totalMass(seed), vertices) << n;  // the seed's rule: mass 1 each
    // Sums of O(n²) positive terms of relative round-off ε each. Precision-aware: 1e-13 is
    // 450 ε·1.8 ≥ n² ε·1.8 for n ≤ 8 in double; the same multiple of ε in float.
    EXPECT_NEAR(totalMass(dense), Real(1.8), test::roundOffBound(1e-13)) << n;
    EXPECT_EQ(dense.triangleModels[0].density, Real(0.3));
    if (n % 2 == 0) {
      // An interior vertex is in 6 triangles of area A/(2n²) each: ρ A/n² (A = 6 m²).
      const std::size_t centre = std::size_t(n / 2 * (n + 1) + n / 2);
      // Precision-aware: six terms and a product of a few roundings of 0.45 at most; 1e-15 is
      // 4.5 ε in double, the same multiple of ε in float.
      EXPECT_NEAR(dense.particles[centre].mass, Real(0.3) * 6 / (n * n), test::roundOffBound(1e-15))
          << n;
    }
  }
}

TEST_F(ParticleMasses, TetMassIsDensityTimesVolumeAndStaticParticlesStayStatic) {
  // tests/data/meshes/tet.node: the unit corner tet, volume 1/6; scaled by 2: 8/6 m³.
  const std::string data = std::string(PBDVAL_TEST_DATA_DIR) + "/meshes/";
  const Scene scene =
      parse(R"({"TetModels": [{"nodeFile": ")" + data + R"(tet.node", "eleFile": ")" + data +
            R"(tet.ele", "scale": [2, 2, 2], "density": 600,
                                "staticParticles": [3]}]})")
          .scene;
  ASSERT_EQ(scene.particles.size(), 4u);
  for (std::size_t i = 0; i < 3; ++i)  // ρ V / 4 = 600 · (8/6) / 4 = 200 kg
    EXPECT_NEAR(scene.particles[i].mass, 200, 1e-12);
  EXPECT_EQ(scene.particles[3].mass, 0);
}

TEST_F(ParticleMasses, LumpingSplitsEveryElementEqually) {
  // Independent of the loader: two triangles of areas 1/2 and 1 sharing the edge 0–1.
  TriangleMesh mesh;
  mesh.vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, -2, 0)};
  mesh.triangles = {{0, 1, 2}, {0, 3, 1}};
  const std::vector<Real> m = lumpedMasses(mesh, 3);
  EXPECT_DOUBLE_EQ(m[0], Real(1.5));  // (1/2 + 1) · 3 / 3
  EXPECT_DOUBLE_EQ(m[1], Real(1.5));
  EXPECT_DOUBLE_EQ(m[2], Real(0.5));
  EXPECT_DOUBLE_EQ(m[3], Real(1));
  // An inverted tet counts with its absolute volume.
  TetMesh tets;
  tets.vertices = {Vector3(0, 0, 0), Vector3(0, 1, 0), Vector3(1, 0, 0), Vector3(0, 0, 1)};
  tets.tetrahedra = {{0, 1, 2, 3}};
  for (Real mass : lumpedMasses(tets, 24))
    EXPECT_DOUBLE_EQ(mass, 1);  // 24 · (1/6) / 4
}

TEST_F(ParticleMasses, BadDensitiesAndVerticesWithoutElementsAreErrors) {
  const std::string obj = write("stray.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 5 5 5\nf 1 2 3\n");
  EXPECT_TRUE(test::containsAll(
      errorOf(R"({"TriangleModels": [{"geometryFile": ")" + obj + R"(", "density": 2}]})"),
      {"TriangleModels[0].density", "vertex 3 is in no element"}));
  // Without a density the stray vertex is a particle of mass 1, as in the seed.
  EXPECT_EQ(
      parse(R"({"TriangleModels": [{"geometryFile": ")" + obj + R"("}]})").scene.particles[3].mass,
      1);
  const std::string square = write("square.obj", squareObj(1));
  for (const char* bad : {"0", "-1", "\"heavy\""})
    EXPECT_TRUE(test::containsAll(errorOf(R"({"TriangleModels": [{"geometryFile": ")" + square +
                                          R"(", "density": )" + bad + "}]}"),
                                  {"TriangleModels[0].density", "expected"}))
        << bad;
}

}  // namespace
}  // namespace pbd
