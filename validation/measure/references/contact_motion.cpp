#include "validation/measure/references/contact_motion.h"

#include <cmath>
#include <sstream>

#include "validation/measure/mechanics.h"

namespace pbdval {

namespace {

constexpr double kPi = 3.14159265358979323846;

double sign(double x) {
  return x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
}

Vector3 anyPerpendicular(const Vector3& v) {
  const Vector3 helper = std::abs(v.x()) < 0.9 ? Vector3::UnitX() : Vector3::UnitY();
  return v.cross(helper).normalized();
}

}  // namespace

CoulombLineMotion::CoulombLineMotion(double gTangent, double gNormal, double friction, double kappa,
                                     double radius, double speed0, double spin0) {
  // Spin acceleration for a friction acceleration f: w′ = −f κ / r (0 for a block).
  const auto spinRate = [&](double f) { return kappa > 0 ? -f * kappa / radius : 0.0; };
  const double slip0 = speed0 - (kappa > 0 ? radius * spin0 : 0.0);
  double noSlipFrom = 0;
  if (slip0 != 0) {
    const double f = -friction * gNormal * sign(slip0);
    const double slipRate = gTangent + f * (1 + kappa);
    addPhase(0, gTangent + f, spinRate(f), speed0, spin0);
    if (!(slipRate * sign(slip0) < 0)) return;  // the slip never ends
    noSlipFrom = std::abs(slip0) / std::abs(slipRate);
  }
  slipEnd_ = noSlipFrom;
  const double required = -gTangent / (1 + kappa);
  // Rolling (sticking) holds while the friction it needs stays inside the cone; the relative
  // slack 1e-12 keeps the exact boundary μ = tan θ · κ/(1+κ) on the rolling side.
  if (std::abs(required) <= friction * gNormal * (1 + 1e-12)) {
    rolls_ = true;
    addPhase(noSlipFrom, gTangent + required, spinRate(required), speed0, spin0);
  } else {
    const double f = -friction * gNormal * sign(gTangent);
    addPhase(noSlipFrom, gTangent + f, spinRate(f), speed0, spin0);
  }
}

void CoulombLineMotion::addPhase(double start, double du, double dw, double speed0, double spin0) {
  Phase next;
  next.start = start;
  next.du = du;
  next.dw = dw;
  if (phases_.empty()) {
    next.u = speed0;
    next.w = spin0;
  } else {
    next.u = speed(start);
    next.w = spin(start);
    next.s = displacement(start);
    next.angle = spinAngle(start);
  }
  phases_.push_back(next);
}

const CoulombLineMotion::Phase& CoulombLineMotion::phaseAt(double t) const {
  std::size_t i = 0;
  while (i + 1 < phases_.size() && phases_[i + 1].start <= t)
    ++i;
  return phases_[i];
}

double CoulombLineMotion::speed(double t) const {
  const Phase& p = phaseAt(t);
  return p.u + p.du * (t - p.start);
}

double CoulombLineMotion::displacement(double t) const {
  const Phase& p = phaseAt(t);
  const double dt = t - p.start;
  return p.s + p.u * dt + 0.5 * p.du * dt * dt;
}

double CoulombLineMotion::spin(double t) const {
  const Phase& p = phaseAt(t);
  return p.w + p.dw * (t - p.start);
}

double CoulombLineMotion::spinAngle(double t) const {
  const Phase& p = phaseAt(t);
  const double dt = t - p.start;
  return p.angle + p.w * dt + 0.5 * p.dw * dt * dt;
}

PlaneContactModel::PlaneContactModel(const ModelContext& context,
                                     const ReferenceParameters& parameters, Kind kind)
    : kind_(kind), body_(describedBody(context, parameters)) {
  const pbd::Scene& scene = *context.scene;
  const int ground = groundBody(context, parameters);
  const Vector3 n = planeNormal(context, parameters, ground);
  const Vector3 g = scene.simulation.gravitation;
  const double gNormal = -g.dot(n);
  if (!(gNormal > 0))
    parameters.failModel("gravity does not press the body onto the plane (g·n ≥ 0)");
  const Vector3 gTangent = g + gNormal * n;
  const bool flat = gTangent.norm() <= 1e-12 * g.norm();
  incline_ = std::atan2(flat ? 0.0 : double(gTangent.norm()), gNormal);
  friction_ = parameters.nonNegativeNumber("friction")
                  .value_or(double(scene.pairMaterial(body_, ground).friction));

  const pbd::RigidBodyDesc& desc = bodyAt(scene, body_);
  const Vector3 v0 = desc.velocity, w0 = desc.angularVelocity;
  if (std::abs(v0.dot(n)) > 1e-9 * (1 + v0.norm()))
    parameters.failModel(desc.jsonPath + " has an initial velocity along the plane's normal");
  if (kind == Kind::BowlingBall && !flat) {
    std::ostringstream message;
    message << "the plane is inclined by " << incline_ * 180 / kPi << " deg (use rolling_sphere)";
    parameters.failModel(message.str());
  }
  if (kind == Kind::Block && !w0.isZero(0))
    parameters.failModel(desc.jsonPath + " spins at t = 0: a sliding block must not");
  const double radius = kind == Kind::Block ? 0.0 : sphereRadius(context, parameters, body_);
  const Vector3 slip = v0 - radius * w0.cross(n);

  if (!flat) {
    direction_ = gTangent.normalized();
    if ((slip - slip.dot(direction_) * direction_).norm() > 1e-9 * (1 + slip.norm()))
      parameters.failModel("the initial slip of " + desc.jsonPath +
                           " is not along the downhill direction (the friction direction would "
                           "turn: no closed form)");
  } else if (slip.norm() > 0) {
    direction_ = slip.normalized();
  } else {
    const Vector3 tangential = v0 - v0.dot(n) * n;
    direction_ = tangential.norm() > 0 ? Vector3(tangential.normalized()) : anyPerpendicular(n);
  }
  spinAxis_ = n.cross(direction_);
  const double kappa = kind == Kind::Block
                           ? 0.0
                           : double(desc.massProperties.mass) * radius * radius /
                                 spinAxis_.dot(worldInertia(desc, desc.rotation) * spinAxis_);
  const double speed0 = v0.dot(direction_), spin0 = w0.dot(spinAxis_);
  crossVelocity_ = v0 - speed0 * direction_ - v0.dot(n) * n;
  hasRotation_ = (w0 - spin0 * spinAxis_).norm() <= 1e-9 * (1 + w0.norm());
  motion_.emplace(flat ? 0.0 : double(gTangent.norm()), gNormal, friction_, kappa, radius, speed0,
                  spin0);
}

std::string PlaneContactModel::description() const {
  std::ostringstream out;
  out << (kind_ == Kind::Block ? "sliding block"
                               : (kind_ == Kind::Sphere ? "rolling sphere" : "bowling ball"))
      << " (incline " << incline_ * 180 / kPi << " deg, mu = " << friction_ << ")";
  if (const std::optional<double> end = motion_->slipEnd()) {
    out << (motion_->rollsOrSticks() ? (kind_ == Kind::Block ? ": sticks" : ": rolls")
                                     : ": slides on")
        << " from t = " << *end << " s";
  } else {
    out << ": slides throughout";
  }
  return out.str();
}

void PlaneContactModel::evaluate(State& state) {
  const double t = state.time;
  BodyState& b = state.bodies[static_cast<std::size_t>(body_)];
  const CoulombLineMotion& m = *motion_;
  b.position += crossVelocity_ * t + m.displacement(t) * direction_;
  b.velocity = crossVelocity_ + m.speed(t) * direction_;
  const double spin0 = b.angularVelocity.dot(spinAxis_);
  b.angularVelocity += (m.spin(t) - spin0) * spinAxis_;
  if (hasRotation_ && kind_ != Kind::Block)
    b.rotation = (rotationAbout(spinAxis_, m.spinAngle(t)) * b.rotation).normalized();
}

}  // namespace pbdval
