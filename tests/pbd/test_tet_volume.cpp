// Tet volume constraints (constraints/tet_volume.h), PBD and XPBD: the gradients against
// central differences, the rest state in either orientation (the seed's |V₀| bug), rigid-motion
// invariance and momentum; in the world: an apex on a static base held by the volume constraint
// alone settles at the closed-form compression 9 m g/(k A²) (XPBD) or
// (1 − k)ⁿ g h_s²/(1 − (1 − k)ⁿ) (PBD, iteration-dependent); the constraints a tet model gets
// from solidSimulationMethod.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/tolerances.h"
#include "pbd/constraints/tet_volume.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const std::array<Vector3, 4> kTet = {Vector3(0.1, -0.2, 0.3), Vector3(1.2, 0.1, -0.1),
                                     Vector3(0.3, 0.9, 0.2), Vector3(0.2, 0.1, 1.1)};

TEST(TetVolume, GradientsMatchCentralDifferences) {
  const std::array<Vector3, 4> g = tetVolumeGradients(kTet);
  const Real h = test::finiteDifferenceStep();
  for (std::size_t i = 0; i < 4; ++i)
    for (int axis = 0; axis < 3; ++axis) {
      std::array<Vector3, 4> plus = kTet, minus = kTet;
      plus[i](axis) += h;
      minus[i](axis) -= h;
      const Real numeric = (signedTetVolume(plus) - signedTetVolume(minus)) / (2 * h);
      EXPECT_NEAR(numeric, g[i](axis), test::finiteDifferenceTolerance()) << i << " " << axis;
    }
  // The gradients sum to zero (translation invariance): exactly up to round-off.
  EXPECT_LT((g[0] + g[1] + g[2] + g[3]).norm(), 10 * kEpsilon);
}

TEST(TetVolume, RestStateInEitherOrientationHasNoCorrection) {
  // Swapping two vertices flips the orientation: V₀ < 0. The seed's |V₀| would give C = −2|V₀|;
  // the signed rest volume gives C = 0 and no correction.
  std::array<Vector3, 4> flipped = kTet;
  std::swap(flipped[1], flipped[2]);
  const std::array<Real, 4> w = {1, 2, Real(0.5), 1};
  for (const auto& tet : {kTet, flipped}) {
    const Real rest = signedTetVolume(tet);
    const TetVolumeCorrection pbd = tetVolumePbd(tet, w, rest, 1);
    const TetVolumeCorrection xpbd = tetVolumeXpbd(tet, w, rest, 1e4, 1e-3, 0);
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(pbd.positions[i], Vector3::Zero());
      EXPECT_EQ(xpbd.positions[i], Vector3::Zero());
    }
  }
  EXPECT_LT(signedTetVolume(flipped), 0);
}

TEST(TetVolume, RigidMotionsAndMomentum) {
  const Quaternion q(AngleAxis(0.8, Vector3(1, 1, -2).normalized()));
  const Vector3 t(-2, 3, 1);
  std::array<Vector3, 4> moved;
  for (std::size_t i = 0; i < 4; ++i)
    moved[i] = q * kTet[i] + t;
  // Round-off of a triple product of O(1) coordinates: a few ε.
  EXPECT_NEAR(signedTetVolume(moved), signedTetVolume(kTet), 20 * kEpsilon);
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  const Real rest = Real(0.8) * signedTetVolume(kTet);  // compressed by a fifth
  for (const TetVolumeCorrection& c :
       {tetVolumePbd(kTet, w, rest, 0.7), tetVolumeXpbd(kTet, w, rest, 1e5, 1e-2, 0)}) {
    Vector3 momentum = Vector3::Zero();
    for (std::size_t i = 0; i < 4; ++i)
      momentum += c.positions[i] / w[i];
    EXPECT_LT(momentum.norm(), 20 * kEpsilon);  // Σ m_i Δp_i = 0: the gradients sum to zero
    EXPECT_GT(c.positions[1].norm(), 1e-3);
  }
  // One PBD projection with k = 1 restores the volume to first order: the residual is the
  // second-order term of V along the correction (small against the initial error 0.2 V).
  const TetVolumeCorrection exact = tetVolumePbd(kTet, w, rest, 1);
  std::array<Vector3, 4> projected;
  for (std::size_t i = 0; i < 4; ++i)
    projected[i] = kTet[i] + exact.positions[i];
  EXPECT_LT(std::abs(signedTetVolume(projected) - rest),
            0.05 * std::abs(0.2 * signedTetVolume(kTet)));
}

