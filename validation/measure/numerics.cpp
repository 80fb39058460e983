#include "validation/measure/numerics.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace pbdval {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Relative slack for sample times that should coincide (times are sums of steps).
double timeSlack(double time) {
  return 1e-9 * std::max(1.0, std::abs(time));
}

}  // namespace

double geodesicAngle(const Quaternion& a, const Quaternion& b) {
  const Quaternion relative = a.normalized().conjugate() * b.normalized();
  return 2 * std::atan2(relative.vec().norm(), std::abs(relative.w()));
}

double rotationAngle(const Quaternion& q) {
  return geodesicAngle(Quaternion::Identity(), q);
}

double wrapAngle(double angle) {
  double wrapped = std::remainder(angle, 2 * kPi);  // in [−π, π]
  if (wrapped <= -kPi) wrapped += 2 * kPi;
  return wrapped;
}

double twistAngle(const Quaternion& q, const Vector3& axis) {
  return wrapAngle(2 * std::atan2(q.vec().dot(axis), q.w()));
}

double angleBetween(const Vector3& a, const Vector3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

double leastSquaresSlope(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size())
    throw std::invalid_argument("leastSquaresSlope: " + std::to_string(x.size()) +
                                " x values but " + std::to_string(y.size()) + " y values");
  if (x.empty()) return 0;
  double meanX = 0, meanY = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    meanX += x[i];
    meanY += y[i];
  }
  meanX /= double(x.size());
  meanY /= double(y.size());
  double covariance = 0, variance = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    covariance += (x[i] - meanX) * (y[i] - meanY);
    variance += (x[i] - meanX) * (x[i] - meanX);
  }
  return variance > 0 ? covariance / variance : 0;
}

