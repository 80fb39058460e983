#include "pbd/contacts/xpbd_contact.h"

#include <algorithm>
#include <cmath>

#include "pbd/math/quaternion.h"

namespace pbd {
namespace {

// The helpers are inlined into the four contact functions: GCC kept most of them as calls (the
// frame, the responses, the impulses: a tenth of the contact's instructions were the calls and
// the copies of their results), and inlined, the parts of a frame that a row does not read are
// never computed. The arithmetic and its order are unchanged (bitwise the same results).
#if defined(__GNUC__)
#define PBD_INLINE inline __attribute__((always_inline))
#define PBD_INLINE_LAMBDA __attribute__((always_inline))
#else
#define PBD_INLINE inline
#define PBD_INLINE_LAMBDA
#endif

std::size_t at(int index) {
  return static_cast<std::size_t>(index);
}

/// The bodies' rotations as the rows read them: the quaternions of the current poses (the
/// position pass, where every row moves them), or rotation matrices formed once for a pass in
/// which the poses do not change (the approach velocities and the velocity pass: a matrix turns
/// a vector in 15 operations where a quaternion takes 30).
struct QuaternionRotations {
  const RigidBodyStates& bodies;
  PBD_INLINE Vector3 toWorld(int body, const Vector3& v) const {
    return rotateVector(bodies.rotation[at(body)], v);
  }
  PBD_INLINE Vector3 toBody(int body, const Vector3& v) const {
    return rotateVectorInverse(bodies.rotation[at(body)], v);
  }
};
struct MatrixRotations {
  const std::vector<Matrix3>& matrices;
  PBD_INLINE Vector3 toWorld(int body, const Vector3& v) const { return matrices[at(body)] * v; }
  PBD_INLINE Vector3 toBody(int body, const Vector3& v) const {
    return matrices[at(body)].transpose() * v;
  }
};

/// One body's response to a unit impulse along the unit direction d at lever r, from
/// u = Rᵀ (r × d), r × d in the body's principal frame (R the body's rotation q): the inverse
/// mass w = m⁻¹ + uᵀ D u (D = diag(I⁻¹)) and the rotation per unit impulse D u, also in the
/// principal frame (I_w⁻¹ (r × d) = R D u). A position row turns the body in its own frame,
/// q ← normalize(q + ½ q ⊗ [0, λ D u]) (the same update as ½ [0, R λ D u] ⊗ q), so it never
/// rotates D u back; a velocity row rotates it once. Zero for static bodies.
struct Response {
  bool dynamic = false;
  Real inverseMass = 0;                               ///< m⁻¹
  Real generalizedInverseMass = 0;                    ///< w
  Vector3 localRotationPerImpulse = Vector3::Zero();  ///< D u
};

PBD_INLINE Response localResponse(const RigidBodyStates& b, std::size_t i, const Vector3& u) {
  Response r;
  r.dynamic = true;
  r.inverseMass = b.inverseMass[i];
  r.localRotationPerImpulse = b.inverseInertia[i].cwiseProduct(u);
  r.generalizedInverseMass = r.inverseMass + u.dot(r.localRotationPerImpulse);
  return r;
}

/// The response of `body` at lever r (world) along d (world): one inverse rotation.
template <typename Rotations>
PBD_INLINE Response rigidResponse(const RigidBodyStates& b, const Rotations& rotations, int body,
                                  const Vector3& lever, const Vector3& direction) {
  const std::size_t i = at(body);
  if (!b.isDynamic(i)) return {};
  return localResponse(b, i, rotations.toBody(body, lever.cross(direction)));
}

/// The response of `body` given u = Rᵀ (r × d) itself (no rotation).
PBD_INLINE Response rigidResponseFromLocal(const RigidBodyStates& b, int body, const Vector3& u) {
  const std::size_t i = at(body);
  if (!b.isDynamic(i)) return {};
  return localResponse(b, i, u);
}

/// q ← normalize(q + ½ q ⊗ [0, θ]) for a turn θ in the body's principal frame
/// (q ⊗ [0, θ] = [−q_v·θ, q_w θ + q_v × θ]: 20 operations where the full product takes 28).
PBD_INLINE void turnInBodyFrame(Quaternion& q, const Vector3& turn) {
  const Real scalar = -q.vec().dot(turn);
  const Vector3 vector = q.w() * turn + q.vec().cross(turn);
  q.w() += Real(0.5) * scalar;
  q.vec() += Real(0.5) * vector;
  q.normalize();
}

/// A positional impulse λ d on a rigid body: x += m⁻¹ λ d, q ← normalize(q + ½ q ⊗ [0, λ D u]).
PBD_INLINE void applyRigidPosition(RigidBodyStates& b, int body, const Response& r,
                                   const Vector3& direction, Real magnitude) {
  if (!r.dynamic) return;
  const std::size_t i = at(body);
  b.position[i] += (magnitude * r.inverseMass) * direction;
  turnInBodyFrame(b.rotation[i], magnitude * r.localRotationPerImpulse);
}

/// A velocity impulse λ d on a rigid body: v += m⁻¹ λ d, ω += λ R D u (= λ I_w⁻¹ (r × d)).
PBD_INLINE void applyRigidVelocity(RigidBodyStates& b, const MatrixRotations& rotations, int body,
                                   const Response& r, const Vector3& direction, Real magnitude) {
  if (!r.dynamic) return;
  const std::size_t i = at(body);
  b.velocity[i] += (magnitude * r.inverseMass) * direction;
  b.angularVelocity[i] += rotations.toWorld(body, magnitude * r.localRotationPerImpulse);
}

PBD_INLINE Vector3 rigidPointVelocity(const RigidBodyStates& b, int body, const Vector3& lever) {
  return b.velocity[at(body)] + b.angularVelocity[at(body)].cross(lever);
}

/// The contact at the current poses. The normal row acts between p₀ and p₁ (for spheres their
/// support points), the static friction between the friction point p₀ᵐ and the anchor; for
/// every contact but a sphere's they are the same points.
struct ContactFrame {
  Vector3 point, surface;            ///< p₀, p₁ (normal row)
  Vector3 pointLever, surfaceLever;  ///< r₀ (zero for a particle), r₁
  Vector3 material, anchor;          ///< p₀ᵐ, the anchor (static friction)
  Vector3 materialLever, anchorLever;
  Vector3 normal;
  /// The normal row's surface point is the anchor R₁ a₁ and n = R₁ n₁ (every contact but a
  /// sphere–sphere pair): then R₁ᵀ (r₁ × n) = a₁ × n₁, body 1's normal response without a
  /// rotation.
  bool surfaceIsAnchor = true;
};

/// The contact's frame at the current poses. `frictionPoints`: also the friction point and the
/// anchor of a sphere's contact (the normal row and the velocity pass do not need them; for
/// every other contact they are the normal row's points anyway).
template <typename Rotations>
PBD_INLINE ContactFrame currentFrame(const XpbdContact& c, const BodyStates& bodies,
                                     const Rotations& rotations, bool frictionPoints = true) {
  const RigidBodyStates& b = bodies.rigid;
  ContactFrame f;
  const auto q1 = [&](const Vector3& v) PBD_INLINE_LAMBDA { return rotations.toWorld(c.body, v); };
  const auto q0 = [&](const Vector3& v) PBD_INLINE_LAMBDA { return rotations.toWorld(c.point, v); };
  const Vector3& x1 = b.position[at(c.body)];
  if (!(c.pointRadius > 0)) {
    f.anchorLever = q1(c.surfaceLocal);
    f.anchor = x1 + f.anchorLever;
    if (c.pointIsParticle) {
      f.material = bodies.particles.position[at(c.point)];
      f.materialLever = Vector3::Zero();
    } else {
      f.materialLever = q0(c.pointLocal);
      f.material = b.position[at(c.point)] + f.materialLever;
    }
    f.normal = q1(c.normalLocal);
    f.surface = f.anchor;
    f.surfaceLever = f.anchorLever;
    f.point = f.material;
    f.pointLever = f.materialLever;
    return f;
  }
  // A sphere (body 0): its centre, usually its centre of mass (no rotation needed then).
  const Vector3& x0 = b.position[at(c.point)];
  const Vector3 center0 = c.pointCenterLocal.isZero(0) ? x0 : Vector3(x0 + q0(c.pointCenterLocal));
  if (c.bodyRadius > 0) {
    const Vector3 center1 = c.bodyCenterLocal.isZero(0) ? x1 : Vector3(x1 + q1(c.bodyCenterLocal));
    const Vector3 between = center0 - center1;
    const Real length = between.norm();
    // Coincident centres: the detected normal.
    f.normal = length > 0 ? Vector3(between / length) : Vector3(q1(c.normalLocal));
    f.surfaceIsAnchor = false;
    f.surface = center1 + c.bodyRadius * f.normal;
    f.surfaceLever = f.surface - x1;
    if (frictionPoints) {
      f.anchorLever = q1(c.surfaceLocal);
      f.anchor = x1 + f.anchorLever;
    }
  } else {
    f.normal = q1(c.normalLocal);
    f.anchorLever = q1(c.surfaceLocal);
    f.anchor = x1 + f.anchorLever;
    f.surface = f.anchor;
    f.surfaceLever = f.anchorLever;
  }
  f.point = center0 - c.pointRadius * f.normal;
  f.pointLever = f.point - x0;
  if (frictionPoints) {
    f.materialLever = q0(c.pointLocal);
    f.material = x0 + f.materialLever;
  }
  return f;
}

/// Re-evaluates body 0's point p₀ = p₀ᵐ of a frame (every contact but a sphere's) at the
/// current pose, as currentFrame does.
template <typename Rotations>
PBD_INLINE void refreshPoint(const XpbdContact& c, const BodyStates& bodies,
                             const Rotations& rotations, ContactFrame& f) {
  if (c.pointIsParticle) {
    f.material = bodies.particles.position[at(c.point)];
    f.materialLever = Vector3::Zero();
  } else {
    f.materialLever = rotations.toWorld(c.point, c.pointLocal);
    f.material = bodies.rigid.position[at(c.point)] + f.materialLever;
  }
  f.point = f.material;
  f.pointLever = f.materialLever;
}

/// The responses of body 0 at lever r₀ and body 1 at r₁ along d (a particle: m⁻¹, no rotation).
struct PairResponse {
  Response point, surface;
  Real inverseMass() const { return point.generalizedInverseMass + surface.generalizedInverseMass; }
};

template <typename Rotations>
PBD_INLINE PairResponse pairResponse(const XpbdContact& c, const BodyStates& bodies,
                                     const Rotations& rotations, const Vector3& pointLever,
                                     const Vector3& surfaceLever, const Vector3& direction) {
  PairResponse r;
  if (c.pointIsParticle) {
    r.point.inverseMass = r.point.generalizedInverseMass =
        bodies.particles.inverseMass[at(c.point)];
  } else {
    r.point = rigidResponse(bodies.rigid, rotations, c.point, pointLever, direction);
  }
  r.surface = rigidResponse(bodies.rigid, rotations, c.body, surfaceLever, direction);
  return r;
}

/// The responses along the contact's normal at the normal row's points.
template <typename Rotations>
PBD_INLINE PairResponse normalResponse(const XpbdContact& c, const BodyStates& bodies,
                                       const Rotations& rotations, const ContactFrame& f) {
  if (!f.surfaceIsAnchor)
    return pairResponse(c, bodies, rotations, f.pointLever, f.surfaceLever, f.normal);
  PairResponse r;
  if (c.pointIsParticle) {
    r.point.inverseMass = r.point.generalizedInverseMass =
        bodies.particles.inverseMass[at(c.point)];
  } else {
    r.point = rigidResponse(bodies.rigid, rotations, c.point, f.pointLever, f.normal);
  }
  r.surface = rigidResponseFromLocal(bodies.rigid, c.body, c.surfaceLocal.cross(c.normalLocal));
  return r;
}

/// +λ d on body 0, −λ d on body 1 (positions).
PBD_INLINE void applyPositionImpulse(const XpbdContact& c, BodyStates& bodies,
                                     const PairResponse& r, const Vector3& direction,
                                     Real magnitude) {
  if (c.pointIsParticle)
    bodies.particles.position[at(c.point)] += (magnitude * r.point.inverseMass) * direction;
  else
    applyRigidPosition(bodies.rigid, c.point, r.point, direction, magnitude);
  applyRigidPosition(bodies.rigid, c.body, r.surface, direction, -magnitude);
}

/// +λ d on body 0, −λ d on body 1 (velocities).
PBD_INLINE void applyVelocityImpulse(const XpbdContact& c, BodyStates& bodies,
                                     const MatrixRotations& rotations, const PairResponse& r,
                                     const Vector3& direction, Real magnitude) {
  if (c.pointIsParticle)
    bodies.particles.velocity[at(c.point)] += (magnitude * r.point.inverseMass) * direction;
  else
    applyRigidVelocity(bodies.rigid, rotations, c.point, r.point, direction, magnitude);
  applyRigidVelocity(bodies.rigid, rotations, c.body, r.surface, direction, -magnitude);
}

/// u = (v₀ + ω₀ × r₀) − (v₁ + ω₁ × r₁) at p₀ and p₁.
PBD_INLINE Vector3 relativeVelocity(const XpbdContact& c, const BodyStates& bodies,
                                    const ContactFrame& f) {
  const Vector3 u0 = c.pointIsParticle ? bodies.particles.velocity[at(c.point)]
                                       : rigidPointVelocity(bodies.rigid, c.point, f.pointLever);
  return u0 - rigidPointVelocity(bodies.rigid, c.body, f.surfaceLever);
}

/// The tangential part of v for the unit normal n.
PBD_INLINE Vector3 tangentialPart(const Vector3& v, const Vector3& normal) {
  return v - normal.dot(v) * normal;
}

/// Anchor ← p₀ᵐ − (n·(p₀ᵐ − p₁)) n: the anchor moves under the friction point, keeping the
/// separation from the surface point p₁.
PBD_INLINE void reanchor(XpbdContact& c, const BodyStates& bodies, const ContactFrame& f) {
  const Vector3 anchor = f.material - f.normal.dot(f.material - f.surface) * f.normal;
  c.surfaceLocal = rotateVectorInverse(bodies.rigid.rotation[at(c.body)],
                                       anchor - bodies.rigid.position[at(c.body)]);
}

#undef PBD_INLINE
#undef PBD_INLINE_LAMBDA

}  // namespace

void XpbdContact::init(const ContactPointGeometry& geometry, bool particle,
                       const BodyStates& bodies, const ContactMaterial& material,
                       Real contactTolerance) {
  const RigidBodyStates& b = bodies.rigid;
  point = geometry.vertexSide;
  pointIsParticle = particle;
  body = geometry.sdfBody;
  // The detector's surfacePoint lies on the tolerance shell; the body's surface is
  // contactTolerance further in along the normal.
  const Vector3 surface = geometry.surfacePoint - contactTolerance * geometry.normal;
  const Quaternion inverse1 = b.rotation[at(body)].conjugate();
  surfaceLocal = inverse1 * (surface - b.position[at(body)]);
  normalLocal = inverse1 * geometry.normal;
  pointLocal = particle ? Vector3::Zero()
                        : Vector3(b.rotation[at(point)].conjugate() *
                                  (geometry.vertexPoint - b.position[at(point)]));
  // A sphere's centre, from its support point (docs in the header: "Spheres").
  pointRadius = particle ? Real(0) : geometry.vertexRadius;
  bodyRadius = pointRadius > 0 ? geometry.sdfRadius : Real(0);
  // A sphere's centre is its scene frame's origin (its SDF |x| − r), in the principal frame:
  // exactly zero when it is the centre of mass, which spares the frame a rotation.
  const auto sceneOrigin = [&b](int i) -> Vector3 {
    return b.principalInScene[at(i)].conjugate() * Vector3(-b.centerOfMassInScene[at(i)]);
  };
  pointCenterLocal = pointRadius > 0 ? sceneOrigin(point) : Vector3::Zero();
  bodyCenterLocal = bodyRadius > 0 ? sceneOrigin(body) : Vector3::Zero();
  friction = material.friction;
  restitution = material.restitution;
  normalMultiplier = 0;
  tangentMultiplier = 0;
  approachVelocity = 0;
}

void XpbdContact::followSupportPoint(const BodyStates& bodies) {
  if (!(pointRadius > 0)) return;
  const ContactFrame f = currentFrame(*this, bodies, QuaternionRotations{bodies.rigid});
  const Vector3 slip = tangentialPart(f.material - f.anchor, f.normal);  // not yet undone
  const Vector3 anchor = f.point - slip - f.normal.dot(f.point - f.surface) * f.normal;
  const RigidBodyStates& b = bodies.rigid;
  pointLocal = rotateVectorInverse(b.rotation[at(point)], f.point - b.position[at(point)]);
  surfaceLocal = rotateVectorInverse(b.rotation[at(body)], anchor - b.position[at(body)]);
}

void XpbdContact::beginSubstep(const BodyStates& bodies, const std::vector<Matrix3>& rotations) {
  normalMultiplier = 0;
  tangentMultiplier = 0;
  if (!(restitution > 0)) return;  // ṽ_n only sets the restitution target (e = 0: none)
  const ContactFrame f =
      currentFrame(*this, bodies, MatrixRotations{rotations}, /*frictionPoints=*/false);
  approachVelocity = f.normal.dot(relativeVelocity(*this, bodies, f));
}

void XpbdContact::solvePosition(BodyStates& bodies, Real substepSize, Real compliance) {
  const QuaternionRotations rotations{bodies.rigid};
  ContactFrame f = currentFrame(*this, bodies, rotations, /*frictionPoints=*/false);
  const Real c = f.normal.dot(f.point - f.surface);
  if (!(c < 0)) {
    // Not touching: the anchor follows the point.
    reanchor(*this, bodies, pointRadius > 0 ? currentFrame(*this, bodies, rotations) : f);
    return;
  }
  // Normal row.
  const Real scaledCompliance = compliance / (substepSize * substepSize);  // α̃ = α/h²
  const PairResponse normal = normalResponse(*this, bodies, rotations, f);
  const Real w = normal.inverseMass();
  if (!(w + scaledCompliance > 0)) return;
  const Real deltaNormal = (-c - scaledCompliance * normalMultiplier) / (w + scaledCompliance);
  normalMultiplier += deltaNormal;
  applyPositionImpulse(*this, bodies, normal, f.normal, deltaNormal);

  // Static friction: the tangential offset of p₀ᵐ from its anchor, C_t = |d_t|, removed by
  // Δλ_t = C_t / w_t, clamped to the cone μ λ_n; when clamped the point slides and the anchor
  // moves under it.
  // It reads the frame after the normal row moved the bodies. A static body 1 did not move:
  // every contact's but a sphere's anchor and normal are those just evaluated, and only the
  // point p₀ (= p₀ᵐ) is new (the same numbers as evaluating the whole frame again).
  if (pointRadius > 0 || bodies.rigid.isDynamic(at(body)))
    f = currentFrame(*this, bodies, rotations);
  else
    refreshPoint(*this, bodies, rotations, f);
  const Vector3 tangential = tangentialPart(f.material - f.anchor, f.normal);
  const Real slip = tangential.norm();
  if (!(slip > 0)) return;
  const Vector3 direction = tangential / slip;
  const PairResponse tangentResponse =
      pairResponse(*this, bodies, rotations, f.materialLever, f.anchorLever, direction);
  const Real wt = tangentResponse.inverseMass();
  if (!(wt > 0)) return;
  const Real budget = std::max(Real(0), friction * normalMultiplier - tangentMultiplier);
  const Real wanted = slip / wt;
  const Real deltaTangent = std::min(wanted, budget);
  tangentMultiplier += deltaTangent;
  applyPositionImpulse(*this, bodies, tangentResponse, direction, -deltaTangent);
  if (wanted > budget) reanchor(*this, bodies, currentFrame(*this, bodies, rotations));
}

void XpbdContact::solveVelocity(BodyStates& bodies, const std::vector<Matrix3>& rotationMatrices,
                                Real substepSize, Real restitutionThreshold) const {
  if (!(normalMultiplier > 0)) return;
  const MatrixRotations rotations{rotationMatrices};
  const ContactFrame f = currentFrame(*this, bodies, rotations, /*frictionPoints=*/false);
  // Restitution: the normal velocity becomes max(−e ṽ_n, 0), by a normal impulse P_n.
  const Real normalVelocity = f.normal.dot(relativeVelocity(*this, bodies, f));
  const Real e = std::abs(approachVelocity) <= restitutionThreshold ? Real(0) : restitution;
  const Real target = e > 0 ? std::max(-e * approachVelocity, Real(0)) : Real(0);
  const PairResponse normal = normalResponse(*this, bodies, rotations, f);
  const Real wn = normal.inverseMass();
  const Real normalImpulse = wn > 0 ? (target - normalVelocity) / wn : Real(0);
  applyVelocityImpulse(*this, bodies, rotations, normal, f.normal, normalImpulse);

  // Dynamic friction against the sliding velocity, within what the substep's Coulomb bound
  // μ (λ_n/h + P_n) leaves after the static friction impulse λ_t/h.
  const Real budget = (friction * normalMultiplier - tangentMultiplier) / substepSize;
  if (!(budget > 0)) return;
  const Vector3 u = relativeVelocity(*this, bodies, f);
  const Vector3 sliding = tangentialPart(u, f.normal);
  const Real speed = sliding.norm();
  if (!(speed > 0)) return;
  const Vector3 direction = sliding / speed;
  const PairResponse tangentResponse =
      pairResponse(*this, bodies, rotations, f.pointLever, f.surfaceLever, direction);
  const Real wt = tangentResponse.inverseMass();
  if (!(wt > 0)) return;
  applyVelocityImpulse(*this, bodies, rotations, tangentResponse, direction,
                       -std::min(budget, speed / wt));
}

void XpbdContactSet::reserve(const ContactGeometryBuffer& geometry, std::size_t rigidBodies) {
  contacts.reserve(geometry.rigid.capacity() + geometry.particle.capacity());
  rotations.assign(rigidBodies, Matrix3::Identity());
}

void XpbdContactSet::formRotations(const RigidBodyStates& bodies) {
  for (std::size_t i = 0; i < rotations.size(); ++i)
    rotations[i] = bodies.rotation[i].toRotationMatrix();
}

bool XpbdContactSet::anyRestitution() const {
  for (const XpbdContact& contact : contacts)
    if (contact.restitution > 0) return true;
  return false;
}

bool XpbdContactSet::anyActive() const {
  for (const XpbdContact& contact : contacts)
    if (contact.normalMultiplier > 0) return true;
  return false;
}

void XpbdContactSet::initialise(const ContactGeometryBuffer& geometry, const BodyStates& bodies,
                                const ContactMaterials& materials, Real contactTolerance) {
  contacts.resize(geometry.rigid.size() + geometry.particle.size());  // within the capacity
  std::size_t k = 0;
  for (const ContactPointGeometry& g : geometry.rigid)
    contacts[k++].init(g, false, bodies, materials.rigid(g.vertexSide, g.sdfBody),
                       contactTolerance);
  for (const ContactPointGeometry& g : geometry.particle)
    contacts[k++].init(g, true, bodies, materials.particle(g.vertexSide, g.sdfBody),
                       contactTolerance);
}

}  // namespace pbd
