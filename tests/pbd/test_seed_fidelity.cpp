// The `pbd` method's fidelity to PositionBasedDynamics 2.2.2 where the seed's behaviour is a
// rule rather than a trajectory (issue 28): the FEM solves' absolute cut-off, the damper
// joint's linear rows, the keys the seed ignores, the precision of OBJ coordinates. Each
// expectation is the stated rule of the seed's code (PositionBasedDynamics.cpp, XPBD.cpp,
// PositionBasedRigidBodyDynamics.cpp, OBJLoader.h), not an output of this library.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "pbd/constraints/fem_tet.h"
#include "pbd/constraints/fem_triangle.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"
#include "pbd/joints/damper_joint.h"
#include "pbd/joints/target_velocity_motor_slider_joint.h"
#include "pbd/model/world.h"

namespace pbd {
namespace {

const std::string kDataDir = PBDVAL_TEST_DATA_DIR;
const std::string kInline = kDataDir + "/scenes/inline.json";

// --- The FEM cut-off ----------------------------------------------------------------------------

TEST(FemCutoff, IsTheSeedsTenToTheMinusSixInThePbdMethodAndZeroInXpbd) {
  SimulationSettings settings;
  EXPECT_EQ(femCutoffFor(settings), Real(1e-6));
  settings.stepMethod = StepMethod::Xpbd;
  EXPECT_EQ(femCutoffFor(settings), Real(0));
  settings.femCutoff = Real(0.25);
  EXPECT_EQ(femCutoffFor(settings), Real(0.25));
  settings.stepMethod = StepMethod::Seed;
  EXPECT_EQ(femCutoffFor(settings), Real(0.25));
}

TEST(FemCutoff, IsReadFromTheSimulationBlockAndRejectsNegativeValues) {
  const Scene scene = parseScene(R"({"Simulation": {"femCutoff": 0}})", kInline).scene;
  EXPECT_EQ(femCutoffFor(scene.simulation), Real(0));
  EXPECT_THROW(parseScene(R"({"Simulation": {"femCutoff": -1}})", kInline), SceneError);
}

/// A right triangle with legs `leg` in the xy plane, its third vertex moved by `stretch` along x.
std::array<Vector3, 3> stretchedTriangle(Real leg, Real stretch) {
  return {Vector3(0, 0, 0), Vector3(0, leg, 0), Vector3(leg + stretch, 0, 0)};
}

FemTriangleConstraint triangleConstraint(Real leg, Real cutoff) {
  FemTriangleConstraint c;
  c.particles = {0, 1, 2};
  EXPECT_TRUE(femTriangleRest(stretchedTriangle(leg, 0), c.area, c.restInverse));
  c.stiffness = orthotropicStiffness(1, 1, 1, Real(0.3), Real(0.3));
  c.cutoff = cutoff;
  return c;
}

Real weightedNorm(const std::array<Vector3, 3>& g, const std::array<Real, 3>& w) {
  Real sum = 0;
  for (std::size_t i = 0; i < 3; ++i)
    sum += w[i] * g[i].squaredNorm();
  return sum;
}

TEST(FemCutoff, AFemTriangleWhoseWeightedGradientSumIsBelowTheCutoffIsNotCorrected) {
  // The seed's solve_FEMTriangleConstraint corrects only when |Σ w_i |∇_iC|²| > 10⁻⁶. A 1 m
  // triangle stretched by 10⁻⁴ m has |∇C| ~ A E ε / L ~ 5·10⁻⁵, far below the cut-off: no
  // correction with it, the exact PBD step without it.
  const std::array<Real, 3> w = {1, 1, 1};
  const std::array<Vector3, 3> x = stretchedTriangle(1, Real(1e-4));
  const FemTriangleConstraint seed = triangleConstraint(1, kSeedFemCutoff);
  const FemTriangleConstraint exact = triangleConstraint(1, 0);
  const Real sum = weightedNorm(femTriangleGradients(x, seed), w);
  ASSERT_GT(sum, 0);
  ASSERT_LT(sum, kSeedFemCutoff);
  for (const Vector3& d : femTrianglePbd(x, w, seed))
    EXPECT_EQ(d, Vector3::Zero());
  const std::array<Vector3, 3> g = femTriangleGradients(x, exact);
  const std::array<Vector3, 3> d = femTrianglePbd(x, w, exact);
  const Real s = femTriangleEnergy(x, exact) / sum;
  // The PBD step −s w_i ∇_iC, evaluated here from the public energy and gradients: the same
  // operations up to their order, 10 ε relative.
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_LE((d[i] + s * w[i] * g[i]).norm(), 10 * kEpsilon * (s * g[i]).norm() + 1e-300);
  EXPECT_GT(d[2].norm(), 0);
}

TEST(FemCutoff, AFemTriangleAboveTheCutoffIsCorrectedAlike) {
  // Stretched by 20 %, Σ w|∇C|² is O(10⁻²): both corrections are the same PBD step.
  const std::array<Real, 3> w = {1, 1, 1};
  const std::array<Vector3, 3> x = stretchedTriangle(1, Real(0.2));
  const FemTriangleConstraint seed = triangleConstraint(1, kSeedFemCutoff);
  const FemTriangleConstraint exact = triangleConstraint(1, 0);
  ASSERT_GT(weightedNorm(femTriangleGradients(x, seed), w), kSeedFemCutoff);
  const auto a = femTrianglePbd(x, w, seed), b = femTrianglePbd(x, w, exact);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_EQ(a[i], b[i]);
  EXPECT_GT(a[2].norm(), 0);
}

/// The unit corner tet, its apex (vertex 3) moved by `stretch` along z.
std::array<Vector3, 4> stretchedTet(Real edge, Real stretch) {
  return {Vector3(0, 0, 0), Vector3(edge, 0, 0), Vector3(0, edge, 0),
          Vector3(0, 0, edge + stretch)};
}

FemTetConstraint tetConstraint(Real edge, Real cutoff, bool xpbd, Real youngs) {
  FemTetConstraint c;
  c.particles = {0, 1, 2, 3};
  EXPECT_TRUE(femTetRestState(stretchedTet(edge, 0), c.inverseRestMatrix, c.restVolume));
  c.youngsModulus = youngs;
  c.poissonRatio = Real(0.3);
  c.xpbd = xpbd;
  c.cutoff = cutoff;
  return c;
}

TEST(FemCutoff, AFemTetBelowTheCutoffIsNotCorrectedByThePbdSolve) {
  // solve_FEMTetraConstraint returns without a correction when Σ w_i |∇_iU|² < 10⁻⁶.
  const std::array<Real, 4> w = {1, 1, 1, 1};
  const std::array<Vector3, 4> x = stretchedTet(1, Real(1e-4));
  const FemTetConstraint seed = tetConstraint(1, kSeedFemCutoff, false, 1);
  const FemTetConstraint exact = tetConstraint(1, 0, false, 1);
  const FemTetEnergy e = femTetEnergy(x, seed);
  Real sum = 0;
  for (std::size_t i = 0; i < 4; ++i)
    sum += w[i] * e.gradients[i].squaredNorm();
  ASSERT_GT(sum, 0);
  ASSERT_LT(sum, kSeedFemCutoff);
  for (const Vector3& d : femTetPbd(x, w, seed).positions)
    EXPECT_EQ(d, Vector3::Zero());
  EXPECT_GT(femTetPbd(x, w, exact).positions[3].norm(), 0);
}

TEST(FemCutoff, TheXpbdTetCutoffIncludesTheComplianceTerm) {
  // XPBD::solve_FEMTetraConstraint compares Σ w|∇U′|² + α̃ C² (U′ = U/E, C = √(2U′),
  // α̃ = 1/(E h²)) with 10⁻⁶. For E = 10⁶ and h = 1 ms, α̃ = 1 and a 10⁻⁴ strain of the unit
  // tet gives both terms ~10⁻⁹: no correction. With E = 10⁻⁵ the same strain has
  // α̃ C² ~ 10⁵ · 10⁻⁹ > 10⁻⁶: corrected.
  const std::array<Real, 4> w = {1, 1, 1, 1};
  const std::array<Vector3, 4> x = stretchedTet(1, Real(1e-4));
  const Real h = Real(1e-3);
  const FemTetCorrection stiff = femTetXpbd(x, w, tetConstraint(1, kSeedFemCutoff, true, 1e6), h);
  for (const Vector3& d : stiff.positions)
    EXPECT_EQ(d, Vector3::Zero());
  EXPECT_EQ(stiff.multiplier, 0);
  EXPECT_GT(femTetXpbd(x, w, tetConstraint(1, 0, true, 1e6), h).positions[3].norm(), 0);
  EXPECT_GT(
      femTetXpbd(x, w, tetConstraint(1, kSeedFemCutoff, true, Real(1e-5)), h).positions[3].norm(),
      0);
}

TEST(FemCutoff, TheSeedsBuilderDropsElementsWhoseRestDeterminantIsNotAboveIt) {
  // init_FEMTriangleConstraint and init_FEMTetraConstraint keep an element only when
  // |det D_m| > 10⁻⁶: a right triangle with legs 0.5 mm has |det D_m| = 2.5·10⁻⁷.
  Real area = 0;
  Eigen::Matrix<Real, 2, 2> restInverse;
  EXPECT_FALSE(
      femTriangleRest(stretchedTriangle(Real(5e-4), 0), area, restInverse, kSeedFemCutoff));
  EXPECT_TRUE(femTriangleRest(stretchedTriangle(Real(5e-4), 0), area, restInverse, 0));
  // A tet with edges 5 mm: |det D_m| = 1.25·10⁻⁷.
  Matrix3 inverse;
  Real volume = 0;
  EXPECT_FALSE(femTetRestState(stretchedTet(Real(5e-3), 0), inverse, volume, kSeedFemCutoff));
  EXPECT_TRUE(femTetRestState(stretchedTet(Real(5e-3), 0), inverse, volume, 0));
  // Edges 2 cm: 8·10⁻⁶, kept.
  EXPECT_TRUE(femTetRestState(stretchedTet(Real(2e-2), 0), inverse, volume, kSeedFemCutoff));
}

// --- The damper joint ---------------------------------------------------------------------------

/// Two unit boxes 1 m apart along x, joined by a damper along x; body 0 turned by 0.3 rad
/// about z so that body 1's centre of mass is off body 0's axis frame origin.
Scene damperScene(const char* jointModel) {
  const std::string json = std::string(R"({"Simulation": {"jointModel": ")") + jointModel +
                           R"("}, "RigidBodies": [
      {"id": 1, "collisionObjectType": 0, "mass": 1, "inertia": [1, 1, 1],
       "translation": [0, 0, 0], "angularVelocity": [0, 0, 3]},
      {"id": 2, "collisionObjectType": 0, "mass": 1, "inertia": [1, 1, 1],
       "translation": [1, 0.2, 0]}],
    "DamperJoints": [{"bodyID1": 1, "bodyID2": 2, "axis": [1, 0, 0], "stiffness": 100}]})";
  return parseScene(json, kInline).scene;
}

