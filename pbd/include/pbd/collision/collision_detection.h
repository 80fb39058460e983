// Collision detection: points of one object against the signed distance function of another,
// both ways, as the seed's DistanceFieldCollisionDetection does (docs/seed.md#collision-detection).
//
// Collision objects: every rigid body with a collisionObjectType (its shape, its surface
// samples and their bounding-sphere hierarchy), and every triangle and tet model (their
// particles, vertex side only). Per detection:
//   1. world boxes of all objects (inflated by contactTolerance) and sweep and prune;
//   2. for every overlapping pair, both directions (a's points vs b's SDF, then b's vs a's),
//      in the seed's order (ordered pairs sorted by vertex object, then SDF object; particle
//      models after the rigid bodies). A direction needs a vertex side with points and
//      `testMesh`, and a rigid body with a shape on the SDF side; pairs of static bodies,
//      pairs of particle models and static particles against static bodies are skipped;
//   3. the vertex side's hierarchy is walked, entering a node whose sphere (centre c, radius
//      ρ) reaches the SDF side's box and satisfies φ(c) − tolerance < ρ;
//   4. a point x with d = φ(x) − tolerance < 0 makes a contact: normal n = ∇φ/|∇φ| (world,
//      out of the SDF body), the point x on the vertex side and x − d n on the SDF side's
//      tolerance shell, and the distance d. With ContactOrder::Seed, a point against the seed's
//      grid of a scaled mesh (collisionObjectScale s ≠ 1) takes the seed's unscaled distance,
//      d = φ_mesh(x ⊙ s⁻¹) − tolerance, and shell point (x ⊙ s⁻¹ − d n) ⊙ s (the seed's
//      CubicSDFCollisionObject::collisionTest does not scale d back;
//      docs/seed.md#unscaled-grid-distance);
//   5. the contacts of one direction are ordered. ContactOrder::Seed (the `seed` contact model):
//      a rigid body with a mesh reports in the seed's kd-tree order (seed_point_order.h), which
//      depends on the mesh's vertex numbering and its round-off-determined principal frame,
//      and a particle model in the order of the seed's kd-tree over its starting positions
//      (a solid landing on a dynamic body: its particles' contacts share the body, and the
//      Gauss–Seidel pass's result depends on their order); primitives without a mesh deepest
//      first.
//      ContactOrder::DeepestFirst (the `corrected` model): deepest first, ties by point index.
//      The order matters to the Gauss–Seidel velocity pass: with several points of a sphere
//      inside the shell, solving the deepest (the support point) first gives the rebound e·u_n
//      without spin, where an off-centre point first spins the sphere and lets the
//      restitution targets and penalties of the others add energy (the seed's sphere dropped
//      1 m with e = 0.8 rebounds to 0.740 of the drop instead of e² = 0.64; test_seed_reference).
// With Simulation.contactGeometry "primitives" (contactGeometryFor; an option of both methods),
// step 2 first offers every pair of rigid bodies to the closed forms (primitive_contacts.h): a
// pair that has one (sphere–sphere, sphere–box, box–box, ...) reports its few exact contacts,
// in the pair order, before every sampled direction, with the body whose face carries the
// normal as the SDF side; the distance is the separation minus the tolerance and the surface
// point lies on the tolerance shell, as for a sample. The other pairs keep steps 2–5.
// Everything is sized when the detector is built; a detection allocates nothing. Contacts or
// pairs beyond the capacity are dropped and counted (see ContactGeometryBuffer).
//
// Threads (SimulationSettings::detectionThreads > 1): step 3–4 run in parallel. The sorted
// directions are split into contiguous ranges of about equal point counts, one per thread;
// each thread collects its directions' contacts, unsorted, into its own buffer. The calling
// thread then appends them in direction order, up to the capacity, and orders each direction
// (step 5), as the serial detection does: the contacts, their order and the drop counts are
// bitwise the same for every thread count (tested).
#pragma once

#include <memory>
#include <vector>

