// Particle-model measurements (validation/measure/deformation.h) against closed forms: a uniformly
// scaled cloth stretches every edge by the scale, a scaled solid changes every tet's volume by its
// cube, the XPBD constraints' energy is ½ k C² of those, a symmetric fold's isometric bending
// energy is ½ k ((6/d) sin²(φ/2))², and computeMetrics reports them for a run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engines/selftest_engine.h"
#include "tests/validation/fixtures.h"
#include "validation/measure/deformation.h"
#include "validation/measure/mechanics.h"
#include "validation/measure/metrics.h"
#include "validation/run/case_spec.h"

namespace pbdval {
namespace {

// A 2 × 2-cell cloth (9 vertices, 8 triangles, 16 edges: 6 of length 0.5, 6 of 0.5 and 4
// diagonals of 0.5√2) in the xz plane, and a unit cube of 5 tets, both with free particles of
// mass 1 (no gravity).
pbd::Scene clothAndCube(int clothMethod, int solidMethod) {
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  pbd::TriangleModelDesc cloth;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      cloth.mesh.vertices.push_back(Vector3(0.5 * i, 0, 0.5 * j));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      cloth.mesh.triangles.push_back({a, a + 3, a + 4});
      cloth.mesh.triangles.push_back({a, a + 4, a + 1});
    }
  cloth.firstParticle = 0;
  scene.triangleModels.push_back(cloth);
  pbd::TetModelDesc cube;
  for (int k = 0; k < 8; ++k)
    cube.mesh.vertices.push_back(Vector3(k & 1, (k >> 1) & 1, (k >> 2) & 1) + Vector3(5, 0, 0));
  // The cube's corner tets around the central tet (0, 3, 5, 6), each positively oriented.
  cube.mesh.tetrahedra = {{0, 1, 3, 5}, {0, 3, 2, 6}, {0, 5, 6, 4}, {3, 6, 5, 7}, {0, 3, 6, 5}};
  cube.firstParticle = 9;
  scene.tetModels.push_back(cube);
  for (const auto& v : cloth.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  for (const auto& v : cube.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.clothSimulationMethod = clothMethod;
  scene.simulation.solidSimulationMethod = solidMethod;
  scene.simulation.clothBendingMethod = 0;
  return scene;
}

/// The initial state with every particle scaled by `s` about its model's first vertex.
State scaled(const pbd::Scene& scene, double s) {
  State state = initialState(scene);
  const Vector3 clothOrigin = scene.particles[0].position, cubeOrigin = scene.particles[9].position;
  for (std::size_t i = 0; i < state.particles.size(); ++i) {
    const Vector3 origin = i < 9 ? clothOrigin : cubeOrigin;
    state.particles[i].position = origin + s * (state.particles[i].position - origin);
  }
  return state;
}

TEST(Deformation, SignedTetVolumeOfTheCubesTetsSumsToOne) {
  const pbd::Scene scene = clothAndCube(0, 0);
  double total = 0;
  for (const auto& t : scene.tetModels[0].mesh.tetrahedra) {
    const auto x = [&](int i) { return scene.tetModels[0].mesh.vertices[std::size_t(i)]; };
    const double v = signedTetVolume(x(t[0]), x(t[1]), x(t[2]), x(t[3]));
    EXPECT_GT(v, 0);
    total += v;
  }
  EXPECT_NEAR(total, 1, 1e-15);  // 4 · 1/6 + 1/3
}

TEST(Deformation, UniformScalingStretchesEveryEdgeAndCubesEveryVolume) {
  const pbd::Scene scene = clothAndCube(0, 0);
  const RestShape rest(scene);
  const RestShape::Measures atRest = rest.measure(initialState(scene));
  EXPECT_EQ(atRest.stretchMax, 0);
  EXPECT_EQ(atRest.tetVolumeErrorMax, 0);
  const double s = 1.01;
  const RestShape::Measures m = rest.measure(scaled(scene, s));
  // 16 cloth edges + the cube's 18 (12 sides, 6 face diagonals); each stretched by s − 1.
  EXPECT_EQ(m.edges, 34u);
  EXPECT_NEAR(m.stretchMax, s - 1, 1e-14);  // ratios of O(1) lengths: round-off ~10⁻¹⁶
  EXPECT_NEAR(std::sqrt(m.stretchSumOfSquares / double(m.edges)), s - 1, 1e-14);
  EXPECT_NEAR(m.tetVolumeErrorMax, s * s * s - 1, 1e-14);
  EXPECT_NEAR(m.solidVolumeErrorMax, s * s * s - 1, 1e-14);
  // A state without the models' particles is an error, not a silent 0.
  State none = initialState(scene);
  none.particles.resize(5);
  EXPECT_THROW(rest.measure(none), std::invalid_argument);
}

TEST(Deformation, ElasticEnergyIsHalfKTimesTheSquaredConstraints) {
  const double s = 1.02;
  // PBD methods (1): no energy.
  {
    const pbd::Scene scene = clothAndCube(1, 1);
    const ElasticEnergy elastic(scene);
    EXPECT_FALSE(elastic.defined());
    EXPECT_TRUE(elastic.hasPbdConstraints());
    EXPECT_EQ(elastic.of(scaled(scene, s)), 0);
  }
  // XPBD (cloth 4, solid 6) with distinct stiffnesses per family.
  pbd::Scene scene = clothAndCube(4, 6);
  scene.simulation.cloth_stiffness = 300;
  scene.simulation.solid_stiffness = 500;
  scene.simulation.solid_volumeStiffness = 7000;
  const ElasticEnergy elastic(scene);
  EXPECT_TRUE(elastic.defined());
  EXPECT_FALSE(elastic.hasPbdConstraints());
  EXPECT_EQ(elastic.of(initialState(scene)), 0);
  State partial = initialState(scene);
  partial.particles.resize(3);
  EXPECT_THROW(elastic.of(partial), std::invalid_argument);
  // Σ ℓ₀²: cloth 12 · 0.25 + 4 · 0.5 = 5; cube 12 · 1 + 6 · 2 = 24. Tets: 4 of 1/6, 1 of 1/3.
  const double e = s - 1, v = s * s * s - 1;
  const double expected =
      0.5 * 300 * e * e * 5 + 0.5 * 500 * e * e * 24 + 0.5 * 7000 * v * v * (4.0 / 36 + 1.0 / 9);
  EXPECT_NEAR(elastic.of(scaled(scene, s)), expected, 1e-12 * expected);
  EXPECT_NEAR(energyOf(scene, scaled(scene, s)).elastic, expected, 1e-12 * expected);
}

TEST(Deformation, IsometricBendingEnergyOfASymmetricFold) {
  // Two triangles over the edge (0,0,0)–(1,0,0), opposite vertices at d over the foot (0.4,0,0);
  // C = (6/d) sin²(φ/2) (tests/pbd/test_isometric_bending.cpp), energy ½ k C².
  const double d = 0.7, phi = 0.9, k = 40;
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  pbd::TriangleModelDesc hinge;
  hinge.mesh.vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0.4, d, 0),
                         Vector3(0.4, -d, 0)};
  hinge.mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
  scene.triangleModels.push_back(hinge);
  for (std::size_t i = 0; i < 4; ++i)
    scene.particles.push_back({hinge.mesh.vertices[i], Vector3::Zero(), i < 2 ? 0.0 : 1.0});
  scene.simulation.clothSimulationMethod = 4;
  scene.simulation.clothBendingMethod = 3;
  scene.simulation.cloth_bendingStiffness = k;
  scene.simulation.cloth_stiffness = 1;  // the fold keeps every edge length: no stretch energy
  State folded = initialState(scene);
  folded.particles[2].position = Vector3(0.4, d * std::cos(phi / 2), d * std::sin(phi / 2));
  folded.particles[3].position = Vector3(0.4, -d * std::cos(phi / 2), d * std::sin(phi / 2));
  const double c = 6 / d * std::pow(std::sin(phi / 2), 2);
  EXPECT_NEAR(ElasticEnergy(scene).of(folded), 0.5 * k * c * c, 1e-12);
}

TEST(Deformation, XpbdFemTetEnergyIsTheStVenantKirchhoffEnergy) {
  // One tet of solidSimulationMethod 3 stretched along x by 1 + e: ε = diag(a, 0, 0) with
  // a = ((1 + e)² − 1)/2, so U = V₀ (μ a² + ½ λ a²) = V₀ (λ + 2μ) a² / 2.
  pbd::Scene scene = test::emptyScene(Vector3::Zero());
  pbd::TetModelDesc tet;
  tet.mesh.vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1)};
  tet.mesh.tetrahedra = {{0, 1, 2, 3}};
  scene.tetModels.push_back(tet);
  for (const auto& v : tet.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.simulation.solidSimulationMethod = 3;
  scene.simulation.solid_stiffness = 5000;
  scene.simulation.solid_poissonRatio = 0.25;
  const ElasticEnergy elastic(scene);
  EXPECT_TRUE(elastic.defined());
  State stretched = initialState(scene);
  const double e = 0.03;
  for (ParticleState& p : stretched.particles)
    p.position.x() *= 1 + e;
  const double mu = 5000 / (2 * 1.25), lambda = 5000 * 0.25 / (1.25 * 0.5);
  const double a = ((1 + e) * (1 + e) - 1) / 2;
  const double expected = (1.0 / 6) * (lambda + 2 * mu) * a * a / 2;
  EXPECT_NEAR(elastic.of(stretched), expected, 1e-12 * expected);  // a few products: round-off
  // A rigid motion stores nothing.
  State moved = initialState(scene);
  const Quaternion q = test::turn(Vector3(1, 2, 3), 0.8);
  for (ParticleState& p : moved.particles)
    p.position = q * p.position + Vector3(1, 2, 3);
  EXPECT_LT(elastic.of(moved), 1e-20);
  // Method 2 (PBD FEM) defines no energy.
  scene.simulation.solidSimulationMethod = 2;
  EXPECT_FALSE(ElasticEnergy(scene).defined());
  EXPECT_TRUE(ElasticEnergy(scene).hasPbdConstraints());
}