TEST(DamperJointModel, TheSeedsLinearRowsMoveTheCentresOfMassOnly) {
  // solve_DamperJoint's Jacobian of its three linear rows is (I, 0) for body 0 and (−I, 0) for
  // body 1, in the joint frame: no angular part.
  const Scene scene = damperScene("seed");
  const World world = buildWorld(scene);
  const DamperJoint joint(world.bodies, [&] {
    JointDesc d = scene.joints[0];
    d.model = JointModel::Seed;
    return d;
  }());
  const auto rows = joint.positionRows(world.bodies);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(rows.angular[k].topRows(3).norm(), 0) << k;
    EXPECT_NEAR(
        (rows.linear[k].topRows(3) * rows.linear[k].topRows(3).transpose() - Matrix3::Identity())
            .norm(),
        0, 10 * kEpsilon)
        << "the rows are the joint frame's three orthonormal axes";
  }
}

TEST(DamperJointModel, TheCorrectedRowsCarryTheAnchorLever) {
  // The anchor is at body 1's initial centre of mass, (1, 0.2, 0) from body 0's: the rows of
  // body 0 have the angular part n × (c₁ − x₀), not zero.
  const Scene scene = damperScene("corrected");
  const World world = buildWorld(scene);
  JointDesc d = scene.joints[0];
  d.model = JointModel::Corrected;
  const DamperJoint joint(world.bodies, d);
  const auto rows = joint.positionRows(world.bodies);
  EXPECT_GT(rows.angular[0].topRows(3).norm(), 0.5);
}

