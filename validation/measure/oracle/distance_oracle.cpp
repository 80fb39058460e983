#include "validation/measure/oracle/distance_oracle.h"

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "validation/measure/oracle/fcl_geometry.h"
#include "validation/measure/oracle/narrow_phase.h"

namespace pbdval {

using fcl_oracle::BodyGeometry;
using fcl_oracle::PlacedBody;

const char* distanceMethodName(DistanceMethod method) {
  switch (method) {
    case DistanceMethod::ClosedForm:
      return "closed_form";
    case DistanceMethod::BoxBoxSat:
      return "box_box_sat";
    case DistanceMethod::GjkEpa:
      return "gjk_epa";
    case DistanceMethod::ShallowMpr:
      return "shallow_mpr";
    case DistanceMethod::MeshDistance:
      return "mesh_distance";
    case DistanceMethod::MeshContact:
      return "mesh_contact";
    case DistanceMethod::MeshVertexDepth:
      return "mesh_vertex_depth";
    case DistanceMethod::MprFallback:
      return "mpr_fallback";
  }
  return "unknown";
}

bool isExact(DistanceMethod method, double signedDistance) {
  switch (method) {
    case DistanceMethod::ClosedForm:
    case DistanceMethod::BoxBoxSat:
    case DistanceMethod::GjkEpa:
    case DistanceMethod::ShallowMpr:
      return true;
    case DistanceMethod::MeshDistance:
      return signedDistance > 0;
    case DistanceMethod::MeshContact:
    case DistanceMethod::MeshVertexDepth:
    case DistanceMethod::MprFallback:
      return false;
  }
  return false;
}

double ContactMargins::forPair(int bodyA, int bodyB) const {
  const auto found = perPair.find({std::min(bodyA, bodyB), std::max(bodyA, bodyB)});
  return found == perPair.end() ? global : found->second;
}

double PenetrationReport::maxDepth() const {
  double deepest = 0;
  for (const PairPenetration& c : contacts) {
    deepest = std::max(deepest, c.depth);
  }
  return deepest;
}

double PenetrationReport::meanDepth() const {
  if (contacts.empty()) return 0;
  double sum = 0;
  for (const PairPenetration& c : contacts) {
    sum += c.depth;
  }
  return sum / static_cast<double>(contacts.size());
}

double PenetrationReport::sumSquaredDepth() const {
  double sum = 0;
  for (const PairPenetration& c : contacts) {
    sum += c.depth * c.depth;
  }
  return sum;
}

int PenetrationReport::inexactContacts() const {
  return static_cast<int>(
      std::count_if(contacts.begin(), contacts.end(),
                    [](const PairPenetration& c) { return !isExact(c.method, c.distance); }));
}

SceneFramePose sceneFramePose(const pbd::RigidBodyDesc& body, const BodyState& state) {
  SceneFramePose pose;
  pose.rotation = state.rotation.normalized();
  pose.origin = state.position - pose.rotation * body.massProperties.centerOfMass;
  return pose;
}

BodyState stateFromSceneFrame(const pbd::RigidBodyDesc& body, const Vector3& origin,
                              const Quaternion& rotation) {
  BodyState state;
  state.id = body.id;
  state.rotation = rotation.normalized();
  state.position = origin + state.rotation * body.massProperties.centerOfMass;
  return state;
}

namespace {

std::set<std::pair<int, int>> jointedPairs(const pbd::Scene& scene) {
  std::set<std::pair<int, int>> pairs;
  for (const pbd::JointDesc& joint : scene.joints) {
    if (joint.body1 < 0 || joint.body2 < 0) continue;  // rigid body–particle joints
    pairs.insert({std::min(joint.body1, joint.body2), std::max(joint.body1, joint.body2)});
  }
  return pairs;
}

/// The smallest margin any pair can get: AABBs must be inflated so that the broad phase finds
/// every pair with distance ≤ activeDistance − margin.
double smallestMargin(const ContactMargins& margins) {
  double smallest = margins.global;
  for (const auto& entry : margins.perPair) {
    smallest = std::min(smallest, entry.second);
  }
  return smallest;
}

/// A collision object whose world AABB can be grown, so that the broad phase also reports pairs
/// that are close but not overlapping.
class InflatableCollisionObject : public fcl::CollisionObjectd {
 public:
  using fcl::CollisionObjectd::CollisionObjectd;
  void inflate(double by) {
    aabb.min_ -= fcl::Vector3d::Constant(by);
    aabb.max_ += fcl::Vector3d::Constant(by);
  }
};

struct CandidatePairs {
  std::vector<std::pair<int, int>> pairs;
};

bool collectCandidate(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data) {
  const int bodyA = *static_cast<const int*>(a->getUserData());
  const int bodyB = *static_cast<const int*>(b->getUserData());
  static_cast<CandidatePairs*>(data)->pairs.emplace_back(std::min(bodyA, bodyB),
                                                         std::max(bodyA, bodyB));
  return false;  // keep going
}

}  // namespace

struct DistanceOracle::Impl {
  DistanceOracleOptions options;
  std::vector<pbd::RigidBodyDesc> bodies;  ///< without meshes (the geometry keeps them)
  fcl_oracle::SceneGeometry geometry;
  std::set<std::pair<int, int>> jointed;

