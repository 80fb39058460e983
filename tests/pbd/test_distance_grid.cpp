// Grid signed distance fields (type 5): the exact mesh distance they are sampled from, the
// Catmull-Rom interpolation and its order, and the on-disk cache (corrupt files are rebuilt).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "pbd/collision/analytic_shapes.h"
#include "pbd/collision/collision_shape.h"
#include "pbd/collision/distance_grid.h"
#include "pbd/collision/grid_cache.h"
#include "pbd/collision/mesh_distance.h"
#include "pbd/io/mesh_loader.h"

namespace pbd {
namespace {

namespace fs = std::filesystem;

const std::string kModels = std::string(PBDVAL_SOURCE_DIR) + "/cases/models/";

std::vector<Vector3> randomPoints(int count, const Vector3& low, const Vector3& high,
                                  unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vector3> points;
  for (int i = 0; i < count; ++i) {
    Vector3 p;
    for (int axis = 0; axis < 3; ++axis)
      p(axis) = low(axis) + Real(unit(random)) * (high(axis) - low(axis));
    points.push_back(p);
  }
  return points;
}

/// Least-squares slope of log(error) against log(1/cells).
double fittedOrder(const std::vector<int>& cells, const std::vector<double>& errors) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const double x = std::log(double(cells[i])), y = -std::log(errors[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// A scratch folder, removed at the end of the test.
struct TemporaryFolder {
  fs::path path;
  explicit TemporaryFolder(const std::string& name)
      : path(fs::temp_directory_path() /
             ("pbdval-test-" + name + "-" + std::to_string(::getpid()))) {
    fs::remove_all(path);
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

// --- Exact mesh distance ----------------------------------------------------------------------

// The unit cube mesh is the box [−½, ½]³ exactly, so its distance is the analytic box SDF
// (distinct formulas: closest triangle + pseudonormal sign vs. the box formula). Both are a
// few operations on O(1) numbers: agreement to 64 ε.
TEST(MeshDistance, CubeMeshIsTheAnalyticBox) {
  const MeshDistance cube(loadObj(kModels + "cube.obj"));
  for (const Vector3& p : randomPoints(2000, Vector3::Constant(-2), Vector3::Constant(2), 1)) {
    EXPECT_NEAR(cube.signedDistance(p), sdf::box(p, Vector3::Constant(Real(0.5))).distance,
                64 * kEpsilon)
        << p.transpose();
  }
  // Exactly on vertices, edges and faces, and at the centre.
  EXPECT_NEAR(cube.signedDistance(Vector3::Constant(Real(0.5))), 0, 4 * kEpsilon);
  EXPECT_NEAR(cube.signedDistance(Vector3(Real(0.5), Real(0.5), 0)), 0, 4 * kEpsilon);
  EXPECT_NEAR(cube.signedDistance(Vector3(Real(0.5), 0, Real(0.1))), 0, 4 * kEpsilon);
  EXPECT_NEAR(cube.signedDistance(Vector3::Zero()), Real(-0.5), 4 * kEpsilon);
}

// The icosphere is inscribed in the unit ball. Its surface lies within the Hausdorff distance
// H = 1 − min over faces of (distance of the face's plane from the origin) of the sphere, and
// signed distances to two nested convex surfaces differ by at most H.
TEST(MeshDistance, IcosphereIsWithinItsSagOfTheSphere) {
  const TriangleMesh mesh = loadObj(kModels + "sphere.obj");
  Real nearestPlane = 1;
  for (const auto& t : mesh.triangles) {
    const Vector3 &a = mesh.vertices[std::size_t(t[0])], &b = mesh.vertices[std::size_t(t[1])],
                  &c = mesh.vertices[std::size_t(t[2])];
    nearestPlane = std::min(nearestPlane, (b - a).cross(c - a).normalized().dot(a));
  }
  const Real sag = 1 - nearestPlane;
  const MeshDistance icosphere(mesh);
  Real worst = 0;
  for (const Vector3& p : randomPoints(2000, Vector3::Constant(-2), Vector3::Constant(2), 2)) {
    const Real error = std::abs(icosphere.signedDistance(p) - sdf::sphere(p, 1).distance);
    worst = std::max(worst, error);
    EXPECT_LE(error, sag + 64 * kEpsilon) << p.transpose();
  }
  std::printf("  icosphere (642 vertices): sag %.3e, max |mesh - sphere| %.3e\n", double(sag),
              double(worst));
}

// --- Catmull-Rom interpolation -----------------------------------------------------------------

// Catmull-Rom reproduces quadratics exactly (Keys 1981), in every direction of the tensor
// product: the only error is round-off of a 64-term sum of O(10) values.
TEST(DistanceGrid, ReproducesQuadraticsExactly) {
  auto quadratic = [](const Vector3& x) {
    return 1 + x.x() - 2 * x.y() + Real(0.5) * x.z() + x.x() * x.x() - x.y() * x.z() +
           3 * x.z() * x.z();
  };
  const DistanceGrid grid =
      DistanceGrid::sample(Vector3(-1, 0, -2), Vector3(1, 1, 0), Vector3i(5, 3, 7), quadratic);
  for (const Vector3& p : randomPoints(500, Vector3(-1, 0, -2), Vector3(1, 1, 0), 3)) {
    const DistanceSample s = grid.evaluate(p);
    EXPECT_NEAR(s.distance, quadratic(p), 1024 * kEpsilon);
    const Vector3 exactGradient(1 + 2 * p.x(), -2 - p.z(), Real(0.5) - p.y() + 6 * p.z());
    EXPECT_LE((s.gradient - exactGradient).norm(), 1024 * kEpsilon * 10);
  }
}

// For a smooth field the interpolation error is O(Δ³) and the gradient's O(Δ²). The field: the
// distance to a sphere whose centre lies outside the domain (so it is smooth there). Fitted
// orders must be those of the interpolant within ±0.3 (the error constants vary a little with
// the resolution: the maxima sit at different points).
/// Fitted orders (value, gradient) of a grid of `interpolation` on the smooth field of the
/// order tests: the distance to a sphere whose centre lies outside the unit cube.
std::pair<double, double> smoothFieldOrders(GridInterpolation interpolation,
                                            const std::vector<int>& cells) {
  const Vector3 centre(-1, Real(-0.5), Real(-0.8));
  auto field = [&](const Vector3& x) { return (x - centre).norm() - Real(0.7); };
  const std::vector<Vector3> points = randomPoints(4000, Vector3::Zero(), Vector3::Ones(), 4);
  std::vector<double> valueErrors, gradientErrors;
  for (int n : cells) {
    const DistanceGrid grid = DistanceGrid::sample(Vector3::Zero(), Vector3::Ones(),
                                                   Vector3i::Constant(n), field, interpolation);
    double value = 0, gradient = 0;
    for (const Vector3& p : points) {
      const DistanceSample s = grid.evaluate(p);
      value = std::max(value, double(std::abs(s.distance - field(p))));
      gradient = std::max(gradient, double((s.gradient - (p - centre).normalized()).norm()));
    }
    valueErrors.push_back(value);
    gradientErrors.push_back(gradient);
    std::printf("  %s, smooth field, %2d cells: max value error %.3e, max gradient error %.3e\n",
                gridInterpolationName(interpolation), n, value, gradient);
  }
  return {fittedOrder(cells, valueErrors), fittedOrder(cells, gradientErrors)};
}

TEST(DistanceGrid, InterpolationErrorFallsAtTheOrderOfTheInterpolant) {
  if (sizeof(Real) < 8) GTEST_SKIP() << "the finest errors are below float round-off";
  const auto [valueOrder, gradientOrder] =
      smoothFieldOrders(GridInterpolation::CatmullRom, {8, 16, 32, 64});
  std::printf("  fitted orders: value %.2f (Catmull-Rom: 3), gradient %.2f (2)\n", valueOrder,
              gradientOrder);
  EXPECT_NEAR(valueOrder, 3, 0.3);
  EXPECT_NEAR(gradientOrder, 2, 0.3);
}

// --- Cubic Lagrange interpolation (the seed's) --------------------------------------------------

// The 32-node serendipity element spans every complete cubic polynomial (Zienkiewicz & Taylor,
// vol. 1, §8.7), so a cubic field, the mixed term xyz included, is reproduced exactly in value
// and gradient: the only error is round-off of a 32-term sum of O(10) values.
TEST(CubicLagrangeGrid, ReproducesCubicsExactly) {
  auto cubic = [](const Vector3& x) {
    return 1 + x.x() - 2 * x.y() + x.x() * x.x() - x.y() * x.z() + x.x() * x.y() * x.z() +
           2 * x.x() * x.x() * x.x() - x.y() * x.y() * x.z() + Real(0.5) * x.z() * x.z() * x.z();
  };
  const DistanceGrid grid =
      DistanceGrid::sample(Vector3(-1, 0, -2), Vector3(1, 1, 0), Vector3i(5, 3, 7), cubic,
                           GridInterpolation::CubicLagrange);
  EXPECT_EQ(grid.nodes().size(),
            DistanceGrid::nodeCount(Vector3i(5, 3, 7), GridInterpolation::CubicLagrange));
  // 6·4·8 corners and two nodes on each of 5·4·8 + 6·3·8 + 6·4·7 edges.
  EXPECT_EQ(grid.nodes().size(), std::size_t(192 + 2 * (160 + 144 + 168)));
  for (const Vector3& p : randomPoints(500, Vector3(-1, 0, -2), Vector3(1, 1, 0), 3)) {
    const DistanceSample s = grid.evaluate(p);
    EXPECT_NEAR(s.distance, cubic(p), 1024 * kEpsilon);
    const Vector3 exactGradient(1 + 2 * p.x() + p.y() * p.z() + 6 * p.x() * p.x(),
                                -2 - p.z() + p.x() * p.z() - 2 * p.y() * p.z(),
                                -p.y() + p.x() * p.y() - p.y() * p.y() + Real(1.5) * p.z() * p.z());
    EXPECT_LE((s.gradient - exactGradient).norm(), 1024 * kEpsilon * 10);
  }
}

// Neighbouring cells share their face nodes, so the field is continuous across a face (C⁰):
// the values just either side of a face differ only by the field's slope times the offset.
TEST(CubicLagrangeGrid, IsContinuousAcrossCellFaces) {
  const Vector3 centre(-1, Real(-0.5), Real(-0.8));
  auto field = [&](const Vector3& x) { return (x - centre).norm() - Real(0.7); };
  const DistanceGrid grid =
      DistanceGrid::sample(Vector3::Zero(), Vector3::Ones(), Vector3i::Constant(4), field,
                           GridInterpolation::CubicLagrange);
  const Real offset = Real(1e-9);
  for (const Vector3& p : randomPoints(200, Vector3::Zero(), Vector3::Ones(), 9)) {
    for (int axis = 0; axis < 3; ++axis) {
      Vector3 below = p, above = p;
      below(axis) = Real(0.5) - offset;  // the face between cells 1 and 2
      above(axis) = Real(0.5) + offset;
      // |∇φ| ≤ ~1.3 for this interpolated distance: 2 × offset × 2 plus round-off.
      EXPECT_NEAR(grid.value(below), grid.value(above), 4 * offset + 64 * kEpsilon);
    }
  }
}

// For a smooth field the serendipity element's error is O(Δ⁴) in value and O(Δ³) in gradient
// (it reproduces cubics). Same field and points as the Catmull-Rom test; fitted orders within
// ±0.3 of the element's.
TEST(CubicLagrangeGrid, InterpolationErrorFallsAtTheOrderOfTheElement) {
  if (sizeof(Real) < 8) GTEST_SKIP() << "the finest errors are below float round-off";
  const auto [valueOrder, gradientOrder] =
      smoothFieldOrders(GridInterpolation::CubicLagrange, {4, 8, 16, 32});
  std::printf("  fitted orders: value %.2f (serendipity cubic: 4), gradient %.2f (3)\n", valueOrder,
              gradientOrder);
  EXPECT_NEAR(valueOrder, 4, 0.3);
  EXPECT_NEAR(gradientOrder, 3, 0.3);
}

// The grid of the icosphere mesh against its exact mesh distance, in the band |φ| < 0.2 around
// the surface, where contacts are evaluated. The mesh field is only Lipschitz across the
// medial surfaces of the polyhedron (inside, they reach the surface at every edge) and its
// curvature is unbounded at the edges outside, so there a cubic interpolant converges at first
// order only; elsewhere at third. Once the cells are smaller than the facets (edge ≈ 0.1 m:
// from 32 cells on) the band's maximum error must therefore fall at least at first order, and
// at every resolution stay below the bound of any
// 1-Lipschitz field: the weights sum to 1, so |I f(x) − f(x)| ≤ Σ|w_ijk| |x_ijk − x|
// ≤ Σ|w_i w_j w_k| (|x_i − x| + |y_j − y| + |z_k − z|) ≤ 3 (Σ|w|)² max_t Σ|w_i(t)||i − t| Δ
// = 3 · 1.25² · 0.75 Δ ≈ 3.52 Δ (Σ|w| ≤ 1.25 and Σ|w||i − t| ≤ 0.75, both at t = ½).
TEST(DistanceGrid, MeshGridConvergesToTheExactMeshDistance) {
  if (sizeof(Real) < 8) GTEST_SKIP() << "the finest errors are below float round-off";
  const TriangleMesh mesh = loadObj(kModels + "sphere.obj");
  const MeshDistance exact(mesh);
  std::vector<Vector3> band;
  for (const Vector3& p : randomPoints(20000, Vector3::Constant(-1.2), Vector3::Constant(1.2), 5))
    if (std::abs(exact.signedDistance(p)) < Real(0.2)) band.push_back(p);
  std::vector<int> cells = {8, 16, 32, 64};
  std::vector<double> errors, outsideErrors;
  const Vector3 low = Vector3::Constant(Real(-1.2)), high = Vector3::Constant(Real(1.2));
  for (int n : cells) {
    const CachedGrid grid = loadOrBuildMeshGrid(mesh, low, high, Vector3i::Constant(n),
                                                GridInterpolation::CatmullRom, "");
    double worst = 0, worstOutside = 0;
    for (const Vector3& p : band) {
      const double d = exact.signedDistance(p);
      const double error = std::abs(double(grid.grid->value(p)) - d);
      worst = std::max(worst, error);
      if (d > 0) worstOutside = std::max(worstOutside, error);
    }
    const double cell = 2.4 / n;
    EXPECT_LE(worst, 3 * 1.25 * 1.25 * 0.75 * cell) << n << " cells";
    errors.push_back(worst);
    outsideErrors.push_back(worstOutside);
    std::printf(
        "  icosphere grid, %2d cells (cell %.3f): max error in |phi| < 0.2: %.3e (outside: "
        "%.3e)\n",
        n, cell, worst, worstOutside);
  }
  std::printf("  fitted order, all resolutions: band %.2f, outside only %.2f\n",
              fittedOrder(cells, errors), fittedOrder(cells, outsideErrors));
  const std::vector<int> fine(cells.end() - 2, cells.end());
  const double order = fittedOrder(fine, {errors.end() - 2, errors.end()});
  std::printf("  fitted order, cells smaller than the facets (32, 64): %.2f\n", order);
  EXPECT_GE(order, 0.9);
}

// The non-convex torus model (R = 1, r = 0.4, 32 × 16 segments, vertices on the smooth torus):
// its facets deviate from the smooth surface by at most the sags of its two circles,
// H = (R + r)(1 − cos(π/32)) + r (1 − cos(π/16)) = 0.0144, and signed distances to two
// surfaces within H of each other differ by at most 2H (H where both agree on the side).
// The grid then adds its interpolation error: reported per resolution, bounded by the
// Lipschitz bound 3.52 Δ of MeshGridConvergesToTheExactMeshDistance.
TEST(DistanceGrid, TorusMeshGridApproachesTheAnalyticTorus) {
  if (sizeof(Real) < 8) GTEST_SKIP() << "reported numbers for the double build";
  const TriangleMesh mesh = loadObj(kModels + "torus.obj");
  const Real sag =
      Real(1.4) * (1 - std::cos(Real(M_PI / 32))) + Real(0.4) * (1 - std::cos(Real(M_PI / 16)));
  const MeshDistance exact(mesh);
  std::vector<Vector3> band;
  for (const Vector3& p : randomPoints(20000, Vector3(-1.5, -0.5, -1.5), Vector3(1.5, 0.5, 1.5), 8))
    if (std::abs(sdf::torus(p, 1, Real(0.4)).distance) < Real(0.1)) band.push_back(p);
  Real meshError = 0;
  for (const Vector3& p : band)
    meshError = std::max(meshError,
                         std::abs(exact.signedDistance(p) - sdf::torus(p, 1, Real(0.4)).distance));
  EXPECT_LE(meshError, 2 * sag);
  std::printf("  torus mesh (512 vertices): sag bound %.3e, max |mesh - torus| %.3e\n", double(sag),
              double(meshError));
  const Vector3 low(Real(-1.54), Real(-0.54), Real(-1.54)), high = -low;
  for (int n : {16, 32, 64}) {
    const Vector3i cells(n, std::max(4, n * 2 / 5), n);
    const CachedGrid grid =
        loadOrBuildMeshGrid(mesh, low, high, cells, GridInterpolation::CatmullRom, "");
    Real toMesh = 0, toTorus = 0;
    for (const Vector3& p : band) {
      const Real g = grid.grid->value(p);
      toMesh = std::max(toMesh, std::abs(g - exact.signedDistance(p)));
      toTorus = std::max(toTorus, std::abs(g - sdf::torus(p, 1, Real(0.4)).distance));
    }
    const Real cell = (high.x() - low.x()) / Real(n);
    EXPECT_LE(toMesh, Real(3.52) * cell);
    std::printf(
        "  torus grid %2d x %2d x %2d (cell %.3f): max error vs mesh %.3e, vs analytic torus "
        "%.3e\n",
        cells.x(), cells.y(), cells.z(), double(cell), double(toMesh), double(toTorus));
  }
}

// --- Cache --------------------------------------------------------------------------------------

const TriangleMesh& cubeMesh() {
  static const TriangleMesh mesh = loadObj(kModels + "cube.obj");
  return mesh;
}

CachedGrid cubeGrid(const std::string& folder, int cells = 6,
                    GridInterpolation interpolation = GridInterpolation::CatmullRom) {
  return loadOrBuildMeshGrid(cubeMesh(), Vector3::Constant(-1), Vector3::Constant(1),
                             Vector3i::Constant(cells), interpolation, folder);
}

void overwrite(const std::string& path, const std::function<void(std::string&)>& edit) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  edit(bytes);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(GridCache, SecondBuildLoadsTheSameGrid) {
  TemporaryFolder folder("cache-load");
  const CachedGrid first = cubeGrid(folder.path.string());
  EXPECT_EQ(first.outcome, GridCacheOutcome::Built);
  ASSERT_TRUE(fs::exists(first.path));
  EXPECT_EQ(fs::path(first.path).parent_path(), folder.path);
  const CachedGrid second = cubeGrid(folder.path.string());
  EXPECT_EQ(second.outcome, GridCacheOutcome::Loaded);
  EXPECT_EQ(second.path, first.path);
  EXPECT_EQ(second.grid->nodes(), first.grid->nodes());  // bit for bit
  // Another resolution is another key, another file.
  const CachedGrid other = cubeGrid(folder.path.string(), 7);
  EXPECT_EQ(other.outcome, GridCacheOutcome::Built);
  EXPECT_NE(other.path, first.path);
  // So is the other interpolation: its own file, loaded back as itself.
  const CachedGrid lagrange = cubeGrid(folder.path.string(), 6, GridInterpolation::CubicLagrange);
  EXPECT_EQ(lagrange.outcome, GridCacheOutcome::Built);
  EXPECT_NE(lagrange.path, first.path);
  const CachedGrid lagrangeAgain =
      cubeGrid(folder.path.string(), 6, GridInterpolation::CubicLagrange);
  EXPECT_EQ(lagrangeAgain.outcome, GridCacheOutcome::Loaded);
  EXPECT_EQ(lagrangeAgain.grid->interpolation(), GridInterpolation::CubicLagrange);
  EXPECT_EQ(lagrangeAgain.grid->nodes(), lagrange.grid->nodes());
  // Writes are atomic: no temporary file is left behind.
  for (const auto& entry : fs::directory_iterator(folder.path))
    EXPECT_EQ(entry.path().extension(), ".grid") << entry.path();
}

TEST(GridCache, CorruptTruncatedForeignOrStaleFilesAreRebuilt) {
  TemporaryFolder folder("cache-corrupt");
  const CachedGrid reference = cubeGrid(folder.path.string());
  const std::string path = reference.path;
  const std::vector<std::pair<const char*, std::function<void(std::string&)>>> damages = {
      {"one flipped payload bit", [](std::string& b) { b[b.size() / 2] ^= 0x10; }},
      {"truncated", [](std::string& b) { b.resize(b.size() - 9); }},
      {"empty", [](std::string& b) { b.clear(); }},
      {"wrong magic", [](std::string& b) { b[0] = 'X'; }},
      {"wrong version", [](std::string& b) { b[8] = char(b[8] + 1); }},
      {"another key in the header", [](std::string& b) { b[12] ^= 0x01; }},
      {"garbage", [](std::string& b) { b = std::string(b.size(), 'g'); }},
  };
  for (const auto& [name, damage] : damages) {
    overwrite(path, damage);
    const CachedGrid rebuilt = cubeGrid(folder.path.string());
    EXPECT_EQ(rebuilt.outcome, GridCacheOutcome::Rebuilt) << name;
    EXPECT_EQ(rebuilt.grid->nodes(), reference.grid->nodes()) << name;
    // ... and the rebuilt file is valid again.
    EXPECT_EQ(cubeGrid(folder.path.string()).outcome, GridCacheOutcome::Loaded) << name;
  }
  // A valid grid file of another mesh, renamed to this key, is stale: rebuilt.
  TriangleMesh shifted = cubeMesh();
  for (Vector3& v : shifted.vertices)
    v.x() += Real(0.25);
  const CachedGrid foreign = loadOrBuildMeshGrid(
      shifted, Vector3::Constant(-1), Vector3::Constant(1), Vector3i::Constant(6),
      GridInterpolation::CatmullRom, folder.path.string());
  fs::copy_file(foreign.path, path, fs::copy_options::overwrite_existing);
  const CachedGrid stale = cubeGrid(folder.path.string());
  EXPECT_EQ(stale.outcome, GridCacheOutcome::Rebuilt);
  EXPECT_EQ(stale.grid->nodes(), reference.grid->nodes());
}

TEST(GridCache, WithoutAFolderOrWithAnUnwritableOneTheGridIsStillBuilt) {
  const CachedGrid disabled = cubeGrid("");
  EXPECT_EQ(disabled.outcome, GridCacheOutcome::Disabled);
  EXPECT_TRUE(disabled.path.empty());
  TemporaryFolder folder("cache-unwritable");
  fs::create_directories(folder.path);
  std::ofstream(folder.path / "file") << "a file where a folder should be";
  const CachedGrid unwritable = cubeGrid((folder.path / "file" / "sub").string());
  ASSERT_TRUE(unwritable.grid);
  EXPECT_EQ(unwritable.grid->nodes(), disabled.grid->nodes());
}

// A type-5 body: the grid covers the collision mesh (geometry ⊘ scale ∘ collisionObjectScale)
// plus max(10 % of its extent, the minimum padding), with resolutionSDF cells.
TEST(CollisionShape, SignedDistanceFieldBodyUsesItsScaledMeshAndResolution) {
  TemporaryFolder folder("cache-body");
  RigidBodyDesc body;
  body.jsonPath = "RigidBodies[0]";
  auto mesh = loadObj(kModels + "sphere.obj");
  for (Vector3& v : mesh.vertices)
    v *= Real(0.5);  // scale 0.5, as the loader stores it
  body.mesh = std::make_shared<const TriangleMesh>(mesh);
  body.scale = Vector3::Constant(Real(0.5));
  body.collision.type = CollisionObjectType::SignedDistanceField;
  body.collision.scale = Vector3::Constant(Real(0.5));
  body.collision.resolutionSDF = Vector3i(12, 14, 16);
  CollisionShapeOptions options;
  options.gridCacheFolder = folder.path.string();
  options.minimumGridPadding = Real(0.02);
  options.gridInterpolation = GridInterpolation::CatmullRom;
  const CollisionShape shape = makeCollisionShape(body, options);
  ASSERT_NE(shape.grid(), nullptr);
  EXPECT_EQ(shape.gridOutcome(), GridCacheOutcome::Built);
  EXPECT_EQ(shape.grid()->cells(), Vector3i(12, 14, 16));
  // Mesh extent 1 (radius 0.5): padding max(0.1, 0.02) = 0.1 on every side.
  EXPECT_NEAR(shape.grid()->domainMax().x(), Real(0.6), 4 * kEpsilon);
  EXPECT_NEAR(shape.grid()->domainMin().y(), Real(-0.6), 4 * kEpsilon);
  EXPECT_EQ(makeCollisionShape(body, options).gridOutcome(), GridCacheOutcome::Loaded);
  // Near the surface the field is the sphere of radius 0.5 to within the mesh's sag (0.5 ×
  // 1.5e-3) plus the interpolation error (a few 1e-3 at 12–16 cells over 1.2 m).
  for (const Vector3& p : randomPoints(200, Vector3::Constant(-1), Vector3::Constant(1), 6)) {
    const Real exact = sdf::sphere(p, Real(0.5)).distance;
    if (std::abs(exact) < Real(0.05)) {
      EXPECT_NEAR(shape.distance(p), exact, Real(0.01)) << p.transpose();
    }
  }
  body.collision.invertSDF = true;
  const Vector3 p(Real(0.1), Real(0.2), Real(-0.1));
  EXPECT_EQ(makeCollisionShape(body, options).distance(p), -shape.distance(p));
  // The seed's grid: the box of the unscaled mesh (radius 1) padded by 0.1, ±1.1 whatever the
  // minimum padding, looked up at p ⊙ collisionObjectScale⁻¹ and scaled back by 0.5.
  body.collision.invertSDF = false;
  options.gridInterpolation = GridInterpolation::CubicLagrange;
  const CollisionShape seedShape = makeCollisionShape(body, options);
  ASSERT_NE(seedShape.grid(), nullptr);
  EXPECT_EQ(seedShape.grid()->interpolation(), GridInterpolation::CubicLagrange);
  EXPECT_NEAR(seedShape.grid()->domainMax().x(), Real(1.1), 4 * kEpsilon);
  EXPECT_NEAR(seedShape.grid()->domainMin().z(), Real(-1.1), 4 * kEpsilon);
  EXPECT_EQ(seedShape.gridScale(), Vector3::Constant(Real(0.5)));
  for (const Vector3& q : randomPoints(200, Vector3::Constant(-1), Vector3::Constant(1), 7)) {
    const Real exact = sdf::sphere(q, Real(0.5)).distance;
    if (std::abs(exact) < Real(0.05)) {
      EXPECT_NEAR(seedShape.distance(q), exact, Real(0.01));
    }
  }
}

}  // namespace
}  // namespace pbd
