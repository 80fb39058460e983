#include "validation/studies/distance_study.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>
#include <sstream>

#include "pbd/collision/collision_shape.h"
#include "pbd/collision/surface_samples.h"
#include "pbd/io/scene_loader.h"
#include "validation/io/json_text.h"
#include "validation/measure/oracle/distance_oracle.h"
#include "validation/studies/sweep.h"

namespace pbdval {
namespace {

using pbd::Quaternion;
using pbd::RigidBodyDesc;
using pbd::Vector3;

/// Built-in shapes, as a scene the loader reads (so that masses, meshes and paths are exactly
/// what a case would give).
const char* kBuiltInScene = R"({
  "RigidBodies": [
    {"id": 1, "collisionObjectType": 1, "collisionObjectScale": [0.4, 0.4, 0.4]},
    {"id": 2, "collisionObjectType": 2, "collisionObjectScale": [0.8, 0.5, 0.6]},
    {"id": 3, "collisionObjectType": 3, "collisionObjectScale": [0.35, 0.8, 0.35]},
    {"id": 4, "geometryFile": "torus.obj", "scale": [0.4, 0.4, 0.4],
     "collisionObjectType": 4, "collisionObjectScale": [0.4, 0.16, 0.4]},
    {"id": 5, "geometryFile": "torus.obj", "scale": [0.4, 0.4, 0.4],
     "collisionObjectType": 5, "collisionObjectScale": [0.4, 0.4, 0.4], "resolutionSDF": [32, 32, 32]}
  ]
})";

const char* typeName(pbd::CollisionObjectType type) {
  switch (type) {
    case pbd::CollisionObjectType::Sphere:
      return "sphere";
    case pbd::CollisionObjectType::Box:
      return "box";
    case pbd::CollisionObjectType::Cylinder:
      return "cylinder";
    case pbd::CollisionObjectType::Torus:
      return "torus";
    case pbd::CollisionObjectType::SignedDistanceField:
      return "grid SDF";
    case pbd::CollisionObjectType::HollowSphere:
      return "hollow sphere";
    case pbd::CollisionObjectType::HollowBox:
      return "hollow box";
    case pbd::CollisionObjectType::None:
      return "none";
  }
  return "?";
}

/// A body in the world: its scene frame's rotation and origin.
struct Placement {
  Quaternion rotation = Quaternion::Identity();
  Vector3 origin = Vector3::Zero();

  BodyState state(const RigidBodyDesc& body) const {
    BodyState s;
    s.id = body.id;
    s.rotation = rotation;
    s.position = origin + rotation * body.massProperties.centerOfMass;
    return s;
  }
  Vector3 toScene(const Vector3& world) const { return rotation.conjugate() * (world - origin); }
  Vector3 toWorld(const Vector3& scene) const { return origin + rotation * scene; }
};

Quaternion randomRotation(std::mt19937_64& random) {
  // Shoemake's uniform unit quaternion.
  std::uniform_real_distribution<double> u(0, 1);
  const double u1 = u(random), u2 = u(random), u3 = u(random);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return Quaternion(Real(a * std::sin(2 * M_PI * u2)), Real(a * std::cos(2 * M_PI * u2)),
                    Real(b * std::sin(2 * M_PI * u3)), Real(b * std::cos(2 * M_PI * u3)));
}

Vector3 randomDirection(std::mt19937_64& random) {
  std::normal_distribution<double> n(0, 1);
  Vector3 d(Real(n(random)), Real(n(random)), Real(n(random)));
  return d.normalized();
}

double boundingRadius(const pbd::CollisionShape& shape) {
  const auto box = shape.bounds();
  double r = 0;
  for (int corner = 0; corner < 8; ++corner)
    r = std::max(
        r, double(box.corner(static_cast<Eigen::AlignedBox<Real, 3>::CornerType>(corner)).norm()));
  return r;
}

std::string label(const RigidBodyDesc& body) {
  return body.jsonPath.empty() ? typeName(body.collision.type)
                               : body.jsonPath + " (" + typeName(body.collision.type) + ")";
}

/// The PBD collision detection's distance: the smallest SDF value of either body's surface
/// samples in the other body.
double pbdDistance(const pbd::CollisionShape& shapeA, const std::vector<Vector3>& samplesA,
                   const Placement& a, const pbd::CollisionShape& shapeB,
                   const std::vector<Vector3>& samplesB, const Placement& b) {
  double d = std::numeric_limits<double>::infinity();
  for (const Vector3& p : samplesA)
    d = std::min(d, double(shapeB.distance(b.toScene(a.toWorld(p)))));
  for (const Vector3& p : samplesB)
    d = std::min(d, double(shapeA.distance(a.toScene(b.toWorld(p)))));
  return d;
}