#include "pbd/collision/broad_phase.h"
#include "pbd/collision/collision_shape.h"
#include "pbd/collision/point_bvh.h"
#include "pbd/collision/primitive_contacts.h"
#include "pbd/collision/tet_contact_detection.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"
#include "pbd/parallel/worker_pool.h"

namespace pbd {

/// One point of an object inside the contact shell of a rigid body's SDF.
struct ContactPointGeometry {
  int vertexSide = -1;  ///< rigid body index, or global particle index (particle contacts)
  int sdfBody = -1;     ///< rigid body index of the SDF side
  int sample = -1;      ///< the point's index in the vertex side's samples (rigid bodies)
  Vector3 vertexPoint = Vector3::Zero();   ///< world: the tested point (the seed's cp₀)
  Vector3 surfacePoint = Vector3::Zero();  ///< world: on the SDF body's tolerance shell (cp₁)
  Vector3 normal = Vector3::UnitY();       ///< world, unit, out of the SDF body
  Real distance = 0;                       ///< φ(vertexPoint) − contactTolerance (< 0)
  /// Closed-form contacts of a sphere (primitive_contacts.h): the vertex side's radius when it
  /// is a sphere, whose vertexPoint is then its support point c − r n, not a point fixed on it
  /// (0 for samples and every other shape). A solver that follows the contact through the step
  /// recomputes the support point from the centre c = vertexPoint + r n.
  Real vertexRadius = 0;
  /// The SDF side's radius when both sides are spheres: the normal is then the line of centres,
  /// c_sdf = (the surface point on the body) − r n (0 otherwise).
  Real sdfRadius = 0;
};

struct ContactGeometryBuffer {
  std::vector<ContactPointGeometry> rigid;     ///< rigid body points vs rigid body SDFs
  std::vector<ContactPointGeometry> particle;  ///< particles vs rigid body SDFs
  std::size_t droppedPairs = 0;     ///< broad-phase pairs beyond capacity, last detection
  std::size_t droppedContacts = 0;  ///< contacts beyond capacity, last detection
};

/// The order of the contacts of one direction (step 5 above).
enum class ContactOrder : int { Seed, DeepestFirst };

class CollisionDetector {
 public:
  CollisionDetector() = default;
  CollisionDetector(CollisionDetector&&) = default;
  CollisionDetector& operator=(CollisionDetector&&) = default;
  /// Builds shapes (grids: from the cache when possible), samples and hierarchies, and sizes
  /// every buffer.
  CollisionDetector(const Scene& scene, const CollisionShapeOptions& options);

  /// Finds all contacts of the current state. Allocates nothing after `reserve`.
  void detect(const BodyStates& bodies, Real tolerance, ContactGeometryBuffer& out,
              ContactOrder order = ContactOrder::DeepestFirst);
  /// Sizes `out` for the worst case this detector allows.
  void reserve(ContactGeometryBuffer& out) const;
  /// Particle–tet contacts between tet models at the current positions
  /// (tet_contact_detection.h). Allocates nothing after `tetContacts().reserve`.
  void detectParticleTet(const ParticleStates& particles, ParticleTetGeometryBuffer& out) {
    tetContacts_.detect(particles, out);
  }
  const TetContactDetector& tetContacts() const { return tetContacts_; }

  std::size_t rigidBodyCount() const { return rigid_.size(); }
  /// Threads of the narrow phase (1: serial).
  int threads() const { return workers_ ? workers_->threads() : 1; }
  const CollisionShape& shape(std::size_t body) const { return rigid_[body].shape; }
  /// Surface samples of a rigid body, in its scene frame.
  const std::vector<Vector3>& samples(std::size_t body) const {
    return rigid_[body].surface->samples;
  }