// The seed's solve_VolumeConstraint (PBD and XPBD) takes C = V − |V₀| but the cross products
// 6 ∇V as its gradients (docs/seed.md, "Volume constraint scale"). Its corrections are therefore
// those of the ∇V projection with C ∇C / Σ w |∇C|² scaled by ⅙ (PBD), and with
// Σ w |6∇V|² + α̃ in the XPBD denominator: both computed here from tetVolumeGradients
// (checked against central differences above).
TEST(TetVolume, SeedFormIsTheProjectionOfSixTimesTheGradients) {
  const std::array<Real, 4> w = {1, 2, Real(0.5), Real(0.25)};
  const Real rest = Real(0.8) * signedTetVolume(kTet);  // compressed by a fifth
  EXPECT_EQ(seedRestTetVolume(kTet), std::abs(signedTetVolume(kTet)));
  const std::array<Vector3, 4> g = tetVolumeGradients(kTet);
  Real sum = 0;  // Σ w |∇V|²
  for (std::size_t i = 0; i < 4; ++i)
    sum += w[i] * g[i].squaredNorm();
  const Real c = signedTetVolume(kTet) - rest;
  const TetVolumeCorrection pbd = seedTetVolumePbd(kTet, w, rest, Real(0.7), Real(1e-6));
  const Real stiffness = 1e5, h = 1e-2, lambda = Real(3e-4), compliance = 1 / (stiffness * h * h);
  const TetVolumeCorrection xpbd =
      seedTetVolumeXpbd(kTet, w, rest, stiffness, h, lambda, Real(1e-6));
  const Real expectedMultiplier = -(c + compliance * lambda) / (36 * sum + compliance);
  // Round-off of a few dozen O(1) operations, relative.
  EXPECT_NEAR(xpbd.multiplier, expectedMultiplier, 100 * kEpsilon * std::abs(expectedMultiplier));
  for (std::size_t i = 0; i < 4; ++i) {
    const Vector3 pbdExpected = -Real(0.7) * c / (6 * sum) * w[i] * g[i];
    const Vector3 xpbdExpected = 6 * expectedMultiplier * w[i] * g[i];
    EXPECT_LT((pbd.positions[i] - pbdExpected).norm(), 100 * kEpsilon * pbdExpected.norm()) << i;
    EXPECT_LT((xpbd.positions[i] - xpbdExpected).norm(), 100 * kEpsilon * xpbdExpected.norm()) << i;
  }
  // A tet listed with negative orientation: its rest volume is |V₀|, so at rest it starts at
  // C = −2|V₀| and is pushed towards inversion (docs/seed.md#tet-orientation).
  std::array<Vector3, 4> flipped = kTet;
  std::swap(flipped[1], flipped[2]);
  const TetVolumeCorrection inverted =
      seedTetVolumePbd(flipped, w, seedRestTetVolume(flipped), 1, Real(1e-6));
  std::array<Vector3, 4> moved;
  for (std::size_t i = 0; i < 4; ++i)
    moved[i] = flipped[i] + inverted.positions[i];
  EXPECT_GT(signedTetVolume(moved), signedTetVolume(flipped));  // towards +|V₀|
  // Below the cut-off nothing moves: every particle static.
  const TetVolumeCorrection none = seedTetVolumePbd(kTet, {0, 0, 0, 0}, rest, 1, Real(1e-6));
  for (const Vector3& d : none.positions)
    EXPECT_EQ(d, Vector3::Zero());
}

TEST(TetVolumeWorld, PbdMethodKeepsTetsOfStaticParticlesAsTheSeedDoes) {
  // Two tets sharing a face; the first's four particles static. The seed keeps its constraint
  // (it moves nothing, but takes a colour group and so decides the solve order): the `pbd`
  // method too (femCutoff unset: the seed's form), pbdval's form (femCutoff 0) leaves it out.
  Scene scene;
  TetModelDesc solid;
  solid.mesh.vertices = {Vector3(0, 0, 0), Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1),
                         Vector3(1, 1, 1)};
  solid.mesh.tetrahedra = {{0, 1, 2, 3}, {1, 3, 2, 4}};
  scene.tetModels.push_back(solid);
  for (std::size_t i = 0; i < solid.mesh.vertices.size(); ++i)
    scene.particles.push_back({solid.mesh.vertices[i], Vector3::Zero(), i < 4 ? Real(0) : 1});
  for (int method : {1, 6}) {
    scene.simulation.solidSimulationMethod = method;
    scene.simulation.femCutoff.reset();
    const World seed = buildWorld(scene);
    ASSERT_EQ(seed.constraints.tetVolumes.size(), 2u) << method;
    for (const TetVolumeConstraint& c : seed.constraints.tetVolumes)
      EXPECT_GT(c.restVolume, 0);  // |V₀|, whatever the orientation ({1, 3, 2, 4} is negative)
    scene.simulation.femCutoff = Real(0);
    const World own = buildWorld(scene);
    ASSERT_EQ(own.constraints.tetVolumes.size(), 1u) << method;
    EXPECT_LT(own.constraints.tetVolumes[0].restVolume, 0);  // signed
  }
}