PairErrors studyPair(const RigidBodyDesc& a, const RigidBodyDesc& b,
                     const DistanceStudyOptions& options, std::mt19937_64& random,
                     const pbd::CollisionShapeOptions& shapeOptions) {
  pbd::Scene pair;
  pair.rigidBodies = {a, b};
  const DistanceOracle oracle(pair);
  const pbd::CollisionShape shapeA = pbd::makeCollisionShape(a, shapeOptions);
  const pbd::CollisionShape shapeB = pbd::makeCollisionShape(b, shapeOptions);
  const std::vector<Vector3> samplesA = pbd::surfaceSamples(a), samplesB = pbd::surfaceSamples(b);
  const double reach = boundingRadius(shapeA) + boundingRadius(shapeB) + options.band;
  std::uniform_real_distribution<double> distance(0, reach);

  PairErrors e;
  e.shapeA = label(a);
  e.shapeB = label(b);
  double sumSquares = 0, sum = 0;
  const Placement placeA;
  for (int attempt = 0; attempt < 100 * options.samples && e.samples < options.samples; ++attempt) {
    Placement placeB;
    placeB.rotation = randomRotation(random);
    placeB.origin = Real(distance(random)) * randomDirection(random);
    const double exact = oracle.distance(0, placeA.state(a), 1, placeB.state(b)).distance;
    if (exact < -options.band / 4 || exact > options.band) continue;
    const double error = pbdDistance(shapeA, samplesA, placeA, shapeB, samplesB, placeB) - exact;
    e.maxAbsError = std::max(e.maxAbsError, std::abs(error));
    sumSquares += error * error;
    sum += error;
    ++e.samples;
  }
  if (e.samples > 0) {
    e.rmsError = std::sqrt(sumSquares / e.samples);
    e.meanError = sum / e.samples;
  }
  return e;
}

/// The winding number of a closed mesh around p: Σ solid angles / 4π (Van Oosterom and
/// Strackee's triangle solid angle): 1 inside, 0 outside. FCL's mesh distances are unsigned, so
/// this independent test decides which points lie outside.
double windingNumber(const pbd::TriangleMesh& mesh, const Vector3& p) {
  double total = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = (mesh.vertices[std::size_t(t[0])] - p).cast<double>();
    const Eigen::Vector3d b = (mesh.vertices[std::size_t(t[1])] - p).cast<double>();
    const Eigen::Vector3d c = (mesh.vertices[std::size_t(t[2])] - p).cast<double>();
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2 * std::atan2(numerator, denominator);
  }
  return total / (4 * M_PI);
}

GridErrors studyGrid(const RigidBodyDesc& body, const DistanceStudyOptions& options,
                     std::mt19937_64& random, const pbd::CollisionShapeOptions& shapeOptions) {
  GridErrors g;
  g.shape = label(body);
  // The exact reference: FCL's distance from the mesh to a sphere of radius ρ at the point, plus
  // ρ (exact for points outside the mesh).
  const double rho = 1e-4;
  pbd::Scene scene;
  scene.rigidBodies = {body};
  scene.rigidBodies[0].collision.type = pbd::CollisionObjectType::SignedDistanceField;
  pbd::RigidBodyDesc probe;
  probe.id = -1;
  probe.collision.type = pbd::CollisionObjectType::Sphere;
  probe.collision.scale = Vector3::Constant(Real(rho));
  probe.massProperties = pbd::toPrincipal(pbd::sphereMoments(Real(rho), 1));
  scene.rigidBodies.push_back(probe);
  const DistanceOracle oracle(scene);

  const pbd::CollisionShape reference = pbd::makeCollisionShape(body, shapeOptions);
  const auto bounds = reference.bounds();
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vector3> points;
  std::vector<double> exact;
  const BodyState bodyState = Placement{}.state(body);
  for (int attempt = 0; attempt < 200 * options.samples && int(points.size()) < options.samples;
       ++attempt) {
    Vector3 p;
    for (int k = 0; k < 3; ++k)
      p(k) = Real(bounds.min()(k) - 0.1 + (bounds.max()(k) - bounds.min()(k) + 0.2) * u(random));
    BodyState probeState;
    probeState.position = p;
    const double d = oracle.distance(0, bodyState, 1, probeState).distance + rho;
    if (d < 0.005 || d > 0.1) continue;                // near the surface ...
    if (windingNumber(*body.mesh, p) > 0.5) continue;  // ... outside the mesh ...
    // ... and inside the grid (the seed's grid is padded by only 0.1 of the mesh file's units;
    // beyond it the seed sees no contact and pbdval an upper bound, neither a grid error).
    const Vector3 gridPoint = p.cwiseProduct(reference.gridScale().cwiseInverse());
    if (reference.grid() && !(gridPoint.array() >= reference.grid()->domainMin().array() &&
                              gridPoint.array() <= reference.grid()->domainMax().array())
                                 .all())
      continue;
    points.push_back(p);
    exact.push_back(d);
  }
  g.samples = int(points.size());
  for (int resolution : options.gridResolutions) {
    pbd::RigidBodyDesc atResolution = body;
    atResolution.collision.resolutionSDF = pbd::Vector3i::Constant(resolution);
    const pbd::CollisionShape shape = pbd::makeCollisionShape(atResolution, shapeOptions);
    double maxError = 0, sumSquares = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const double error = double(shape.distance(points[k])) - exact[k];

      maxError = std::max(maxError, std::abs(error));
      sumSquares += error * error;
    }
    const Vector3 extent = shape.grid()
                               ? Vector3((shape.grid()->domainMax() - shape.grid()->domainMin())
                                             .cwiseQuotient(shape.grid()->cells().cast<Real>())
                                             .cwiseProduct(shape.gridScale()))  // scene frame
                               : Vector3::Zero();
    g.resolutions.push_back(resolution);
    g.cellSizes.push_back(double(extent.maxCoeff()));
    g.maxAbsErrors.push_back(maxError);
    g.rmsErrors.push_back(points.empty() ? 0 : std::sqrt(sumSquares / double(points.size())));
  }
  // max error ∝ hᵖ: the slope of log error against log cell size (the sweep's fit).
  std::vector<std::vector<double>> sizes;
  for (double h : g.cellSizes)
    sizes.push_back({h});
  const SweepFit fit = fitConvergence("grid", {"cellSize"}, sizes, g.maxAbsErrors);
  if (!fit.slopes.empty()) {
    g.order = fit.slopes[0];
    g.rSquared = fit.rSquared;
  }
  return g;
}

}  // namespace

