#include "pbd/collision/collision_detection.h"

#include <algorithm>
#include <map>
#include <memory>
#include <tuple>

#include "pbd/collision/seed_point_order.h"
#include "pbd/collision/surface_samples.h"

namespace pbd {
namespace {

/// A point can touch at most this many other objects at once in a sensible scene (a corner in
/// a pile); contact buffers are sized for it.
constexpr std::size_t kContactsPerPoint = 4;
/// Broad-phase pairs per object (a dense pile has ~10 neighbours per body).
constexpr std::size_t kPairsPerObject = 64;

/// Below this squared gradient length the SDF has no usable direction (the seed's 1e-6).
constexpr Real kMinimumSquaredGradient = Real(1e-6);

Eigen::AlignedBox<Real, 3> boundsOf(const std::vector<Vector3>& points) {
  Eigen::AlignedBox<Real, 3> box;
  box.setEmpty();
  for (const Vector3& p : points)
    box.extend(p);
  return box;
}

/// Orders contacts by depth, deepest first, ties by point index (a total order: the points
/// of one direction are distinct). std::sort sorts in place, without allocating.
void deepestFirst(std::vector<ContactPointGeometry>::iterator begin,
                  std::vector<ContactPointGeometry>::iterator end) {
  std::sort(begin, end, [](const ContactPointGeometry& a, const ContactPointGeometry& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.sample < b.sample);
  });
}

/// Orders contacts as the seed reports them: by the seed's rank of their points, `rank` indexed
/// by the sample less `firstSample` (a particle model's first particle).
void seedOrder(std::vector<ContactPointGeometry>::iterator begin,
               std::vector<ContactPointGeometry>::iterator end, const std::vector<int>& rank,
               int firstSample = 0) {
  std::sort(begin, end, [&](const ContactPointGeometry& a, const ContactPointGeometry& b) {
    return rank[std::size_t(a.sample - firstSample)] < rank[std::size_t(b.sample - firstSample)];
  });
}

/// The radius of a sphere's shape, 0 for any other shape.
Real sphereRadius(const CollisionShape& shape) {
  return shape.type() == CollisionObjectType::Sphere ? shape.size().x() : Real(0);
}

}  // namespace