// A tet with a static base (right triangle of legs 1 in the xz-plane, area A = ½) and an apex of
// mass m at height 1, gravity along −y, the volume constraint alone.
World apexOnBase(bool xpbd, Real stiffness, int iterations, bool seedForm = false) {
  Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = iterations;
  scene.particles.push_back({Vector3(0, 0, 0), Vector3::Zero(), 0});
  scene.particles.push_back({Vector3(1, 0, 0), Vector3::Zero(), 0});
  scene.particles.push_back({Vector3(0, 0, 1), Vector3::Zero(), 0});
  scene.particles.push_back({Vector3(0.2, 1, 0.2), Vector3::Zero(), 1});
  World world = buildWorld(scene);
  TetVolumeConstraint c;
  c.particles = {0, 1, 2, 3};
  c.restVolume = signedTetVolume({scene.particles[0].position, scene.particles[1].position,
                                  scene.particles[2].position, scene.particles[3].position});
  c.xpbd = xpbd;
  c.stiffness = stiffness;
  if (seedForm) {
    // The seed's form: |V₀| (listed with positive orientation, so C = 0 at rest), 6 ∇V.
    c.particles = {0, 2, 1, 3};
    c.restVolume = seedRestTetVolume({scene.particles[0].position, scene.particles[2].position,
                                      scene.particles[1].position, scene.particles[3].position});
    c.cutoff = kSeedFemCutoff;
  }
  world.constraints.tetVolumes.push_back(c);
  return world;
}

Real meanCompression(World& world, Real from, Real to) {
  Real sum = 0;
  int count = 0;
  while (world.time < to) {
    world.step();
    if (world.time > from) {
      sum += 1 - world.bodies.particles.position[3].y();
      ++count;
    }
  }
  return sum / count;
}

TEST(TetVolumeWorld, XpbdCompressionIsTheClosedFormAndPbdsIsSetByIterations) {
  // XPBD: k C ∇C = m g with C = (A/3) Δh, |∇C| = A/3: Δh = 9 m g/(k A²) = 35.3 mm for
  // k = 10⁴ N/m⁵; ω = (A/3)√(k/m) = 16.7 rad/s. The mean over 3 s (eight periods, lightly
  // damped) is the static value within the window's share of a partial period: 1 % allowed.
  const Real g = Real(9.81), area = Real(0.5), k = Real(1e4);
  const Real expected = 9 * g / (k * area * area);
  for (int iterations : {1, 8}) {
    World world = apexOnBase(true, k, iterations);
    const Real measured = meanCompression(world, 0, 3);
    std::printf("  XPBD tet apex, %d iterations: compression %.6g m (9 m g/(k A^2) = %.6g m)\n",
                iterations, double(measured), double(expected));
    EXPECT_NEAR(measured, expected, 0.01 * expected);
  }
  // PBD, k = 0.5: C is linear in the apex height, so each iteration keeps (1 − k) of the error
  // the prediction adds (g h_s² per substep): (1 − k)ⁿ g h_s²/(1 − (1 − k)ⁿ), as for a distance.
  const Real substep = Real(0.001);
  for (int iterations : {1, 8}) {
    const Real kept = std::pow(Real(0.5), Real(iterations));
    const Real closed = kept * g * substep * substep / (1 - kept);
    // Double-only (the last case; everything above has run): with eight iterations the
    // compression is g h_s²/255 = 3.8e-8 m at an apex height of 1 m, a third of float's ulp
    // there (1.2e-7 m), so 1 − y rounds to 0 in float.
    if (sizeof(Real) < 8 && iterations == 8)
      GTEST_SKIP() << "needs double precision: the 8-iteration compression g h^2/255 = 3.8e-8 m "
                      "is below float's ulp of 1.2e-7 m at the 1 m apex height";
    World world = apexOnBase(false, Real(0.5), iterations);
    const Real measured = meanCompression(world, 0.5, 1);
    std::printf("  PBD tet apex, k = 0.5, %d iterations: compression %.6g m (closed form %.6g m)\n",
                iterations, double(measured), double(closed));
    EXPECT_NEAR(measured, closed, 0.01 * closed);
  }
}