std::vector<RigidBodyDesc> builtInShapes(const std::string& modelsFolder) {
  return pbd::parseScene(kBuiltInScene, modelsFolder + "/builtin-shapes.json").scene.rigidBodies;
}

std::vector<RigidBodyDesc> shapesOfScenes(const std::vector<pbd::Scene>& scenes) {
  std::vector<RigidBodyDesc> shapes;
  for (const pbd::Scene& scene : scenes)
    for (RigidBodyDesc body : scene.rigidBodies) {
      if (body.collision.type == pbd::CollisionObjectType::None) continue;
      body.jsonPath = scene.name.empty() ? body.jsonPath : scene.name + ": " + body.jsonPath;
      shapes.push_back(body);
    }
  return shapes;
}

DistanceStudy runDistanceStudy(const std::vector<RigidBodyDesc>& shapes,
                               const DistanceStudyOptions& options) {
  DistanceStudy study;
  std::mt19937_64 random(options.seed);
  pbd::CollisionShapeOptions shapeOptions;
  std::vector<RigidBodyDesc> usable;
  for (const RigidBodyDesc& body : shapes) {
    pbd::Scene alone;
    alone.rigidBodies = {body};
    const DistanceOracle oracle(alone);
    if (!oracle.unsupported().empty()) {
      study.notes.push_back(
          label(body) + ": skipped, FCL cannot represent it: " + oracle.unsupported()[0].reason);
      continue;
    }
    if (pbd::surfaceSamples(body).empty())
      study.notes.push_back(
          label(body) +
          ": has no surface samples (no geometry file): it acts only through its SDF");
    usable.push_back(body);
  }
  for (std::size_t i = 0; i < usable.size(); ++i)
    for (std::size_t j = i; j < usable.size(); ++j) {
      RigidBodyDesc a = usable[i], b = usable[j];
      a.id = 0;
      b.id = 1;
      study.pairs.push_back(studyPair(a, b, options, random, shapeOptions));
    }
  for (const RigidBodyDesc& body : usable)
    if (body.collision.type == pbd::CollisionObjectType::SignedDistanceField)
      study.grids.push_back(studyGrid(body, options, random, shapeOptions));
  return study;
}

std::string distanceStudyJson(const DistanceStudy& study, const DistanceStudyOptions& options) {
  using Json = nlohmann::json;
  Json pairs = Json::array();
  for (const PairErrors& p : study.pairs)
    pairs.push_back({{"shapeA", p.shapeA},
                     {"shapeB", p.shapeB},
                     {"samples", p.samples},
                     {"max_abs_error_m", p.maxAbsError},
                     {"rms_error_m", p.rmsError},
                     {"mean_error_m", p.meanError}});
  Json grids = Json::array();
  for (const GridErrors& g : study.grids)
    grids.push_back({{"shape", g.shape},
                     {"samples", g.samples},
                     {"resolutions", g.resolutions},
                     {"cell_sizes_m", g.cellSizes},
                     {"max_abs_errors_m", g.maxAbsErrors},
                     {"rms_errors_m", g.rmsErrors},
                     {"fitted_order", g.order},
                     {"r_squared", g.rSquared}});
  const Json document = {{"schema", "pbdval-distance"},
                         {"schemaVersion", 1},
                         {"samples", options.samples},
                         {"seed", options.seed},
                         {"band_m", options.band},
                         {"pairs", pairs},
                         {"grids", grids},
                         {"notes", study.notes}};
  return jsonText(document) + "\n";
}

}  // namespace pbdval