CollisionDetector::CollisionDetector(const Scene& scene,
                                     const CollisionShapeOptions& givenOptions) {
  CollisionShapeOptions options = givenOptions;
  options.gridInterpolation = distanceGridFor(scene.simulation);
  primitives_ = contactGeometryFor(scene.simulation) == ContactGeometry::Primitives;
  for (const JointDesc& joint : scene.joints)
    if (joint.body1 >= 0 && joint.body2 >= 0 && joint.body1 != joint.body2)
      jointedPairs_.emplace_back(std::min(joint.body1, joint.body2),
                                 std::max(joint.body1, joint.body2));
  std::sort(jointedPairs_.begin(), jointedPairs_.end());
  rigid_.resize(scene.rigidBodies.size());
  std::size_t shapedBodies = 0, rigidPoints = 0, particlePoints = 0;
  // Samples depend only on the mesh (shared by the loader) or on the primitive's type and
  // size (surface_samples.h): bodies alike share one SampledSurface.
  using SurfaceKey = std::tuple<const TriangleMesh*, int, Real, Real, Real>;
  std::map<SurfaceKey, std::shared_ptr<const SampledSurface>> surfaces;
  const auto empty = std::make_shared<const SampledSurface>();
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const RigidBodyDesc& desc = scene.rigidBodies[i];
    RigidObject& object = rigid_[i];
    object.shape = makeCollisionShape(desc, options);
    object.dynamic = desc.isDynamic && desc.massProperties.mass > 0;
    object.testMesh = desc.collision.testMesh;
    object.surface = empty;
    if (!object.shape.exists()) continue;
    ++shapedBodies;
    const Vector3 size = desc.mesh ? Vector3::Zero() : desc.collision.scale;
    const SurfaceKey key{desc.mesh.get(), desc.mesh ? -1 : int(desc.collision.type), size.x(),
                         size.y(), size.z()};
    std::shared_ptr<const SampledSurface>& surface = surfaces[key];
    if (!surface) {
      auto built = std::make_shared<SampledSurface>();
      built->samples = surfaceSamples(desc);
      built->hierarchy = PointBvh(built->samples);
      surface = std::move(built);
    }
    object.surface = surface;
    if (desc.mesh)
      object.seedRank = seedVertexReportRank(*desc.mesh, desc.scale, desc.translation,
                                             desc.rotation, desc.density);
    object.localBounds = boundsOf(surface->samples).extend(object.shape.bounds());
    if (object.testMesh) rigidPoints += surface->samples.size();
  }
  auto addModel = [&](int first, std::size_t count, bool testMesh) {
    ParticleModel model;
    model.firstParticle = first;
    model.particleCount = static_cast<int>(count);
    model.testMesh = testMesh;
    const auto begin = scene.particles.begin() + first;
    std::vector<Vector3> positions;
    for (auto it = begin; it != begin + static_cast<std::ptrdiff_t>(count); ++it)
      positions.push_back(it->position);
    model.hierarchy = PointBvh(positions);
    model.seedRank = seedPointReportRank(positions);
    particleModels_.push_back(std::move(model));
    if (testMesh) particlePoints += count;
  };
  for (const TriangleModelDesc& m : scene.triangleModels)
    addModel(m.firstParticle, m.mesh.vertices.size(), true);
  // The seed always tests a tet model without a collision shape, else as its testMesh says.
  for (const TetModelDesc& m : scene.tetModels)
    addModel(m.firstParticle, m.mesh.vertices.size(),
             m.collision.type == CollisionObjectType::None || m.collision.testMesh);

  tetContacts_ = TetContactDetector(scene);
  const std::size_t others = shapedBodies > 0 ? shapedBodies - 1 : 0;
  rigidContactCapacity_ = rigidPoints * std::min(others, kContactsPerPoint);
  particleContactCapacity_ = particlePoints * std::min(shapedBodies, kContactsPerPoint);
  const std::size_t objects = rigid_.size() + particleModels_.size();
  const std::size_t allPairs = objects * (objects > 0 ? objects - 1 : 0) / 2;
  const std::size_t pairCapacity = std::min(allPairs, kPairsPerObject * objects);
  frames_.resize(rigid_.size());
  boxes_.resize(objects);
  broadPhase_ = SweepAndPrune(objects, pairCapacity);
  directions_.reserve(2 * pairCapacity);
  const int threads = scene.simulation.detectionThreads;
  if (threads < 1)
    throw std::invalid_argument("detection threads: expected at least 1, got " +
                                std::to_string(threads));
  if (threads > 1) {
    workers_ = std::make_unique<WorkerPool>(threads);
    parts_.resize(std::size_t(threads));
    for (PartBuffers& part : parts_) {
      part.rigid.reserve(rigidContactCapacity_);
      part.particle.reserve(particleContactCapacity_);
    }
    directionContacts_.resize(2 * pairCapacity);
    partBegin_.resize(std::size_t(threads) + 1);
  }
}

void CollisionDetector::reserve(ContactGeometryBuffer& out) const {
  out.rigid.clear();
  out.particle.clear();
  out.rigid.reserve(rigidContactCapacity_);
  out.particle.reserve(particleContactCapacity_);
}

void CollisionDetector::updateFrames(const RigidBodyStates& bodies) {
  for (std::size_t i = 0; i < rigid_.size(); ++i) {
    // The scene frame: rotation q ⊗ p⁻¹ (p: principal → scene), origin x − R c.
    const Quaternion sceneRotation = bodies.rotation[i] * bodies.principalInScene[i].conjugate();
    frames_[i].rotation = sceneRotation.toRotationMatrix();
    frames_[i].origin = bodies.position[i] - frames_[i].rotation * bodies.centerOfMassInScene[i];
  }
}