  void checkBody(int body, const char* what) const {
    if (body < 0 || body >= static_cast<int>(bodies.size())) {
      throw std::invalid_argument(std::string(what) + ": body index " + std::to_string(body) +
                                  " out of range (the scene has " + std::to_string(bodies.size()) +
                                  " rigid bodies)");
    }
  }

  const BodyGeometry& geometryOf(int body, const char* what) const {
    checkBody(body, what);
    const BodyGeometry& g = geometry.bodies[body];
    if (!g.geometry) {
      throw std::invalid_argument(std::string(what) + ": " + bodies[body].jsonPath +
                                  " has no geometry in the distance oracle (" + g.description +
                                  ")");
    }
    return g;
  }

  /// The world pose of the body's FCL geometry frame. Throws std::invalid_argument for a pose
  /// FCL cannot take: a position or quaternion holding NaN or Inf, or a zero quaternion (FCL's
  /// bounding-volume trees are not made for them; a diverged run's state reaches here only by
  /// mistake, and must be refused, not crash the process).
  fcl::Transform3d geometryPose(int body, const BodyState& state) const {
    if (!state.position.allFinite() || !state.rotation.coeffs().allFinite() ||
        state.rotation.squaredNorm() == 0)
      throw std::invalid_argument(
          bodies[body].jsonPath + " (body " + std::to_string(bodies[body].id) +
          "): its state holds NaN or Inf in the position or a zero, NaN or Inf quaternion; "
          "the distance oracle measures only finite poses");
    const SceneFramePose scenePose = sceneFramePose(bodies[body], state);
    fcl::Transform3d pose = fcl::Transform3d::Identity();
    pose.linear() = scenePose.rotation.toRotationMatrix().cast<double>();
    pose.translation() = scenePose.origin.cast<double>();
    return pose * geometry.bodies[body].geometryInSceneFrame;
  }

  PairDistance query(int bodyA, const BodyState& stateA, int bodyB, const BodyState& stateB) const {
    const PlacedBody a{geometryOf(bodyA, "distance"), geometryPose(bodyA, stateA)};
    const PlacedBody b{geometryOf(bodyB, "distance"), geometryPose(bodyB, stateB)};
    return fcl_oracle::pairDistance(a, b, options);
  }

