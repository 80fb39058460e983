// FCL as the exact distance oracle: signed distances, witness points and penetration depths
// between the rigid bodies of a Scene, in poses read back from any engine (docs/fcl-oracle.md).
//
// Built once from a pbd::Scene: one FCL geometry per rigid body with a collision object, in the
// body's scene frame. Sphere, box and cylinder are FCL primitives; torus and SDF bodies are
// represented by their mesh (an FCL Convex when the mesh is convex, else a BVHModel<OBBRSS>).
// Hollow shapes and invertSDF are not represented: they are reported by unsupported().
//
// Which algorithm answers a pair, and how exact it is, is reported with every result
// (DistanceMethod). FCL is included only by the .cpp files of this folder.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

/// How a pair's signed distance was obtained. The first three are exact up to the GJK tolerance;
/// the others are approximations (docs/fcl-oracle.md, "Accuracy").
enum class DistanceMethod {
  ClosedForm,       ///< FCL's analytic sphere–sphere, sphere–box, sphere–cylinder routines
  BoxBoxSat,        ///< overlapping boxes: separating-axis depth over the 15 axes (exact)
  GjkEpa,           ///< convex pair: libccd GJK when separated (EPA is never called)
  ShallowMpr,       ///< convex pair overlapping by less than the GJK tolerance: MPR's depth
  MeshDistance,     ///< separated pair with a triangle mesh: FCL's BVH traversal
  MeshContact,      ///< penetrating mesh–convex pair: FCL's deepest triangle contact
  MeshVertexDepth,  ///< penetrating mesh–mesh pair: deepest vertex inside the other mesh
  MprFallback,      ///< overlapping convex pair (not two boxes): libccd MPR contact depth, an
                    ///< upper bound; FCL 0.7's EPA aborts the process on nearly flat contacts
};

const char* distanceMethodName(DistanceMethod method);
/// ClosedForm, GjkEpa, ShallowMpr (within the GJK tolerance), and MeshDistance when separated.
bool isExact(DistanceMethod method, double signedDistance);

/// The signed distance of two bodies and its witness points.
struct PairDistance {
  /// > 0: the gap; < 0: minus the penetration depth (the shortest translation that separates).
  double distance = 0;
  /// World. Separated: the closest points. Penetrating: A's deepest point inside B and B's
  /// deepest point inside A (|pointOnA − pointOnB| = depth); for penetrating mesh pairs both
  /// are FCL's contact point or the deepest vertex and its nearest surface point.
  Vector3 pointOnA = Vector3::Zero();
  Vector3 pointOnB = Vector3::Zero();
  DistanceMethod method = DistanceMethod::GjkEpa;

  double depth() const { return distance < 0 ? -distance : 0; }
};

/// The FCL geometry a body got.
enum class OracleShape { None, Sphere, Box, Cylinder, ConvexMesh, TriangleMesh, Unsupported };

/// A body with a collision object the oracle cannot represent exactly.
struct UnsupportedBody {
  int body = -1;         ///< index into Scene::rigidBodies
  std::string jsonPath;  ///< "RigidBodies[3]"
  std::string reason;    ///< "hollow box: ..."

  std::string message() const { return jsonPath + ": " + reason; }
};

struct DistanceOracleOptions {
  /// GJK termination tolerance for separated pairs (m): FCL's DistanceRequest::
  /// distance_tolerance. At FCL's default 1e-6, GJK stops up to 6e-4 m short on a sphere near a
  /// polytope; at 1e-9 the error stays below 1e-6 m (docs/fcl-oracle.md).
  double distanceTolerance = 1e-9;
  /// EPA termination tolerance for penetrating convex pairs (m). FCL 0.7's EPA aborts the
  /// process on curved shapes below 1e-6, so keep it; depths below it come from MPR.
  double epaTolerance = 1e-6;
};

/// Contact margins to subtract from penetration depths (engines' declared margins, recorded
/// with their runs). A margin m means the engine lets bodies overlap by up to m at rest: a
/// pair's depth becomes max(0, depth − m). Values are in metres and may be negative.
struct ContactMargins {
  double global = 0;
  /// (lower body index, higher body index) → margin; replaces `global` for that pair.
  std::map<std::pair<int, int>, double> perPair;