 private:
  /// Surface samples and their hierarchy, shared by every body with the same samples (a pile
  /// of equal spheres holds one copy: the detection reads it from cache instead of memory).
  struct SampledSurface {
    std::vector<Vector3> samples;  ///< scene frame
    PointBvh hierarchy;
  };
  struct RigidObject {
    CollisionShape shape;
    std::shared_ptr<const SampledSurface> surface;  ///< never null
    std::vector<int> seedRank;               ///< the seed's report rank per sample (meshes only)
    Eigen::AlignedBox<Real, 3> localBounds;  ///< samples ∪ shape bounds, scene frame
    bool testMesh = true;
    bool dynamic = false;
  };
  struct ParticleModel {
    int firstParticle = 0, particleCount = 0;
    bool testMesh = true;
    PointBvh hierarchy;         ///< over the model's particles, refitted every detection
    std::vector<int> seedRank;  ///< the seed's report rank per particle of the model
  };
  struct Frame {
    Matrix3 rotation = Matrix3::Identity();  ///< scene frame → world
    Vector3 origin = Vector3::Zero();
  };

  void updateFrames(const RigidBodyStates& bodies);
  void updateBoxes(const BodyStates& bodies, Real tolerance);
  /// The directions of step 2; with primitive contacts, the closed-form pairs' contacts first.
  void collectDirections(Real tolerance, ContactGeometryBuffer& out);
  /// The closed-form contacts of rigid bodies a < b, appended to `out`; false when the pair has
  /// none (it keeps its samples).
  bool primitivePair(int a, int b, Real tolerance, ContactGeometryBuffer& out);
  bool canBeVertexSide(int object) const;
  void rigidAgainstRigid(int vertexBody, int sdfBody, Real tolerance,
                         std::vector<ContactPointGeometry>& out, std::size_t& dropped) const;
  void particlesAgainstRigid(const ParticleModel& model, const ParticleStates& particles,
                             int sdfBody, Real tolerance, std::vector<ContactPointGeometry>& out,
                             std::size_t& dropped) const;
  template <typename Emit>
  void testPoint(const Vector3& world, int sdfBody, Real tolerance, Emit&& emit) const;
  bool sphereMayTouch(const Vector3& centerWorld, Real radius, int sdfBody, Real tolerance) const;

  std::vector<RigidObject> rigid_;
  bool primitives_ = false;  ///< contactGeometryFor(scene) == Primitives
  /// Rigid body pairs (a < b) joined by a joint, sorted: they keep their samples (contacts.md).
  std::vector<ObjectPair> jointedPairs_;
  PrimitiveManifold manifold_;     ///< scratch of primitivePair
  bool seedGridDistance_ = false;  ///< the seed's unscaled grid distance (step 4), per detection
  std::vector<ParticleModel> particleModels_;
  TetContactDetector tetContacts_;  ///< tet model against tet model
  std::size_t rigidContactCapacity_ = 0, particleContactCapacity_ = 0;
  // Per-detection scratch, sized at construction.
  std::vector<Frame> frames_;
  std::vector<Aabb> boxes_;  ///< rigid bodies, then particle models
  SweepAndPrune broadPhase_;
  std::vector<ObjectPair> directions_;  ///< (vertex object, SDF body), sorted

  // Parallel narrow phase (threads > 1), sized at construction.
  struct PartBuffers {
    std::vector<ContactPointGeometry> rigid, particle;  ///< unsorted, in direction order
    std::size_t dropped = 0;
  };
  void collectDirection(const ObjectPair& direction, const ParticleStates& particles,
                        Real tolerance, std::vector<ContactPointGeometry>& rigidOut,
                        std::vector<ContactPointGeometry>& particleOut, std::size_t& dropped) const;
  void orderDirection(const ObjectPair& direction,
                      std::vector<ContactPointGeometry>::iterator begin,
                      std::vector<ContactPointGeometry>::iterator end, ContactOrder order) const;
  void detectInParallel(const BodyStates& bodies, Real tolerance, ContactGeometryBuffer& out,
                        ContactOrder order);
  std::unique_ptr<WorkerPool> workers_;
  std::vector<PartBuffers> parts_;
  std::vector<std::size_t> directionContacts_;  ///< contacts found per direction
  std::vector<std::size_t> partBegin_;          ///< first direction of each part (+ end)
};

}  // namespace pbd