namespace {

using pbd::AngleAxis;
using pbd::Matrix3;

/// Cubic Hermite of a position with its velocities at both ends, and its time derivative; s in
/// [0, 1] over an interval of length dt. Exact for cubic motions.
std::pair<Vector3, Vector3> hermite(const Vector3& x0, const Vector3& v0, const Vector3& x1,
                                    const Vector3& v1, double s, double dt) {
  const double s2 = s * s, s3 = s2 * s;
  const Vector3 x = (2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * dt * v0 +
                    (-2 * s3 + 3 * s2) * x1 + (s3 - s2) * dt * v1;
  const Vector3 v =
      (6 * s2 - 6 * s) / dt * (x0 - x1) + (3 * s2 - 4 * s + 1) * v0 + (3 * s2 - 2 * s) * v1;
  return {x, v};
}

Matrix3 cross(const Vector3& a) {
  Matrix3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

/// The inverse of SO(3)'s left Jacobian: φ̇ = J_l⁻¹(φ) ω for q = exp(φ) q₀ with world-frame ω.
Matrix3 inverseLeftJacobian(const Vector3& phi) {
  const double theta = phi.norm();
  // 1/θ² − (1 + cos θ)/(2 θ sin θ) → 1/12 + θ²/720 as θ → 0 (the series below 1e-4 rad).
  const double c =
      theta < 1e-4 ? 1.0 / 12 + theta * theta / 720
                   : 1 / (theta * theta) - (1 + std::cos(theta)) / (2 * theta * std::sin(theta));
  const Matrix3 k = cross(phi);
  return Matrix3::Identity() - 0.5 * k + c * k * k;
}

Vector3 rotationVector(const Quaternion& q) {  // log, for w ≥ 0: angle ∈ [0, π]
  const Vector3 v = q.vec();
  const double sine = v.norm();
  if (sine == 0) return Vector3::Zero();
  return (2 * std::atan2(sine, q.w()) / sine) * v;
}

Quaternion exponential(const Vector3& phi) {
  const double theta = phi.norm();
  if (theta == 0) return Quaternion::Identity();
  return Quaternion(AngleAxis(theta, phi / theta));
}

/// q(t) = exp(φ(t)) q₀ with φ a cubic Hermite in the tangent space at q₀: φ(0) = 0,
/// φ̇(0) = ω₀, φ(dt) = log(q₁ q₀⁻¹), φ̇(dt) = J_l⁻¹ ω₁. Exact for a constant angular velocity,
/// O(dt⁴) for a smooth rotation (slerp is O(dt²)).
Quaternion hermiteRotation(Quaternion q0, const Vector3& w0, Quaternion q1, const Vector3& w1,
                           double s, double dt) {
  q0.normalize();
  q1.normalize();
  Quaternion delta = q1 * q0.conjugate();
  if (delta.w() < 0) delta.coeffs() = -delta.coeffs();  // the shorter arc
  const Vector3 phiEnd = rotationVector(delta);
  const Vector3 rateEnd = inverseLeftJacobian(phiEnd) * w1;
  const double s2 = s * s, s3 = s2 * s;
  const Vector3 phi =
      (s3 - 2 * s2 + s) * dt * w0 + (-2 * s3 + 3 * s2) * phiEnd + (s3 - s2) * dt * rateEnd;
  return (exponential(phi) * q0).normalized();
}

}  // namespace

State interpolateState(const State& a, const State& b, double s, double time) {
  if (a.bodies.size() != b.bodies.size() || a.particles.size() != b.particles.size())
    throw std::invalid_argument("interpolateState: the two states hold different bodies");
  const double dt = b.time - a.time;
  if (!(dt > 0)) {  // one instant: nothing to interpolate
    State out = s < 0.5 ? a : b;
    out.time = time;
    return out;
  }
  State out;
  out.time = time;
  out.bodies.resize(a.bodies.size());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const BodyState& p = a.bodies[i];
    const BodyState& q = b.bodies[i];
    BodyState& r = out.bodies[i];
    r.id = p.id;
    std::tie(r.position, r.velocity) =
        hermite(p.position, p.velocity, q.position, q.velocity, s, dt);
    r.angularVelocity = (1 - s) * p.angularVelocity + s * q.angularVelocity;
    r.rotation =
        hermiteRotation(p.rotation, p.angularVelocity, q.rotation, q.angularVelocity, s, dt);
  }
  out.particles.resize(a.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i)
    std::tie(out.particles[i].position, out.particles[i].velocity) =
        hermite(a.particles[i].position, a.particles[i].velocity, b.particles[i].position,
                b.particles[i].velocity, s, dt);
  return out;
}

std::vector<State> resampleStates(const std::vector<State>& source,
                                  const std::vector<double>& times) {
  if (source.empty()) throw std::invalid_argument("resampleStates: the source has no samples");
  for (std::size_t i = 1; i < source.size(); ++i)
    if (!(source[i].time >= source[i - 1].time))
      throw std::invalid_argument("resampleStates: source times are not ordered at sample " +
                                  std::to_string(i));
  const double first = source.front().time, last = source.back().time;
  std::vector<State> out;
  out.reserve(times.size());
  for (const double t : times) {
    if (!std::isfinite(t) || t < first - timeSlack(t) || t > last + timeSlack(t)) {
      std::ostringstream message;
      message << "resampleStates: time " << t << " s is outside the source's range [" << first
              << ", " << last << "] s";
      throw std::invalid_argument(message.str());
    }
    const double clamped = std::clamp(t, first, last);
    // First sample with time ≥ clamped.
    const auto upper =
        std::lower_bound(source.begin(), source.end(), clamped,
                         [](const State& state, double value) { return state.time < value; });
    if (upper->time == clamped || upper == source.begin()) {
      out.push_back(*upper);
      out.back().time = t;
      continue;
    }
    const State& before = *(upper - 1);
    const double s = (clamped - before.time) / (upper->time - before.time);
    out.push_back(interpolateState(before, *upper, s, t));
  }
  return out;
}

}  // namespace pbdval