void CollisionDetector::updateBoxes(const BodyStates& bodies, Real tolerance) {
  const Vector3 margin = Vector3::Constant(tolerance);
  for (std::size_t i = 0; i < rigid_.size(); ++i) {
    Aabb& box = boxes_[i];
    box.active = rigid_[i].shape.exists();
    if (!box.active) continue;
    if (seedGridDistance_ && !rigid_[i].seedRank.empty()) {
      // The seed's box (CollisionDetection::updateAABB): the bounds of the mesh's vertices in
      // the world, without the collision shape's, which can reach past them (an analytic torus
      // fatter than its mesh): the seed prunes points there (docs/methods.md, "Fidelity to the
      // seed: particle models, damper, motors").
      const std::vector<Vector3>& vertices = rigid_[i].surface->samples;
      box.min = box.max = frames_[i].rotation * vertices[0] + frames_[i].origin;
      for (std::size_t v = 1; v < vertices.size(); ++v) {
        const Vector3 world = frames_[i].rotation * vertices[v] + frames_[i].origin;
        box.min = box.min.cwiseMin(world);
        box.max = box.max.cwiseMax(world);
      }
      box.min -= margin;
      box.max += margin;
      continue;
    }
    const Eigen::AlignedBox<Real, 3>& local = rigid_[i].localBounds;
    const Vector3 center = frames_[i].rotation * local.center() + frames_[i].origin;
    const Vector3 half = frames_[i].rotation.cwiseAbs() * (local.sizes() / 2);
    box.min = center - half - margin;
    box.max = center + half + margin;
  }
  for (std::size_t m = 0; m < particleModels_.size(); ++m) {
    ParticleModel& model = particleModels_[m];
    Aabb& box = boxes_[rigid_.size() + m];
    box.active = model.particleCount > 0;
    if (!box.active) continue;
    const Vector3* positions = bodies.particles.position.data() + model.firstParticle;
    model.hierarchy.refit(positions);
    box.min = box.max = positions[0];
    for (int p = 1; p < model.particleCount; ++p) {
      box.min = box.min.cwiseMin(positions[p]);
      box.max = box.max.cwiseMax(positions[p]);
    }
    box.min -= margin;
    box.max += margin;
  }
}

bool CollisionDetector::canBeVertexSide(int object) const {
  if (object >= static_cast<int>(rigid_.size()))
    return particleModels_[std::size_t(object) - rigid_.size()].testMesh;
  const RigidObject& body = rigid_[std::size_t(object)];
  return body.testMesh && !body.surface->samples.empty();
}

void CollisionDetector::collectDirections(Real tolerance, ContactGeometryBuffer& out) {
  const int rigidCount = static_cast<int>(rigid_.size());
  directions_.clear();
  auto add = [&](int vertexObject, int sdfObject) {
    if (sdfObject >= rigidCount || !canBeVertexSide(vertexObject)) return;
    if (vertexObject < rigidCount && !rigid_[std::size_t(vertexObject)].dynamic &&
        !rigid_[std::size_t(sdfObject)].dynamic)
      return;  // static–static
    directions_.emplace_back(vertexObject, sdfObject);
  };
  for (const ObjectPair& pair : broadPhase_.pairs()) {
    // The pairs come sorted (a < b): the closed-form contacts are in pair order.
    if (primitives_ && pair.second < rigidCount &&
        primitivePair(pair.first, pair.second, tolerance, out))
      continue;
    add(pair.first, pair.second);
    add(pair.second, pair.first);
  }
  std::sort(directions_.begin(), directions_.end());  // in place: no allocation
}

