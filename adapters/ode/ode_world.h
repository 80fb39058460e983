// The ODE model of a Scene's rigid bodies and collision shapes.
//
// Frames. ODE needs a body's frame at its centre of mass; with a diagonal inertia it must also
// be the principal frame. A dynamic body is therefore placed at x_c = T + R c with orientation
// q_p = R P (T, R the scene frame's pose; c, P the centre of mass and principal rotation in the
// scene frame), its mass properties given explicitly (dMassSetParameters: mass, principal
// moments, no products, centre at the origin). Its geom sits in the scene frame, offset from the
// body by P⁻¹(s − c) and P⁻¹ S (s, S the shape's pose in the scene frame). Reading back undoes
// it: scene rotation = q_p ⊗ P⁻¹. A static body is a geom without a body, posed in the world.
//
// Shapes (`collisionObjectType`): sphere, box and cylinder are ODE primitives (ODE's cylinder
// axis is z, the seed's is y: S = rotation by −90° about x); torus and SDF collide the body's
// mesh as a trimesh; hollow shapes have no ODE counterpart (odeFeatures(), ode_features.cpp).
//
// Contacts (collide()): every pair of geoms whose bounding boxes overlap, except static–static,
// gets up to maxContacts points from dCollide, each a contact joint with the pair's friction
// and restitution from Scene::pairMaterial: Coulomb friction as ODE's pyramid (dContactApprox1:
// the limit is μ times the normal force) with its first direction fdir1 along world x
// projected onto the contact plane (world z when the normal is within 30° of x), restitution as
// `bounce` with no velocity threshold (bounce_vel 0), softness soft_erp/soft_cfm. Bodies
// joined by a joint collide too, as in the seed.
#pragma once

#include <ode/ode.h>

#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "adapters/ode/ode_settings.h"

namespace pbdval::ode {

inline Vector3 fromOde(const dReal* v) {
  return Vector3(v[0], v[1], v[2]);
}
inline Quaternion quaternionFromOde(const dReal* q) {
  return Quaternion(q[0], q[1], q[2], q[3]);
}
inline void toOde(const Quaternion& q, dQuaternion out) {
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}

/// One contact point handed to ODE in the last step (tests and diagnostics).
struct ContactRecord {
  int body1 = -1;  ///< scene index of the first geom's body
  int body2 = -1;
  double friction = 0;     ///< surface.mu
  double restitution = 0;  ///< surface.bounce
  Vector3 position = Vector3::Zero();
  Vector3 normal = Vector3::Zero();
  double depth = 0;
};

/// The friction pyramid's first direction for a contact normal (see the file comment).
Vector3 frictionDirection(const Vector3& normal);

class OdeWorld {
 public:
  /// Builds the world, bodies and geoms. `scene` must outlive the OdeWorld. Call inside an
  /// OdeCall; throws EngineError.
  OdeWorld(const pbd::Scene& scene, const OdeSettings& settings);
  ~OdeWorld();
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  dWorldID id() const { return world_.get(); }
  /// The ODE body of scene body `sceneIndex`; null for a static body.
  dBodyID body(int sceneIndex) const;
  /// The geom of scene body `sceneIndex`; null when it has no collision shape.
  dGeomID geom(int sceneIndex) const;

  /// A body that is not part of the scene (a ball-on-line carriage), with isotropic inertia.
  dBodyID addAuxiliaryBody(double mass, double inertia, const Vector3& position);
  std::size_t auxiliaryBodyCount() const { return auxiliaryBodies_; }

  /// Collision detection: contact joints for the coming step.
  void collide();
  /// Removes the contact joints (after the step).
  void clearContacts();
  const std::vector<ContactRecord>& contacts() const { return contacts_; }

  /// Scene body `sceneIndex` in the scene's frames (static bodies at their initial pose).
  BodyState state(int sceneIndex) const;

 private:
  struct ThreadingDeleter {
    void operator()(dxThreadingImplementation* t) const { dThreadingFreeImplementation(t); }
  };
  struct WorldDeleter {
    void operator()(dxWorld* w) const { dWorldDestroy(w); }
  };
  struct SpaceDeleter {
    void operator()(dxSpace* s) const { dSpaceDestroy(s); }
  };
  struct JointGroupDeleter {
    void operator()(dxJointGroup* g) const { dJointGroupDestroy(g); }
  };
  struct TriMesh;  // ODE's trimesh data and the index array it points into

  void configureWorld();
  dBodyID createBody(const pbd::RigidBodyDesc& desc);
  dGeomID createGeom(const pbd::RigidBodyDesc& desc, int sceneIndex, dBodyID body);
  dGeomID createShape(const pbd::RigidBodyDesc& desc);
  /// dSpaceCollide's callback: never lets an exception out into ODE (see collide()).
  static void nearCallback(void* self, dGeomID a, dGeomID b) noexcept;
  void addContacts(dGeomID a, dGeomID b);

  const pbd::Scene& scene_;
  OdeSettings settings_;
  // Destroyed in reverse order: contact joints, geoms, trimesh data, the world (bodies and
  // joints), then the world's step scheduler.
  std::unique_ptr<dxThreadingImplementation, ThreadingDeleter> threading_;
  std::unique_ptr<dxWorld, WorldDeleter> world_;
  std::vector<std::unique_ptr<TriMesh>> triMeshes_;
  std::unique_ptr<dxSpace, SpaceDeleter> space_;
  std::unique_ptr<dxJointGroup, JointGroupDeleter> contactJoints_;
  std::vector<dBodyID> bodies_;  ///< by scene index; null for static bodies
  std::vector<dGeomID> geoms_;   ///< by scene index; null without a shape
  std::size_t auxiliaryBodies_ = 0;
  std::vector<dContact> contactBuffer_;
  std::vector<ContactRecord> contacts_;
  std::exception_ptr callbackFailure_;  ///< the first error in nearCallback during collide()
};

}  // namespace pbdval::ode