TEST(DamperJointModel, TheTwoModelsTurnASpinningFirstBodyDifferently) {
  // Zero gravity, body 0 spinning at 3 rad/s about z: the seed's linear rows exert no torque,
  // so only the rotation rows act on body 0's spin; the corrected rows add the lever's torque.
  // The two spins must differ after one step (the rows differ exactly in that torque).
  Scene seed = damperScene("seed"), corrected = damperScene("corrected");
  for (Scene* s : {&seed, &corrected})
    s->simulation.gravitation = Vector3::Zero();
  World a = buildWorld(seed), b = buildWorld(corrected);
  a.step();
  b.step();
  EXPECT_GT((a.bodies.rigid.angularVelocity[0] - b.bodies.rigid.angularVelocity[0]).norm(), 1e-6);
}

// --- The target-velocity motor slider -----------------------------------------------------------

/// A static body and a unit-inertia box (isotropic, so R I⁻¹ Rᵀ = I⁻¹ for every frame R) on a
/// velocity motor slider along `axis`, set point 0; the box spins at ω about (1, 2, 3).
World spinningSliderWorld(const char* jointModel) {
  const std::string json = std::string(R"({"Simulation": {"jointModel": ")") + jointModel +
                           R"(", "gravitation": [0, 0, 0]}, "RigidBodies": [
      {"id": 1, "collisionObjectType": 0, "isDynamic": false, "mass": 1, "inertia": [1, 1, 1],
       "translation": [0, 0, 0]},
      {"id": 2, "collisionObjectType": 0, "mass": 2, "inertia": [1, 1, 1],
       "translation": [1, 0.2, 0], "angularVelocity": [0.01, 0.02, 0.03]}],
    "TargetVelocityMotorSliderJoints": [{"bodyID1": 1, "bodyID2": 2, "axis": [0.6, 0.8, 0],
       "targetSequence": [0, 0, 1, 0]}]})";
  return buildWorld(parseScene(json, kInline).scene);
}