bool CollisionDetector::primitivePair(int a, int b, Real tolerance, ContactGeometryBuffer& out) {
  const RigidObject& objectA = rigid_[std::size_t(a)];
  const RigidObject& objectB = rigid_[std::size_t(b)];
  if (!hasPrimitiveContacts(objectA.shape.type(), objectB.shape.type())) return false;
  // Jointed bodies overlap at their joint by design (the seed lets them collide): samples push
  // each point of the overlap out of its nearest face and largely cancel, where a manifold's
  // one separating axis pushes the whole overlap against the joint (contacts.md).
  if (std::binary_search(jointedPairs_.begin(), jointedPairs_.end(), ObjectPair(a, b)))
    return false;
  // The pair's contacts exist where a sampled direction would: static–static pairs and pairs
  // of which neither side tests its points have none.
  if (!objectA.dynamic && !objectB.dynamic) return true;
  if (!canBeVertexSide(a) && !canBeVertexSide(b)) return true;
  const Frame& frameA = frames_[std::size_t(a)];
  const Frame& frameB = frames_[std::size_t(b)];
  if (!primitiveContacts(placePrimitive(objectA.shape, frameA.rotation, frameA.origin),
                         placePrimitive(objectB.shape, frameB.rotation, frameB.origin), tolerance,
                         manifold_))
    return false;
  out.droppedContacts += std::size_t(manifold_.dropped);
  // The body whose face carries the normal is the SDF side (n out of it).
  const bool sdfIsA = manifold_.normalFixedInA;
  const std::size_t first = out.rigid.size();
  for (int k = 0; k < manifold_.count; ++k) {
    const PrimitiveContact& c = manifold_.contacts[std::size_t(k)];
    ContactPointGeometry contact;
    contact.vertexSide = sdfIsA ? b : a;
    contact.sdfBody = sdfIsA ? a : b;
    contact.sample = k;
    contact.normal = sdfIsA ? Vector3(-c.normal) : c.normal;
    contact.vertexPoint = sdfIsA ? c.pointOnB : c.pointOnA;
    contact.surfacePoint = (sdfIsA ? c.pointOnA : c.pointOnB) + tolerance * contact.normal;
    contact.distance = c.separation - tolerance;
    contact.vertexRadius = sphereRadius((sdfIsA ? objectB : objectA).shape);
    contact.sdfRadius =
        contact.vertexRadius > 0 ? sphereRadius((sdfIsA ? objectA : objectB).shape) : Real(0);
    if (out.rigid.size() == out.rigid.capacity()) {
      ++out.droppedContacts;
      continue;
    }
    out.rigid.push_back(contact);
  }
  // Deepest first, ties by their index in the manifold, as a direction of samples (step 5).
  deepestFirst(out.rigid.begin() + static_cast<std::ptrdiff_t>(first), out.rigid.end());
  return true;
}

bool CollisionDetector::sphereMayTouch(const Vector3& centerWorld, Real radius, int sdfBody,
                                       Real tolerance) const {
  if (!(boxes_[std::size_t(sdfBody)].exteriorDistance(centerWorld) < radius)) return false;
  const Frame& frame = frames_[std::size_t(sdfBody)];
  const Vector3 local = frame.rotation.transpose() * (centerWorld - frame.origin);
  return rigid_[std::size_t(sdfBody)].shape.distance(local) - tolerance < radius;
}

template <typename Emit>
void CollisionDetector::testPoint(const Vector3& world, int sdfBody, Real tolerance,
                                  Emit&& emit) const {
  const Frame& frame = frames_[std::size_t(sdfBody)];
  const Vector3 local = frame.rotation.transpose() * (world - frame.origin);
  const CollisionShape& shape = rigid_[std::size_t(sdfBody)].shape;
  // The seed's grid test (CubicSDFCollisionObject::collisionTest) works in the grid's unscaled
  // frame and does not scale the distance back: d = φ_unscaled(x ⊙ s⁻¹) − tolerance, the
  // shell point (x ⊙ s⁻¹ − d n) ⊙ s. Kept with the seed's rules; exact (s = 1) otherwise.
  const bool unscaledGrid =
      seedGridDistance_ && shape.grid() && shape.gridScale() != Vector3::Ones();
  const Vector3 gridPoint =
      unscaledGrid ? Vector3(local.cwiseProduct(shape.gridScale().cwiseInverse())) : local;
  const DistanceSample sample =
      unscaledGrid ? shape.evaluateGrid(gridPoint) : shape.evaluate(local);
  const Real distance = sample.distance - tolerance;
  if (!(distance < 0)) return;
  const Real squared = sample.gradient.squaredNorm();
  if (squared < kMinimumSquaredGradient) return;  // no direction to push along
  const Vector3 normal = sample.gradient / std::sqrt(squared);
  const Vector3 shellPoint =
      unscaledGrid ? Vector3((gridPoint - distance * normal).cwiseProduct(shape.gridScale()))
                   : Vector3(local - distance * normal);
  ContactPointGeometry contact;
  contact.sdfBody = sdfBody;
  contact.vertexPoint = world;
  contact.surfacePoint = frame.rotation * shellPoint + frame.origin;
  contact.normal = frame.rotation * normal;
  contact.distance = distance;
  emit(contact);
}

