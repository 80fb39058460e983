#include "pbd/contacts/contact_impulse.h"

#include <algorithm>
#include <cmath>

#include "pbd/math/quaternion.h"

namespace pbd {
namespace {

/// The seed keeps a tangential velocity of at most 1 mm/s unnormalised (|t|² ≤ 10⁻⁶ m²/s²).
constexpr Real kTangentNormalisationThreshold = Real(1e-6);
/// Below this slip speed (m/s) there is no slip direction to act along.
constexpr Real kMinimumSlipSpeed = Real(1e-9);

void initSeedFriction(ContactImpulse& c, const Matrix3& k, const Vector3& u) {
  c.tangent = u - u.dot(c.normal) * c.normal;
  const Real squared = c.tangent.squaredNorm();
  if (squared > kTangentNormalisationThreshold) c.tangent /= std::sqrt(squared);
  const Real tkt = c.tangent.dot(k * c.tangent);
  c.maxFrictionImpulse = tkt > 0 ? std::max(Real(0), u.dot(c.tangent) / tkt) : Real(0);
}

void initCorrectedFriction(ContactImpulse& c, const Matrix3& k) {
  const Matrix3 frame = frameFromAxis(c.normal);
  c.tangent1 = frame.col(1);
  c.tangent2 = frame.col(2);
  Eigen::Matrix<Real, 3, 2> t;
  t << c.tangent1, c.tangent2;
  c.tangentInverseMass = t.transpose() * k * t;
  c.tangentNormalCoupling = t.transpose() * k * c.normal;
}

Vector3 seedFriction(const ContactImpulse& c, Real normalIncrement) {
  const Real limited =
      std::clamp(c.friction * normalIncrement, -c.maxFrictionImpulse, c.maxFrictionImpulse);
  return -limited * c.tangent;
}

/// Coulomb friction on the accumulated impulse, along the current slip. With the slip after
/// this iteration's normal increment s = Tᵀ(u + K n Δp_n) and its direction ŝ, the impulse
/// m_s |s| with m_s = 1/(ŝᵀ K_t ŝ) removes the slip along ŝ; it is added to the accumulated
/// λ_t, which is then clamped to the cone |λ_t| ≤ μ P_n. While the contact slides, λ_t stays
/// opposed to the slip (maximal dissipation); when it sticks, the iterations drive every
/// direction of slip to zero. (Projecting λ − K_t⁻¹ s onto the disc instead tilts a sliding
/// contact's friction away from the slip wherever K_t is anisotropic — off-centre points —
/// and loses several percent of it.)
Vector3 correctedFriction(ContactImpulse& c, const Vector3& u, Real normalIncrement) {
  const Vector2 slip =
      Vector2(c.tangent1.dot(u), c.tangent2.dot(u)) + c.tangentNormalCoupling * normalIncrement;
  Vector2 accumulated = c.tangentImpulse;
  const Real speed = slip.norm();
  if (speed > kMinimumSlipSpeed) {
    const Vector2 direction = slip / speed;
    const Real resistance = direction.dot(c.tangentInverseMass * direction);  // ŝᵀ K_t ŝ
    if (resistance > 0) accumulated -= (speed / resistance) * direction;
  }
  const Real limit = c.friction * c.normalImpulse;
  const Real length = accumulated.norm();
  if (length > limit) accumulated *= length > 0 ? limit / length : Real(0);
  const Vector2 change = accumulated - c.tangentImpulse;
  c.tangentImpulse = accumulated;
  return change.x() * c.tangent1 + change.y() * c.tangent2;
}

}  // namespace

Matrix3 pointInverseMass(Real inverseMass, const Matrix3& inverseInertiaWorld, const Vector3& r) {
  const Matrix3 cross = crossMatrix(r);
  return inverseMass * Matrix3::Identity() - cross * inverseInertiaWorld * cross;
}

void initContactImpulse(ContactImpulse& c, const Vector3& normal, const Matrix3& k,
                        const Vector3& u, const ContactMaterial& material, Real penaltyVelocity,
                        const ContactSolveSettings& settings) {
  c.normal = normal;
  const Real nkn = normal.dot(k * normal);
  c.normalMass = nkn > 0 ? 1 / nkn : Real(0);
  c.penaltyVelocity = penaltyVelocity;
  c.friction = material.friction;
  const Real approach = u.dot(normal);
  const Real threshold =
      settings.model == ContactModel::Corrected ? -settings.restitutionThreshold : Real(0);
  c.targetNormalVelocity = approach < threshold ? -material.restitution * approach : Real(0);
  c.normalImpulse = 0;
  c.tangentImpulse.setZero();
  if (settings.model == ContactModel::Seed)
    initSeedFriction(c, k, u);
  else
    initCorrectedFriction(c, k);
}

Vector3 warmStartContactImpulse(ContactImpulse& c, Real previousNormalImpulse,
                                const Vector3& previousTangentImpulse) {
  c.normalImpulse = std::max(previousNormalImpulse, Real(0));
  Vector2 tangent(c.tangent1.dot(previousTangentImpulse), c.tangent2.dot(previousTangentImpulse));
  const Real limit = c.friction * c.normalImpulse, length = tangent.norm();
  if (length > limit) tangent *= limit / length;
  c.tangentImpulse = tangent;
  return c.normalImpulse * c.normal + tangentImpulseWorld(c);
}

Vector3 contactIterationImpulse(ContactImpulse& c, const Vector3& u, ContactModel model) {
  Real increment = c.normalMass * (c.targetNormalVelocity - u.dot(c.normal));
  increment = std::max(increment, -c.normalImpulse);
  increment += c.normalMass * c.penaltyVelocity;
  c.normalImpulse += increment;
  const Vector3 friction =
      model == ContactModel::Seed ? seedFriction(c, increment) : correctedFriction(c, u, increment);
  return increment * c.normal + friction;
}

}  // namespace pbd