TEST(TetVolumeWorld, SeedFormActsAsSixTimesTheXpbdStiffnessAndASixthOfThePbdStep) {
  // The seed's XPBD form: at rest the correction 6 w |∇C| |Δλ| of each substep, with
  // Δλ = −C/(36 w |∇C|² + α̃), |∇C| = A/3, m = 1, must undo the prediction's g h_s², so
  // C = g h_s² (36 |∇C|² + α̃)/(6 |∇C|) and the compression is 9 m g/(6 k A²) + 6 g h_s²
  // (5.945 mm for k = 10⁴ N/m⁵, h_s = 1 ms): k acts as 6k (its force −6 k C ∇C is that of
  // ½ (6k) C²). The mean over 3 s, as above: 1 %.
  const Real g = Real(9.81), area = Real(0.5), k = Real(1e4), substep = Real(0.001);
  const Real expected = 9 * g / (6 * k * area * area) + 6 * g * substep * substep;
  World xpbd = apexOnBase(true, k, 1, true);
  const Real measured = meanCompression(xpbd, 0, 3);
  std::printf(
      "  seed-form XPBD tet apex: compression %.6g m (9 m g/(6 k A^2) + 6 g h^2 = %.6g m)\n",
      double(measured), double(expected));
  EXPECT_NEAR(measured, expected, 0.01 * expected);
  // The seed's PBD step is ⅙ of the projection: each iteration keeps (1 − k/6) of the error,
  // so the apex settles at (1 − k/6) g h_s²/(1 − (1 − k/6)) with one iteration, 11 g h_s² for
  // k = ½ (C is linear in the apex height, as above).
  const Real kept = 1 - Real(0.5) / 6;
  const Real closed = kept * g * substep * substep / (1 - kept);
  World pbd = apexOnBase(false, Real(0.5), 1, true);
  const Real settled = meanCompression(pbd, 2, 3);
  std::printf("  seed-form PBD tet apex, k = 0.5: compression %.6g m (closed form %.6g m)\n",
              double(settled), double(closed));
  EXPECT_NEAR(settled, closed, 0.01 * closed);
}

TEST(TetVolumeWorld, SolidsGetEdgeAndVolumeConstraintsFromTheirMethod) {
  // A unit cube of five tets: 12 cube edges and 6 face diagonals, 5 volumes.
  Scene scene;
  TetModelDesc solid;
  for (int k = 0; k < 8; ++k)
    solid.mesh.vertices.push_back(Vector3(Real(k & 1), Real((k >> 1) & 1), Real((k >> 2) & 1)));
  solid.mesh.tetrahedra = {{0, 1, 2, 4}, {1, 3, 2, 7}, {1, 4, 5, 7}, {2, 4, 7, 6}, {1, 2, 4, 7}};
  scene.tetModels.push_back(solid);
  for (const Vector3& v : solid.mesh.vertices)
    scene.particles.push_back({v, Vector3::Zero(), 1});
  for (int method : {0, 1, 2, 3, 4, 5, 6}) {
    scene.simulation.solidSimulationMethod = method;
    const World world = buildWorld(scene);
    const bool made = method == 1 || method == 6;
    ASSERT_EQ(world.constraints.particleDistances.size(), made ? 18u : 0u) << method;
    ASSERT_EQ(world.constraints.tetVolumes.size(), made ? 5u : 0u) << method;
    Real volume = 0;
    for (const TetVolumeConstraint& c : world.constraints.tetVolumes) {
      EXPECT_EQ(c.xpbd, method == 6);
      EXPECT_EQ(c.stiffness, method == 6 ? Real(1e5) : Real(1));  // the seed's forced values
      volume += std::abs(c.restVolume);
    }
    if (made) {
      EXPECT_NEAR(volume, 1, 10 * kEpsilon);  // the five tets fill the unit cube
    }
    for (const ParticleDistanceConstraint& c : world.constraints.particleDistances)
      EXPECT_EQ(c.stiffness, method == 6 ? Real(1e5) : Real(1));
  }
  // The cube stands on its own static bottom face: a step keeps its volume (no load but
  // gravity on the top four, 1 kg each, against 10⁵-stiff constraints). pbdval's form
  // (femCutoff 0; the seed's is SeedFormIsTheProjectionOfSixTimesTheGradients').
  for (int i = 0; i < 8; ++i)
    if (((i >> 1) & 1) == 0) scene.particles[std::size_t(i)].mass = 0;
  scene.simulation.solidSimulationMethod = 6;
  scene.simulation.femCutoff = Real(0);
  World world = buildWorld(scene);
  Real worst = 0;
  while (world.time < 1) {
    world.step();
    Real volume = 0;
    for (const TetVolumeConstraint& c : world.constraints.tetVolumes) {
      std::array<Vector3, 4> p;
      for (std::size_t i = 0; i < 4; ++i)
        p[i] = world.bodies.particles.position[std::size_t(c.particles[i])];
      volume += signedTetVolume(p) * (c.restVolume < 0 ? -1 : 1);
    }
    worst = std::max(worst, std::abs(volume - 1));
  }
  std::printf("  XPBD cube of 5 tets under its own weight: largest volume change %.3g\n",
              double(worst));
  // The load is 4 × 9.81 N on a unit face against edge and volume stiffness 10⁵: a compression
  // of order 40/10⁵ = 4·10⁻⁴ (twice that in the first swing); 10⁻² allowed.
  EXPECT_LT(worst, 1e-2);
}

}  // namespace
}  // namespace pbd