  CandidatePairs broadPhase(const State& state, double inflation) const;
  bool skipPair(int bodyA, int bodyB, const PenetrationOptions& options) const;
};

CandidatePairs DistanceOracle::Impl::broadPhase(const State& state, double inflation) const {
  std::vector<int> indices;
  std::vector<std::unique_ptr<InflatableCollisionObject>> objects;
  indices.reserve(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (geometry.bodies[i].geometry) indices.push_back(static_cast<int>(i));
  }
  std::vector<fcl::CollisionObjectd*> registered;
  for (int& body : indices) {
    auto object = std::make_unique<InflatableCollisionObject>(
        geometry.bodies[body].geometry, geometryPose(body, state.bodies[body]));
    object->inflate(inflation);
    object->setUserData(&body);
    registered.push_back(object.get());
    objects.push_back(std::move(object));
  }
  fcl::DynamicAABBTreeCollisionManagerd manager;
  manager.registerObjects(registered);
  manager.setup();
  CandidatePairs candidates;
  manager.collide(&candidates, &collectCandidate);
  std::sort(candidates.pairs.begin(), candidates.pairs.end());
  candidates.pairs.erase(std::unique(candidates.pairs.begin(), candidates.pairs.end()),
                         candidates.pairs.end());
  return candidates;
}

bool DistanceOracle::Impl::skipPair(int bodyA, int bodyB, const PenetrationOptions& opts) const {
  if (!bodies[bodyA].isDynamic && !bodies[bodyB].isDynamic) return true;
  return opts.skipJointedPairs && jointed.count({bodyA, bodyB}) > 0;
}

DistanceOracle::DistanceOracle(const pbd::Scene& scene, DistanceOracleOptions options)
    : impl_(std::make_unique<Impl>()) {
  if (!(options.distanceTolerance > 0) || !(options.epaTolerance > 0)) {
    throw std::invalid_argument("DistanceOracle: distanceTolerance and epaTolerance must be > 0");
  }
  impl_->options = options;
  for (const pbd::RigidBodyDesc& body : scene.rigidBodies) {
    impl_->bodies.push_back(body);
    impl_->bodies.back().mesh.reset();
  }
  impl_->geometry = fcl_oracle::buildSceneGeometry(scene);
  impl_->jointed = jointedPairs(scene);
}

DistanceOracle::~DistanceOracle() = default;
DistanceOracle::DistanceOracle(DistanceOracle&&) noexcept = default;
DistanceOracle& DistanceOracle::operator=(DistanceOracle&&) noexcept = default;

int DistanceOracle::bodyCount() const {
  return static_cast<int>(impl_->bodies.size());
}

OracleShape DistanceOracle::shape(int body) const {
  impl_->checkBody(body, "shape");
  return impl_->geometry.bodies[body].shape;
}

bool DistanceOracle::hasGeometry(int body) const {
  impl_->checkBody(body, "hasGeometry");
  return impl_->geometry.bodies[body].geometry != nullptr;
}

const std::string& DistanceOracle::description(int body) const {
  impl_->checkBody(body, "description");
  return impl_->geometry.bodies[body].description;
}

const std::vector<UnsupportedBody>& DistanceOracle::unsupported() const {
  return impl_->geometry.unsupported;
}

const std::vector<std::string>& DistanceOracle::notes() const {
  return impl_->geometry.notes;
}

PairDistance DistanceOracle::distance(int bodyA, const BodyState& stateA, int bodyB,
                                      const BodyState& stateB) const {
  if (bodyA == bodyB) {
    throw std::invalid_argument("distance: a body and itself (index " + std::to_string(bodyA) +
                                ")");
  }
  return impl_->query(bodyA, stateA, bodyB, stateB);
}

PenetrationReport DistanceOracle::penetrations(const State& state,
                                               const PenetrationOptions& options) const {
  if (state.bodies.size() != impl_->bodies.size()) {
    throw std::invalid_argument("penetrations: the state has " +
                                std::to_string(state.bodies.size()) + " bodies, the scene " +
                                std::to_string(impl_->bodies.size()));
  }
  const double inflation =
      std::max(0.0, options.activeDistance - smallestMargin(options.margins)) / 2;
  PenetrationReport report;
  for (const auto& [bodyA, bodyB] : impl_->broadPhase(state, inflation).pairs) {
    if (impl_->skipPair(bodyA, bodyB, options)) continue;
    ++report.pairsTested;
    PairDistance pair;
    try {
      pair = impl_->query(bodyA, state.bodies[bodyA], bodyB, state.bodies[bodyB]);
    } catch (const std::exception& error) {
      report.failures.push_back({bodyA, bodyB, error.what()});
      continue;
    }
    const double margin = options.margins.forPair(bodyA, bodyB);
    if (pair.distance + margin > options.activeDistance) continue;
    report.contacts.push_back(
        {bodyA, bodyB, pair.distance, margin, std::max(0.0, -pair.distance - margin), pair.method});
  }
  return report;
}

}  // namespace pbdval
