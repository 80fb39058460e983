#include "validation/measure/references/bouncing_ball.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pbdval {

namespace {

/// Flights shorter than this count as rest (the Zeno limit of e < 1).
constexpr double kShortestFlight = 1e-12;
/// Bounces walked in one call before giving up (e very close to 1 over a very long run).
constexpr long kMaxBounces = 100000000;

/// n·(top of the ground's collision box along n): c·n + Σ |n·(R e_i)| extent_i / 2.
double boxTop(const pbd::RigidBodyDesc& ground, const Vector3& n) {
  const pbd::Matrix3 r = ground.rotation.normalized().toRotationMatrix();
  double top = ground.translation.dot(n);
  for (int i = 0; i < 3; ++i)
    top += 0.5 * std::abs(n.dot(r.col(i))) * ground.collision.scale[i];
  return top;
}

}  // namespace

std::vector<double> bounceApexHeights(double firstApex, double restitution, int count) {
  std::vector<double> heights;
  double h = firstApex;
  for (int k = 0; k < count; ++k) {
    heights.push_back(h);
    h *= restitution * restitution;
  }
  return heights;
}

BouncingBallModel::BouncingBallModel(const ModelContext& context,
                                     const ReferenceParameters& parameters)
    : body_(describedBody(context, parameters)) {
  const pbd::Scene& scene = *context.scene;
  const pbd::RigidBodyDesc& ball = bodyAt(scene, body_);
  const Vector3 g = scene.simulation.gravitation;
  if (!(g.norm() > 0)) parameters.failModel("needs gravity");
  normal_ = parameters.direction("normal").value_or(Vector3(-g.normalized()));
  gravity_ = -g.dot(normal_);
  if (!(gravity_ > 0) || (g + gravity_ * normal_).norm() > 1e-9 * g.norm())
    parameters.fail("normal", "the direction opposite to gravity (the plane must be level)");
  const bool needGround = !parameters.has("restitution") || !parameters.has("contactHeight");
  const int ground = needGround ? groundBody(context, parameters) : -1;
  restitution_ =
      parameters.numberInRange("restitution", 0, 1)
          .value_or(ground >= 0 ? double(scene.pairMaterial(body_, ground).restitution) : 0.0);
  if (restitution_ > 1 || restitution_ < 0)
    parameters.fail("restitution",
                    "a number in [0, 1] (the material gives " + std::to_string(restitution_) + ")");
  if (const std::optional<double> h = parameters.number("contactHeight")) {
    contactHeight_ = *h;
  } else {
    const pbd::RigidBodyDesc& support = bodyAt(scene, ground);
    if (support.collision.type != pbd::CollisionObjectType::Box)
      parameters.fail("contactHeight", "a number (" + support.jsonPath +
                                           " is not a box to take the plane's height from)");
    contactHeight_ = boxTop(support, normal_) + sphereRadius(context, parameters, body_);
  }
  height0_ = ball.initialCenterOfMass().dot(normal_) - contactHeight_;
  if (height0_ < -1e-12) parameters.failModel(ball.jsonPath + " starts below the contact height");
  height0_ = std::max(0.0, height0_);
  speed0_ = ball.velocity.dot(normal_);
  hasRotation_ = ball.angularVelocity.isZero(0);
  flightHeight_ = height0_;
  flightSpeed_ = speed0_;
}

double BouncingBallModel::firstImpactTime() const {
  return (speed0_ + std::sqrt(speed0_ * speed0_ + 2 * gravity_ * height0_)) / gravity_;
}

double BouncingBallModel::restTime() const {
  if (!(restitution_ < 1)) return std::numeric_limits<double>::infinity();
  const double impactSpeed = std::sqrt(speed0_ * speed0_ + 2 * gravity_ * height0_);
  return firstImpactTime() + 2 * restitution_ * impactSpeed / (gravity_ * (1 - restitution_));
}

std::vector<double> BouncingBallModel::apexHeights(int count) const {
  const double impactSpeed2 = speed0_ * speed0_ + 2 * gravity_ * height0_;
  return bounceApexHeights(impactSpeed2 / (2 * gravity_), restitution_, count);
}

std::pair<double, double> BouncingBallModel::normalMotion(double t) {
  if (t < flightStart_) {  // restart: times went backwards
    flightStart_ = 0;
    flightHeight_ = height0_;
    flightSpeed_ = speed0_;
    resting_ = false;
  }
  for (long bounce = 0; !resting_; ++bounce) {
    if (bounce > kMaxBounces)
      throw std::runtime_error("analytic reference 'bouncing_ball': too many bounces");
    const double u = flightSpeed_;
    const double impactSpeed = std::sqrt(u * u + 2 * gravity_ * flightHeight_);
    const double flight = (u + impactSpeed) / gravity_;
    if (t <= flightStart_ + flight) {
      const double dt = t - flightStart_;
      return {flightHeight_ + u * dt - 0.5 * gravity_ * dt * dt, u - gravity_ * dt};
    }
    flightStart_ += flight;
    flightHeight_ = 0;
    flightSpeed_ = restitution_ * impactSpeed;
    resting_ = 2 * flightSpeed_ / gravity_ < kShortestFlight;
  }
  return {0.0, 0.0};
}

std::string BouncingBallModel::description() const {
  std::ostringstream out;
  out << "bouncing ball (e = " << restitution_ << ", first apex " << apexHeights(1).front()
      << " m above contact, first impact at " << firstImpactTime() << " s)";
  return out.str();
}

void BouncingBallModel::evaluate(State& state) {
  const double t = state.time;
  BodyState& b = state.bodies[static_cast<std::size_t>(body_)];
  const auto [height, speed] = normalMotion(t);
  const Vector3 tangentialVelocity = b.velocity - b.velocity.dot(normal_) * normal_;
  const Vector3 tangentialStart = b.position - b.position.dot(normal_) * normal_;
  b.position = tangentialStart + tangentialVelocity * t + (contactHeight_ + height) * normal_;
  b.velocity = tangentialVelocity + speed * normal_;
}

}  // namespace pbdval
