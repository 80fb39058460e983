// Particle–tet collision detection between tet models: a particle of one tet model inside a
// tetrahedron of another (the seed's DistanceFieldCollisionDetection::collisionDetectionSolidSolid,
// docs/seed.md#tet-against-tet; Bender et al.).
//
// Per detection, for every ordered pair (A, B) of different tet models whose current boxes
// overlap, in model order (A, then B), A with `testMesh` (or no collision type, as for the
// particle–rigid side), and every particle p of A in index order:
//   1. B's tet hierarchy (tet_bvh.h, refitted from the current positions) yields the tets whose
//      box contains x_p; x_p's barycentric coordinates b in each (A b = x_p − x₀, A the edge
//      matrix) decide whether it is inside (every b_i ≥ 0); of several (x_p on a shared face)
//      the one with the largest min_i b_i wins, ties by the lower tet index;
//   2. the same barycentrics give the particle's place in B's reference (rest) configuration,
//      X = Σ b_i X_i;
//   3. the closest point Q of B's reference boundary surface to X (the faces that belong to a
//      single tet, with an exact closest-triangle query: mesh_distance.h) lies on a face of
//      exactly one tet T'; Q's barycentrics b' in T' (the face's, 0 at the opposite vertex)
//      map it back to the current configuration, c = Σ b'_i x_i;
//   4. the contact: particle p, tet T' with weights b', normal n = the current outward unit
//      normal of Q's face (out of B) and depth d = n·(x_p − c) ≤ 0. The seed takes
//      n = (c − x_p)/|c − x_p|, which the reference mapping tilts as B deforms: under an
//      off-centre load the tilted normals pushed a resting cube sideways; the face normal is
//      exact for a flat face (and the same for an undeformed tet).
// The seed does step 3 with B's signed distance field (its collisionObjectType shape, in B's
// initial frame) and then searches the reference tet containing the SDF's closest point
// (findRefTetAt); the tet model's own boundary makes the SDF unnecessary and the tet exact,
// so pbdval uses it and ignores a tet model's SDF keys (docs/contacts.md). Contacts are
// only generated for particles inside B: there is no tolerance shell (neither in the seed).
// Pairs where the particle and the four tet vertices are all static are skipped.
// Self-collision (A = B) is not detected (nor in the seed).
//
// Everything is sized at construction; a detection allocates nothing. A particle has at most
// one contact per other tet model; the capacity is Σ_A |A| · min(models − 1, 4) contacts
// (4: a particle inside more than four other solids at once is not a sensible scene); beyond
// it, contacts are dropped and counted.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "pbd/collision/broad_phase.h"
#include "pbd/collision/mesh_distance.h"
#include "pbd/collision/tet_bvh.h"
#include "pbd/model/body_states.h"
#include "pbd/model/scene.h"

namespace pbd {

/// A particle of one tet model inside a tet of another.
struct ParticleTetContactGeometry {
  int particle = -1;  ///< global particle index (vertex side)
  int tetModel = -1;  ///< index of the tet side in Scene::tetModels
  int tet = -1;       ///< the tet T' of the contact point, index in its model
  std::array<int, 4> vertices{-1, -1, -1, -1};  ///< T''s global particle indices
  std::array<Real, 4> weights{0, 0, 0, 0};      ///< b', Σ = 1, all ≥ 0
  Vector3 normal = Vector3::UnitY();            ///< world, unit, out of the tet side
  Real distance = 0;                            ///< n·(x_p − c) ≤ 0
};

struct ParticleTetGeometryBuffer {
  std::vector<ParticleTetContactGeometry> contacts;
  std::size_t droppedContacts = 0;  ///< beyond capacity, last detection
};

class TetContactDetector {
 public:
  TetContactDetector() = default;
  explicit TetContactDetector(const Scene& scene);

  /// Finds every particle–tet contact at the current positions. Allocates nothing.
  void detect(const ParticleStates& particles, ParticleTetGeometryBuffer& out);
  void reserve(ParticleTetGeometryBuffer& out) const;
  bool empty() const { return models_.size() < 2; }

 private:
  struct BoundaryFace {
    int tet = -1;
    std::array<int, 3> corners{};  ///< local vertex slots (0..3) of the face in its tet, outward
    int opposite = -1;             ///< the slot not on the face
  };
  struct Model {
    int firstParticle = 0, particleCount = 0;
    bool vertexSide = true;
    std::vector<std::array<int, 4>> tets;  ///< global particle indices
    std::vector<Vector3> reference;        ///< rest positions, local index
    TetBvh hierarchy;
    std::shared_ptr<const MeshDistance> boundary;  ///< over the reference boundary faces
    std::vector<BoundaryFace> faces;               ///< same order as the boundary's triangles
    Aabb box;
  };
  void testParticle(const Model& tetSide, int tetModel, int particle,
                    const ParticleStates& particles, ParticleTetGeometryBuffer& out) const;

  std::vector<Model> models_;
  std::size_t capacity_ = 0;
};

}  // namespace pbd