TEST(Deformation, ComputeMetricsReportsStretchAndVolume) {
  const pbd::Scene scene = clothAndCube(4, 6);
  const std::vector<State> samples = {initialState(scene), scaled(scene, 1.03),
                                      scaled(scene, 0.99)};
  MetricInputs in;
  in.scene = &scene;
  const CaseSpec spec;
  in.spec = &spec;
  in.samples = &samples;
  const MetricSet m = computeMetrics(in);
  EXPECT_NEAR(m.values.at(metric::kParticleStretchMax), 0.03, 1e-14);
  // RMS over 3 samples × 34 edges of strains 0, 0.03, −0.01.
  EXPECT_NEAR(m.values.at(metric::kParticleStretchRms), std::sqrt((0.03 * 0.03 + 0.01 * 0.01) / 3),
              1e-14);
  EXPECT_NEAR(m.values.at(metric::kTetVolumeErrorMax), std::pow(1.03, 3) - 1, 1e-14);
  EXPECT_NEAR(m.values.at(metric::kSolidVolumeErrorMax), std::pow(1.03, 3) - 1, 1e-14);
  // Without particles read back: no deformation metrics, and a note.
  std::vector<State> bare = samples;
  for (State& s : bare)
    s.particles.clear();
  in.samples = &bare;
  const MetricSet without = computeMetrics(in);
  EXPECT_EQ(without.values.count(metric::kParticleStretchMax), 0u);
}

}  // namespace
}  // namespace pbdval