TEST(VelocityMotorSliderModel, TheSeedsAngularRowsTurnARelativeSpinIntoMinusThreeTimesItself) {
  // velocitySolve_TargetVelocityMotorSliderJoint: K_ang = t I⁻¹ tᵀ with t the slider's rotation
  // Jacobian, ½ R (a rotation R) while the joint's frames are aligned, so K_ang = ¼ I⁻¹ for an
  // isotropic I; λ = −K⁻¹ (ω₀ − ω₁) and Δω₁ = −I⁻¹ λ = −4 ω₁: one velocity iteration leaves
  // −3 ω₁. The corrected rows (K = I⁻¹, consistent) leave 0. Round-off: 10 ε of ω.
  for (const char* model : {"seed", "corrected"}) {
    World world = spinningSliderWorld(model);
    const Vector3 spin = world.bodies.rigid.angularVelocity[1];
    ASSERT_EQ(world.joints.size(), 1u);
    std::visit([&](auto& joint) { joint.solveVelocity(world.bodies); }, world.joints[0]);
    const Vector3 expected = std::string(model) == "seed" ? Vector3(-3 * spin) : Vector3::Zero();
    EXPECT_NEAR((world.bodies.rigid.angularVelocity[1] - expected).norm(), 0,
                10 * kEpsilon * spin.norm())
        << model;
  }
}

TEST(DamperJointModel, IsSeedInThePbdMethodAndCorrectedInXpbdUnlessTheSceneSaysSo) {
  SimulationSettings settings;
  EXPECT_EQ(jointModelFor(settings), JointModel::Seed);
  settings.stepMethod = StepMethod::Xpbd;
  EXPECT_EQ(jointModelFor(settings), JointModel::Corrected);
  settings.jointModel = JointModel::Seed;
  EXPECT_EQ(jointModelFor(settings), JointModel::Seed);
  EXPECT_THROW(parseScene(R"({"Simulation": {"jointModel": "exact"}})", kInline), SceneError);
}

// --- Keys and files the seed ignores ------------------------------------------------------------

TEST(SeedIgnoredInput, AMissingVisualFileOfATetModelIsAWarning) {
  const LoadedScene loaded = parseScene(R"({"TetModels": [{"nodeFile": "../meshes/tet.node",
      "eleFile": "../meshes/tet.ele", "visFile": "../meshes/no_such_surface.obj"}]})",
                                        kInline);
  ASSERT_EQ(loaded.scene.tetModels.size(), 1u);
  EXPECT_EQ(loaded.scene.tetModels[0].visFile, "");
  bool warned = false;
  for (const SceneDiagnostic& w : loaded.warnings)
    warned = warned || (w.jsonPath == "TetModels[0].visFile" &&
                        w.message.find("without a visual mesh") != std::string::npos);
  EXPECT_TRUE(warned);
  LoadOptions strict;
  strict.strict = true;
  EXPECT_THROW(parseScene(R"({"TetModels": [{"nodeFile": "../meshes/tet.node",
      "eleFile": "../meshes/tet.ele", "visFile": "../meshes/no_such_surface.obj"}]})",
                          kInline, strict),
               SceneError);
}

// --- OBJ precision ------------------------------------------------------------------------------

