#include "adapters/ode/ode_world.h"

#include <cmath>
#include <cstdint>
#include <exception>
#include <utility>

namespace pbdval::ode {
namespace {

using pbd::CollisionObjectType;

static_assert(sizeof(Vector3) == 3 * sizeof(double), "trimesh vertices are read in place");

/// ODE's cylinder axis is its z axis, the seed's is y: rotating by −90° about x maps z to y.
Quaternion cylinderAxisRotation() {
  return Quaternion(pbd::AngleAxis(Real(-M_PI / 2), Vector3::UnitX()));
}

void* geomTag(int sceneIndex) {
  return reinterpret_cast<void*>(static_cast<std::intptr_t>(sceneIndex));
}
int sceneIndexOf(dGeomID geom) {
  return static_cast<int>(reinterpret_cast<std::intptr_t>(dGeomGetData(geom)));
}

}  // namespace

struct OdeWorld::TriMesh {
  std::shared_ptr<const pbd::TriangleMesh> mesh;  // the vertices ODE reads in place
  std::vector<dTriIndex> indices;
  dTriMeshDataID data = nullptr;

  explicit TriMesh(std::shared_ptr<const pbd::TriangleMesh> triangles)
      : mesh(std::move(triangles)), data(dGeomTriMeshDataCreate()) {
    indices.reserve(mesh->triangles.size() * 3);
    for (const auto& triangle : mesh->triangles)
      for (const int vertex : triangle)
        indices.push_back(static_cast<dTriIndex>(vertex));
    dGeomTriMeshDataBuildDouble(data, mesh->vertices.data(), int(sizeof(Vector3)),
                                int(mesh->vertices.size()), indices.data(), int(indices.size()),
                                int(3 * sizeof(dTriIndex)));
  }
  ~TriMesh() { dGeomTriMeshDataDestroy(data); }
  TriMesh(const TriMesh&) = delete;
  TriMesh& operator=(const TriMesh&) = delete;
};

Vector3 frictionDirection(const Vector3& normal) {
  Vector3 direction = Vector3::UnitX() - normal * normal.x();
  if (direction.norm() < Real(0.5)) direction = Vector3::UnitZ() - normal * normal.z();
  return direction.normalized();
}

OdeWorld::OdeWorld(const pbd::Scene& scene, const OdeSettings& settings)
    : scene_(scene),
      settings_(settings),
      threading_(dThreadingAllocateSelfThreadedImplementation()),
      world_(dWorldCreate()),
      space_(dHashSpaceCreate(nullptr)),
      contactJoints_(dJointGroupCreate(0)),
      contactBuffer_(static_cast<std::size_t>(settings.maxContacts)) {
  if (!threading_) throw EngineError("ODE: dThreadingAllocateSelfThreadedImplementation failed");
  // The world's own (single-threaded) step scheduler instead of ODE's process-wide default: an
  // ODE error inside a step unwinds out of it with jobs still queued, and the queue that holds
  // them must be this world's, dropped with it (OdeEngine::destroyModel), not the process's,
  // whose destructor in dCloseODE would find the stale jobs and end the process.
  dWorldSetStepThreadingImplementation(
      world_.get(), dThreadingImplementationGetFunctions(threading_.get()), threading_.get());
  configureWorld();
  const int count = static_cast<int>(scene.rigidBodies.size());
  bodies_.assign(scene.rigidBodies.size(), nullptr);
  geoms_.assign(scene.rigidBodies.size(), nullptr);
  for (int i = 0; i < count; ++i) {
    const pbd::RigidBodyDesc& desc = scene.rigidBodies[static_cast<std::size_t>(i)];
    if (desc.isDynamic) bodies_[std::size_t(i)] = createBody(desc);
    geoms_[std::size_t(i)] = createGeom(desc, i, bodies_[std::size_t(i)]);
  }
}

OdeWorld::~OdeWorld() = default;

// Every setting that could differ from the parity rules is set explicitly, defaults included.
void OdeWorld::configureWorld() {
  dWorldID w = world_.get();
  const Vector3& g = scene_.simulation.gravitation;
  dWorldSetGravity(w, g.x(), g.y(), g.z());
  dWorldSetERP(w, settings_.erp);
  dWorldSetCFM(w, settings_.cfm);
  dWorldSetQuickStepNumIterations(w, settings_.iterations);
  dWorldSetQuickStepW(w, settings_.overRelaxation);
  dWorldSetAutoDisableFlag(w, 0);
  dWorldSetDamping(w, 0, 0);
  dWorldSetMaxAngularSpeed(w, dInfinity);
  dWorldSetContactMaxCorrectingVel(w, dInfinity);
  dWorldSetContactSurfaceLayer(w, 0);
}

dBodyID OdeWorld::createBody(const pbd::RigidBodyDesc& desc) {
  const pbd::MassProperties& m = desc.massProperties;
  dBodyID body = dBodyCreate(world_.get());
  dMass mass;
  dMassSetZero(&mass);
  dMassSetParameters(&mass, m.mass, 0, 0, 0, m.principalInertia.x(), m.principalInertia.y(),
                     m.principalInertia.z(), 0, 0, 0);
  dBodySetMass(body, &mass);
  const Vector3 centerOfMass = desc.initialCenterOfMass();
  dBodySetPosition(body, centerOfMass.x(), centerOfMass.y(), centerOfMass.z());
  dQuaternion rotation;
  toOde(desc.initialPrincipalRotation(), rotation);
  dBodySetQuaternion(body, rotation);
  dBodySetLinearVel(body, desc.velocity.x(), desc.velocity.y(), desc.velocity.z());
  dBodySetAngularVel(body, desc.angularVelocity.x(), desc.angularVelocity.y(),
                     desc.angularVelocity.z());
  dBodySetGyroscopicMode(body, settings_.gyroscopic ? 1 : 0);
  dBodySetFiniteRotationMode(body, 0);
  dBodySetAutoDisableFlag(body, 0);
  dBodySetDamping(body, 0, 0);
  return body;
}

dBodyID OdeWorld::addAuxiliaryBody(double mass, double inertia, const Vector3& position) {
  dBodyID body = dBodyCreate(world_.get());
  dMass m;
  dMassSetZero(&m);
  dMassSetParameters(&m, mass, 0, 0, 0, inertia, inertia, inertia, 0, 0, 0);
  dBodySetMass(body, &m);
  dBodySetPosition(body, position.x(), position.y(), position.z());
  dBodySetGyroscopicMode(body, settings_.gyroscopic ? 1 : 0);
  dBodySetAutoDisableFlag(body, 0);
  dBodySetDamping(body, 0, 0);
  ++auxiliaryBodies_;
  return body;
}

dGeomID OdeWorld::createShape(const pbd::RigidBodyDesc& desc) {
  const pbd::CollisionObjectDesc& c = desc.collision;
  dSpaceID space = space_.get();
  switch (c.type) {
    case CollisionObjectType::Sphere:
      return dCreateSphere(space, c.scale.x());
    case CollisionObjectType::Box:
      return dCreateBox(space, c.scale.x(), c.scale.y(), c.scale.z());
    case CollisionObjectType::Cylinder:
      return dCreateCylinder(space, c.scale.x(), c.scale.y());
    case CollisionObjectType::Torus:
    case CollisionObjectType::SignedDistanceField:
      triMeshes_.push_back(std::make_unique<TriMesh>(desc.mesh));
      return dCreateTriMesh(space, triMeshes_.back()->data, nullptr, nullptr, nullptr);
    case CollisionObjectType::None:
    case CollisionObjectType::HollowSphere:
    case CollisionObjectType::HollowBox:
      break;
  }
  return nullptr;
}

// Shapes sit at the scene frame's origin, in its axes (the cylinder turned to y).
dGeomID OdeWorld::createGeom(const pbd::RigidBodyDesc& desc, int sceneIndex, dBodyID body) {
  dGeomID geom = createShape(desc);
  if (geom == nullptr) return nullptr;
  dGeomSetData(geom, geomTag(sceneIndex));
  const Quaternion shapeRotation = desc.collision.type == CollisionObjectType::Cylinder
                                       ? cylinderAxisRotation()
                                       : Quaternion::Identity();
  dQuaternion q;
  if (body == nullptr) {
    dGeomSetPosition(geom, desc.translation.x(), desc.translation.y(), desc.translation.z());
    toOde((desc.rotation * shapeRotation).normalized(), q);
    dGeomSetQuaternion(geom, q);
    return geom;
  }
  dGeomSetBody(geom, body);
  const Quaternion toPrincipal = desc.massProperties.principalRotation.conjugate();
  const Vector3 offset = toPrincipal * (-desc.massProperties.centerOfMass);
  dGeomSetOffsetPosition(geom, offset.x(), offset.y(), offset.z());
  toOde((toPrincipal * shapeRotation).normalized(), q);
  dGeomSetOffsetQuaternion(geom, q);
  return geom;
}

dBodyID OdeWorld::body(int sceneIndex) const {
  return bodies_.at(std::size_t(sceneIndex));
}
dGeomID OdeWorld::geom(int sceneIndex) const {
  return geoms_.at(std::size_t(sceneIndex));
}

void OdeWorld::collide() {
  contacts_.clear();
  callbackFailure_ = nullptr;
  dSpaceCollide(space_.get(), this, &OdeWorld::nearCallback);
  // An error in a pair's collision (ours, or ODE's handlers' EngineError from inside dCollide)
  // was caught in the callback, so that no exception unwinds through ODE's collision loop
  // (C frames); it is thrown here, with ODE back in our code.
  if (callbackFailure_) std::rethrow_exception(std::exchange(callbackFailure_, nullptr));
}

void OdeWorld::clearContacts() {
  dJointGroupEmpty(contactJoints_.get());
}

void OdeWorld::nearCallback(void* self, dGeomID a, dGeomID b) noexcept {
  OdeWorld& world = *static_cast<OdeWorld*>(self);
  if (world.callbackFailure_) return;  // the step fails anyway: no more pairs
  try {
    world.addContacts(a, b);
  } catch (...) {
    world.callbackFailure_ = std::current_exception();
  }
}

void OdeWorld::addContacts(dGeomID a, dGeomID b) {
  dBodyID bodyA = dGeomGetBody(a);
  dBodyID bodyB = dGeomGetBody(b);
  if (bodyA == nullptr && bodyB == nullptr) return;  // static–static
  // Bodies joined by a joint collide, as in the seed: no dAreConnected filter here.
  const int count =
      dCollide(a, b, settings_.maxContacts, &contactBuffer_[0].geom, sizeof(dContact));
  if (count == 0) return;
  const int indexA = sceneIndexOf(a), indexB = sceneIndexOf(b);
  const pbd::ContactMaterial material = scene_.pairMaterial(indexA, indexB);
  for (int k = 0; k < count; ++k) {
    dContact& contact = contactBuffer_[std::size_t(k)];
    dSurfaceParameters& surface = contact.surface;
    surface = dSurfaceParameters{};
    surface.mode = dContactApprox1 | dContactFDir1 | dContactSoftERP | dContactSoftCFM;
    if (material.restitution > 0) surface.mode |= dContactBounce;
    surface.mu = material.friction;
    surface.bounce = material.restitution;
    surface.bounce_vel = 0;
    surface.soft_erp = settings_.contactErp;
    surface.soft_cfm = settings_.contactCfm;
    const Vector3 normal = fromOde(contact.geom.normal);
    const Vector3 direction = frictionDirection(normal);
    contact.fdir1[0] = direction.x();
    contact.fdir1[1] = direction.y();
    contact.fdir1[2] = direction.z();
    dJointAttach(dJointCreateContact(world_.get(), contactJoints_.get(), &contact), bodyA, bodyB);
    contacts_.push_back({indexA, indexB, surface.mu, surface.bounce, fromOde(contact.geom.pos),
                         normal, contact.geom.depth});
  }
}

BodyState OdeWorld::state(int sceneIndex) const {
  const pbd::RigidBodyDesc& desc = scene_.rigidBodies[std::size_t(sceneIndex)];
  BodyState s;
  s.id = desc.id;
  dBodyID b = bodies_[std::size_t(sceneIndex)];
  if (b == nullptr) {
    s.position = desc.initialCenterOfMass();
    s.rotation = desc.rotation;
    return s;
  }
  s.position = fromOde(dBodyGetPosition(b));
  s.rotation =
      quaternionFromOde(dBodyGetQuaternion(b)) * desc.massProperties.principalRotation.conjugate();
  s.velocity = fromOde(dBodyGetLinearVel(b));
  s.angularVelocity = fromOde(dBodyGetAngularVel(b));
  return s;
}

}  // namespace pbdval::ode