namespace pbdval {
namespace {

// particle_penetration_max: a static sphere (r = 0.5, centre (0, −1, 0), turned and placed by
// its pose) below the cloth; cloth vertex 4 pushed 0.2 m into it, vertex 0 onto its surface.
TEST(Deformation, ParticlePenetrationIsTheDeepestVertexBelowARigidSurface) {
  pbd::Scene scene = clothAndCube(4, 6);
  pbd::RigidBodyDesc sphere;
  sphere.id = 7;
  sphere.isDynamic = false;
  sphere.translation = Vector3(0, -1, 0);
  sphere.collision.type = pbd::CollisionObjectType::Sphere;
  sphere.collision.scale = Vector3(0.5, 0.5, 0.5);
  scene.rigidBodies.push_back(sphere);
  std::vector<State> samples = {initialState(scene), initialState(scene)};
  // The sample's pose moves the sphere's scene frame: centre at (1, −1, 2).
  samples[1].bodies[0].position = Vector3(1, -1, 2);
  samples[1].bodies[0].rotation = test::turn(Vector3(1, 1, 0), 0.4);
  samples[1].particles[4].position = Vector3(1, -1, 2) + Vector3(0, 0.3, 0);  // 0.2 inside
  samples[1].particles[0].position = Vector3(1, -1, 2) + Vector3(0.5, 0, 0);  // on the surface
  MetricInputs in;
  in.scene = &scene;
  const CaseSpec spec;
  in.spec = &spec;
  in.samples = &samples;
  const MetricSet m = computeMetrics(in);
  // |x − c| − r = 0.3 − 0.5 exactly representable up to one rounding of the pose.
  EXPECT_NEAR(m.values.at(metric::kParticlePenetrationMax), 0.2, 1e-14);
  // Nothing inside: 0.
  samples.pop_back();
  EXPECT_EQ(computeMetrics(in).values.at(metric::kParticlePenetrationMax), 0);
}

// solid_penetration_max: a second unit cube of 5 tets overlapping the first; its vertex 0 moved
// to (5.9, 0.5, 0.45) inside the first cube ([5, 6] × [0, 1]²): 0.1 from the face x = 6.
TEST(Deformation, SolidPenetrationIsTheDeepestVertexInsideAnotherSolid) {
  pbd::Scene scene = clothAndCube(4, 6);
  pbd::TetModelDesc second = scene.tetModels[0];
  second.firstParticle = static_cast<int>(scene.particles.size());
  for (Vector3& v : second.mesh.vertices)
    v += Vector3(3, 0, 0);  // at x ∈ [8, 9]: apart
  for (const Vector3& v : second.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  scene.tetModels.push_back(second);
  std::vector<State> samples = {initialState(scene)};
  MetricInputs in;
  in.scene = &scene;
  const CaseSpec spec;
  in.spec = &spec;
  in.samples = &samples;
  EXPECT_EQ(computeMetrics(in).values.at(metric::kSolidPenetrationMax), 0);  // apart
  samples.push_back(initialState(scene));
  samples[1].particles[std::size_t(second.firstParticle)].position = Vector3(5.9, 0.5, 0.45);
  // The distance to the face x = 6, a few roundings.
  EXPECT_NEAR(computeMetrics(in).values.at(metric::kSolidPenetrationMax), 0.1, 1e-14);
}

// Cosserat rods: each segment is an edge of the stretch measure (a rod stretched uniformly by
// 2 % has every |ℓ/ℓ₀ − 1| = 0.02), a PBD rod defines no elastic energy, an XPBD rod's is the
// rods' own (tests/validation/test_rod_energy.cpp), not the cloth and solid constraints'.
TEST(Deformation, RodSegmentsAreEdgesAndOnlyXpbdRodsDefineEnergy) {
  for (bool xpbd : {false, true}) {
    pbd::Scene scene = test::emptyScene(Vector3::Zero());
    pbd::LineModelDesc rod;
    rod.points = {Vector3(0, 0, 0), Vector3(0.5, 0, 0), Vector3(0.5, 0.25, 0), Vector3(1, 1, 1)};
    rod.staticParticles = {0};
    if (xpbd) {
      rod.radius = 0.01;
      rod.youngsModulus = 1e9;
      rod.shearModulus = 4e8;
    }
    pbd::appendLineModel(scene, rod);
    State state = initialState(scene);
    for (auto& p : state.particles)
      p.position *= 1.02;  // about the static first point
    const RestShape rest(scene);
    const RestShape::Measures m = rest.measure(state);
    EXPECT_EQ(m.edges, 3u);
    EXPECT_NEAR(m.stretchMax, 0.02, 1e-14);  // 0.02 up to the round-off of lengths ~1
    const ElasticEnergy energy(scene);
    EXPECT_FALSE(energy.defined());
    EXPECT_EQ(energy.hasPbdConstraints(), !xpbd);
    EXPECT_EQ(energy.hasXpbdRods(), xpbd);
  }
}

}  // namespace
}  // namespace pbdval

namespace pbdval {
namespace {

// Validation.staticDisplacement: the region picks particles by their initial positions, the
// metric is the mean of (x − x₀)·d over them and over the samples from `from` on.
pbd::Scene withStaticDisplacement(const std::string& block) {
  pbd::Scene scene = clothAndCube(4, 6);
  scene.sourceFile = "case.json";
  scene.validationJson = R"({"duration": 1, "staticDisplacement": )" + block + "}";
  return scene;
}

TEST(StaticDisplacement, IsTheMeanDisplacementOfTheRegionFromItsStartTime) {
  // The cube's top face y = 1 (4 particles); direction −y given unnormalised.
  const pbd::Scene scene = withStaticDisplacement(
      R"({"region": {"min": [4, 0.9, -1], "max": [7, 1.1, 2]}, "direction": [0, -2, 0],
          "from": 0.4, "expected": 0.01})");
  const CaseSpec spec = parseCaseSpec(scene, testRegistry());
  ASSERT_TRUE(spec.staticDisplacement);
  EXPECT_EQ(spec.staticDisplacement->particles, (std::vector<int>{9 + 2, 9 + 3, 9 + 6, 9 + 7}));
  // Samples at t = 0, 0.5, 1: the top face 0.3 m down at t = 0 (before `from`, ignored), then
  // 0.008 m and 0.014 m down: mean 0.011 m (closed form), error |0.011 − 0.01| / 0.01 = 0.1.
  std::vector<State> samples;
  for (auto [t, down] : {std::pair{0.0, 0.3}, {0.5, 0.008}, {1.0, 0.014}}) {
    State s = initialState(scene);
    s.time = t;
    for (int i : spec.staticDisplacement->particles)
      s.particles[std::size_t(i)].position.y() -= down;
    samples.push_back(s);
  }
  MetricInputs in;
  in.scene = &scene;
  in.spec = &spec;
  in.samples = &samples;
  const MetricSet m = computeMetrics(in);
  // Sums of a few doubles: round-off ~1e-17 m.
  EXPECT_NEAR(m.values.at(metric::kStaticDisplacement), 0.011, 1e-15);
  EXPECT_NEAR(m.values.at(metric::kStaticDisplacementError), 0.1, 1e-12);
  // No particles read back: absent, with a note.
  for (State& s : samples)
    s.particles.clear();
  const MetricSet bare = computeMetrics(in);
  EXPECT_EQ(bare.values.count(metric::kStaticDisplacement), 0u);
  EXPECT_NE(bare.notes.end(),
            std::find_if(bare.notes.begin(), bare.notes.end(), [](const std::string& n) {
              return n.find("static_displacement") != std::string::npos;
            }));
}

TEST(StaticDisplacement, BadBlocksNameThePathAndWhatWasExpected) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"region": {"min": [10, 10, 10], "max": [11, 11, 11]}, "direction": [0, -1, 0], "from": 0, "expected": 1})",
       "Validation.staticDisplacement.region: expected a box holding at least one particle"},
      {R"({"region": {"min": [1, 0, 0], "max": [0, 1, 1]}, "direction": [0, -1, 0], "from": 0, "expected": 1})",
       "region: expected min ≤ max"},
      {R"({"region": {"min": [-1, -1, -1], "max": [9, 9, 9]}, "direction": [0, 0, 0], "from": 0, "expected": 1})",
       "direction: expected a non-zero vector"},
      {R"({"region": {"min": [-1, -1, -1], "max": [9, 9, 9]}, "direction": [0, 1, 0], "from": 1, "expected": 1})",
       "from: expected a time in [0, 1) s"},
      {R"({"region": {"min": [-1, -1, -1], "max": [9, 9, 9]}, "direction": [0, 1, 0], "from": 0, "expected": 0})",
       "expected: expected a non-zero displacement"},
      {R"({"region": {"min": [-1, -1, -1], "max": [9, 9, 9]}, "direction": [0, 1, 0], "from": 0, "expected": 1, "tip": 2})",
       "Validation.staticDisplacement.tip: unknown key"},
  };
  for (const auto& [block, message] : cases) {
    try {
      parseCaseSpec(withStaticDisplacement(block), testRegistry());
      ADD_FAILURE() << "accepted " << block;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("case.json"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pbdval

namespace pbdval {
namespace {

TEST(ParticleTrajectoryError, IsTheDistanceToTheReferencesParticles) {
  // Particles only (no bodies): the run's particles at sample 1 moved 0.03 m along x and 0.04 m
  // along y from the reference's (distance 0.05 m, closed form), sample 0 identical: max 0.05 m,
  // RMS over 2 samples × 17 particles √(0.05² / 2).
  const pbd::Scene scene = clothAndCube(4, 6);
  ReferenceTrajectory reference;
  reference.description = "engine";
  reference.samples = {initialState(scene), initialState(scene)};
  reference.samples[1].time = 0.1;
  std::vector<State> samples = reference.samples;
  for (ParticleState& p : samples[1].particles)
    p.position += Vector3(0.03, 0.04, 0);
  const CaseSpec spec;
  MetricInputs in;
  in.scene = &scene;
  in.spec = &spec;
  in.samples = &samples;
  in.reference = &reference;
  const MetricSet m = computeMetrics(in);
  // A few roundings of 0.03, 0.04 and their squares: ~1e-17 m.
  EXPECT_NEAR(m.values.at(metric::kParticleTrajectoryErrorMax), 0.05, 1e-15);
  EXPECT_NEAR(m.values.at(metric::kParticleTrajectoryErrorRms), 0.05 / std::sqrt(2.0), 1e-15);
  EXPECT_EQ(m.values.count(metric::kTrajectoryErrorMax), 0u);  // no bodies to compare
  // A reference without particles (an analytic model): no particle metric, a note.
  for (State& s : reference.samples)
    s.particles.clear();
  const MetricSet without = computeMetrics(in);
  EXPECT_EQ(without.values.count(metric::kParticleTrajectoryErrorMax), 0u);
  EXPECT_NE(without.notes.end(),
            std::find_if(without.notes.begin(), without.notes.end(), [](const std::string& n) {
              return n.find("particle_trajectory_error") != std::string::npos;
            }));
}

}  // namespace
}  // namespace pbdval