TEST(ObjPrecision, SingleReadsEachCoordinateAsStofDoes) {
  // OBJLoader::loadObj: pos[i] = stof(token) (then widened to double). 0.1 is not a float:
  // single gives the float nearest 0.1, double the double nearest.
  const std::string obj = "v 0.1 -2.7182818284590 1e-3\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const TriangleMesh single = parseObj(obj, "m.obj", ObjPrecision::Single);
  const TriangleMesh full = parseObj(obj, "m.obj", ObjPrecision::Double);
  EXPECT_EQ(single.vertices[0].x(), Real(0.1f));
  EXPECT_EQ(single.vertices[0].y(), Real(-2.7182818284590f));
  EXPECT_EQ(single.vertices[0].z(), Real(1e-3f));
  EXPECT_EQ(full.vertices[0].x(), Real(0.1));
  EXPECT_NE(Real(0.1f), Real(0.1));
  // A number that is no float (beyond its range) is an error naming the line.
  EXPECT_THROW(parseObj("v 1e300 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "m.obj", ObjPrecision::Single),
               SceneError);
}

TEST(ObjPrecision, ScenesReadSingleByDefaultAndDoubleOnRequest) {
  const std::string body =
      R"("RigidBodies": [{"id": 1, "geometryFile": "../meshes/tet_surface.obj", "collisionObjectType": 0,
          "mass": 1, "inertia": [1, 1, 1]}])";
  const Scene byDefault = parseScene("{" + body + "}", kInline).scene;
  const Scene full =
      parseScene(R"({"Simulation": {"objPrecision": "double"}, )" + body + "}", kInline).scene;
  const TriangleMesh fileSingle =
      loadObj(kDataDir + "/meshes/tet_surface.obj", ObjPrecision::Single);
  const TriangleMesh fileDouble =
      loadObj(kDataDir + "/meshes/tet_surface.obj", ObjPrecision::Double);
  EXPECT_EQ(byDefault.rigidBodies[0].mesh->vertices, fileSingle.vertices);
  EXPECT_EQ(full.rigidBodies[0].mesh->vertices, fileDouble.vertices);
  // `--set` cannot change it after the meshes were read.
  SimulationSettings settings;
  EXPECT_THROW(applySimulationSetting(settings, "objPrecision", "double", "--set"), SceneError);
}

}  // namespace
}  // namespace pbd

namespace pbd {
namespace {

// --- The seed's Gauss–Seidel order of particle constraints ---------------------------------------

TEST(SeedConstraintOrder, FemTrianglesAreSolvedGroupByGroupOfTheGreedyColouring) {
  // SimulationModel::initConstraintGroups: in list order, each constraint joins the first group
  // none of whose constraints shares a particle with it; the groups are solved in turn. The
  // expected order is that colouring, computed here from the mesh's triangle list.
  const std::string json = R"({"Simulation": {"clothSimulationMethod": 2, "clothBendingMethod": 0},
      "TriangleModels": [{"id": 0, "geometryFile": "../meshes/plane_3x3.obj"}]})";
  const Scene scene = parseScene(json, kInline).scene;
  const auto& triangles = scene.triangleModels[0].mesh.triangles;
  std::vector<std::vector<int>> groups;
  std::vector<std::vector<char>> used;
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::size_t g = 0;
    while (g < used.size() &&
           (used[g][std::size_t(triangles[t][0])] || used[g][std::size_t(triangles[t][1])] ||
            used[g][std::size_t(triangles[t][2])]))
      ++g;
    if (g == used.size()) {
      used.emplace_back(scene.particles.size(), char(0));
      groups.emplace_back();
    }
    for (int v : triangles[t])
      used[g][std::size_t(v)] = 1;
    groups[g].push_back(int(t));
  }
  std::vector<std::array<int, 3>> expected;
  for (const auto& group : groups)
    for (int t : group)
      expected.push_back(triangles[std::size_t(t)]);
  ASSERT_GT(groups.size(), 1u) << "the mesh's triangles share vertices";

  const World world = buildWorld(scene);
  ASSERT_EQ(world.constraints.femTriangles.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_EQ(world.constraints.femTriangles[k].particles, expected[k]) << k;
  // One run covers them all (one family), in that order.
  ASSERT_EQ(world.constraints.seedOrder.size(), 1u);
  EXPECT_EQ(world.constraints.seedOrder[0].begin, 0u);
  EXPECT_EQ(world.constraints.seedOrder[0].end, expected.size());

  // pbd.xpbd keeps the list order.
  Scene xpbd = scene;
  xpbd.simulation.stepMethod = StepMethod::Xpbd;
  const World listOrder = buildWorld(xpbd);
  EXPECT_TRUE(listOrder.constraints.seedOrder.empty());
  for (std::size_t k = 0; k < triangles.size(); ++k)
    EXPECT_EQ(listOrder.constraints.femTriangles[k].particles, triangles[k]) << k;
}

}  // namespace
}  // namespace pbd