  double forPair(int bodyA, int bodyB) const;
};

struct PenetrationOptions {
  ContactMargins margins;
  /// A pair is an active contact when distance + margin ≤ activeDistance (m). 0: touching or
  /// overlapping after the margin.
  double activeDistance = 0;
  /// Pairs connected by a joint overlap by design in many scenes; skip them.
  bool skipJointedPairs = true;
};

/// One active contact of a state.
struct PairPenetration {
  int bodyA = -1, bodyB = -1;  ///< indices into Scene::rigidBodies, bodyA < bodyB
  double distance = 0;         ///< the oracle's signed distance, m
  double margin = 0;           ///< subtracted, m
  double depth = 0;            ///< max(0, −distance − margin), m
  DistanceMethod method = DistanceMethod::GjkEpa;
};

/// A pair whose query failed (FCL threw twice); it is not counted in the aggregates.
struct PairFailure {
  int bodyA = -1, bodyB = -1;
  std::string message;
};

/// The penetrations of one state. The aggregates are those of the validation metrics
/// penetration_max and penetration_mean; all are 0 when there is no active contact.
struct PenetrationReport {
  std::vector<PairPenetration> contacts;  ///< sorted by (bodyA, bodyB)
  std::vector<PairFailure> failures;
  int pairsTested = 0;  ///< pairs that passed the broad phase and were queried

  double maxDepth() const;
  double meanDepth() const;
  double sumSquaredDepth() const;  ///< Σ depth², SimBenchmark's per-step penetration measure
  int inexactContacts() const;     ///< active contacts answered by an approximate method
};

class DistanceOracle {
 public:
  /// Builds the FCL geometries of every rigid body. Never throws for unsupported collision
  /// types (see unsupported()); throws std::invalid_argument for a malformed mesh.
  explicit DistanceOracle(const pbd::Scene& scene, DistanceOracleOptions options = {});
  ~DistanceOracle();
  DistanceOracle(DistanceOracle&&) noexcept;
  DistanceOracle& operator=(DistanceOracle&&) noexcept;
  DistanceOracle(const DistanceOracle&) = delete;
  DistanceOracle& operator=(const DistanceOracle&) = delete;

  int bodyCount() const;
  OracleShape shape(int body) const;
  bool hasGeometry(int body) const;
  /// "box 1 × 2 × 3", "convex mesh (8 vertices)", "triangle mesh (1152 triangles)".
  const std::string& description(int body) const;
  /// Bodies whose collision object is not represented, with the reason.
  const std::vector<UnsupportedBody>& unsupported() const;
  /// Approximations and frame conventions worth knowing, by body ("RigidBodies[2]: torus
  /// (R, r) represented by its mesh, which deviates from it by up to 3.1e-3 m").
  const std::vector<std::string>& notes() const;

  /// The signed distance of bodies `bodyA` and `bodyB` (indices) in the given states. Throws
  /// std::invalid_argument for a body without geometry or a pose holding NaN or Inf, and
  /// std::runtime_error if FCL fails.
  PairDistance distance(int bodyA, const BodyState& stateA, int bodyB,
                        const BodyState& stateB) const;

  /// Every active contact of `state` (bodies in Scene order): all pairs of bodies with
  /// geometry, static–static pairs skipped, candidates from FCL's dynamic AABB tree. Throws
  /// std::invalid_argument when the state does not match the scene or a body's pose holds NaN
  /// or Inf (or a zero quaternion): FCL is never given one.
  PenetrationReport penetrations(const State& state, const PenetrationOptions& options = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The world pose of a body's scene frame: rotation `state.rotation`, origin
/// state.position − state.rotation · centerOfMass.
struct SceneFramePose {
  Quaternion rotation = Quaternion::Identity();
  Vector3 origin = Vector3::Zero();
};
SceneFramePose sceneFramePose(const pbd::RigidBodyDesc& body, const BodyState& state);

/// The state a body has when its scene frame is at `origin` with `rotation` (the inverse of
/// sceneFramePose; for tests and for placing bodies by their scene frame).
BodyState stateFromSceneFrame(const pbd::RigidBodyDesc& body, const Vector3& origin,
                              const Quaternion& rotation = Quaternion::Identity());

}  // namespace pbdval