void CollisionDetector::rigidAgainstRigid(int vertexBody, int sdfBody, Real tolerance,
                                          std::vector<ContactPointGeometry>& out,
                                          std::size_t& dropped) const {
  const RigidObject& body = rigid_[std::size_t(vertexBody)];
  const Frame& frame = frames_[std::size_t(vertexBody)];
  body.surface->hierarchy.traverse(
      [&](const PointBvh::Node& node) {
        return sphereMayTouch(frame.rotation * node.center + frame.origin, node.radius, sdfBody,
                              tolerance);
      },
      [&](int point) {
        const Vector3 world =
            frame.rotation * body.surface->samples[std::size_t(point)] + frame.origin;
        testPoint(world, sdfBody, tolerance, [&](ContactPointGeometry& contact) {
          contact.vertexSide = vertexBody;
          contact.sample = point;
          if (out.size() == out.capacity()) {
            ++dropped;
            return;
          }
          out.push_back(contact);
        });
      });
}

void CollisionDetector::particlesAgainstRigid(const ParticleModel& model,
                                              const ParticleStates& particles, int sdfBody,
                                              Real tolerance,
                                              std::vector<ContactPointGeometry>& out,
                                              std::size_t& dropped) const {
  const bool sdfStatic = !rigid_[std::size_t(sdfBody)].dynamic;
  model.hierarchy.traverse(
      [&](const PointBvh::Node& node) {
        return sphereMayTouch(node.center, node.radius, sdfBody, tolerance);
      },
      [&](int point) {
        const int particle = model.firstParticle + point;
        if (sdfStatic && !(particles.inverseMass[std::size_t(particle)] > 0)) return;
        testPoint(particles.position[std::size_t(particle)], sdfBody, tolerance,
                  [&](ContactPointGeometry& contact) {
                    contact.vertexSide = particle;
                    contact.sample = particle;
                    if (out.size() == out.capacity()) {
                      ++dropped;
                      return;
                    }
                    out.push_back(contact);
                  });
      });
}

void CollisionDetector::detect(const BodyStates& bodies, Real tolerance, ContactGeometryBuffer& out,
                               ContactOrder order) {
  out.rigid.clear();
  out.particle.clear();
  out.droppedContacts = 0;
  seedGridDistance_ = order == ContactOrder::Seed;
  updateFrames(bodies.rigid);
  updateBoxes(bodies, tolerance);
  out.droppedPairs = broadPhase_.findPairs(boxes_);
  collectDirections(tolerance, out);
  if (workers_) {
    detectInParallel(bodies, tolerance, out, order);
    return;
  }
  const int rigidCount = static_cast<int>(rigid_.size());
  for (const ObjectPair& direction : directions_) {
    std::vector<ContactPointGeometry>& list =
        direction.first < rigidCount ? out.rigid : out.particle;
    const std::size_t first = list.size();
    collectDirection(direction, bodies.particles, tolerance, out.rigid, out.particle,
                     out.droppedContacts);
    orderDirection(direction, list.begin() + static_cast<std::ptrdiff_t>(first), list.end(), order);
  }
}

void CollisionDetector::collectDirection(const ObjectPair& direction,
                                         const ParticleStates& particles, Real tolerance,
                                         std::vector<ContactPointGeometry>& rigidOut,
                                         std::vector<ContactPointGeometry>& particleOut,
                                         std::size_t& dropped) const {
  const int rigidCount = static_cast<int>(rigid_.size());
  if (direction.first < rigidCount)
    rigidAgainstRigid(direction.first, direction.second, tolerance, rigidOut, dropped);
  else
    particlesAgainstRigid(particleModels_[std::size_t(direction.first - rigidCount)], particles,
                          direction.second, tolerance, particleOut, dropped);
}

void CollisionDetector::orderDirection(const ObjectPair& direction,
                                       std::vector<ContactPointGeometry>::iterator begin,
                                       std::vector<ContactPointGeometry>::iterator end,
                                       ContactOrder order) const {
  const int rigidCount = static_cast<int>(rigid_.size());
  if (order == ContactOrder::Seed && direction.first < rigidCount &&
      !rigid_[std::size_t(direction.first)].seedRank.empty())
    seedOrder(begin, end, rigid_[std::size_t(direction.first)].seedRank);
  else if (order == ContactOrder::Seed && direction.first >= rigidCount) {
    const ParticleModel& model = particleModels_[std::size_t(direction.first - rigidCount)];
    seedOrder(begin, end, model.seedRank, model.firstParticle);
  } else
    deepestFirst(begin, end);
}

void CollisionDetector::detectInParallel(const BodyStates& bodies, Real tolerance,
                                         ContactGeometryBuffer& out, ContactOrder order) {
  // Contiguous ranges of directions with about equal work (the vertex side's point count).
  const int rigidCount = static_cast<int>(rigid_.size());
  auto work = [&](const ObjectPair& d) -> std::size_t {
    return d.first < rigidCount
               ? rigid_[std::size_t(d.first)].surface->samples.size() + 1
               : std::size_t(particleModels_[std::size_t(d.first - rigidCount)].particleCount) + 1;
  };
  std::size_t total = 0;
  for (const ObjectPair& d : directions_)
    total += work(d);
  const std::size_t partCount = parts_.size();
  std::size_t done = 0, direction = 0;
  for (std::size_t part = 0; part < partCount; ++part) {
    partBegin_[part] = direction;
    const std::size_t target = total * (part + 1) / partCount;
    while (direction < directions_.size() && (part + 1 == partCount || done < target))
      done += work(directions_[direction++]);
  }
  partBegin_[partCount] = directions_.size();

  struct Context {
    CollisionDetector* self;
    const ParticleStates* particles;
    Real tolerance;
  } context{this, &bodies.particles, tolerance};
  workers_->run(
      [](void* raw, int partIndex) {
        const Context& c = *static_cast<const Context*>(raw);
        CollisionDetector& d = *c.self;
        PartBuffers& part = d.parts_[std::size_t(partIndex)];
        part.rigid.clear();
        part.particle.clear();
        part.dropped = 0;
        for (std::size_t k = d.partBegin_[std::size_t(partIndex)];
             k < d.partBegin_[std::size_t(partIndex) + 1]; ++k) {
          const std::size_t before = part.rigid.size() + part.particle.size();
          d.collectDirection(d.directions_[k], *c.particles, c.tolerance, part.rigid, part.particle,
                             part.dropped);
          d.directionContacts_[k] = part.rigid.size() + part.particle.size() - before;
        }
      },
      &context);

  // In direction order: append up to the capacity (the serial detection's drops), then order.
  for (std::size_t p = 0; p < partCount; ++p) {
    const PartBuffers& part = parts_[p];
    out.droppedContacts += part.dropped;
    std::size_t rigidAt = 0, particleAt = 0;
    for (std::size_t k = partBegin_[p]; k < partBegin_[p + 1]; ++k) {
      const bool rigidSide = directions_[k].first < rigidCount;
      std::vector<ContactPointGeometry>& list = rigidSide ? out.rigid : out.particle;
      const std::vector<ContactPointGeometry>& source = rigidSide ? part.rigid : part.particle;
      std::size_t& at = rigidSide ? rigidAt : particleAt;
      const std::size_t count = directionContacts_[k];
      const std::size_t room = list.capacity() - list.size();
      const std::size_t kept = std::min(count, room);
      const std::size_t first = list.size();
      const auto from = source.begin() + static_cast<std::ptrdiff_t>(at);
      list.insert(list.end(), from, from + static_cast<std::ptrdiff_t>(kept));
      out.droppedContacts += count - kept;
      at += count;
      orderDirection(directions_[k], list.begin() + static_cast<std::ptrdiff_t>(first), list.end(),
                     order);
    }
  }
}

}  // namespace pbd
