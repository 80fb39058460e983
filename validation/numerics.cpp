#include "validation/numerics.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

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

State interpolateState(const State& a, const State& b, double s, double time) {
  if (a.bodies.size() != b.bodies.size() || a.particles.size() != b.particles.size())
    throw std::invalid_argument("interpolateState: the two states hold different bodies");
  State out;
  out.time = time;
  out.bodies.resize(a.bodies.size());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const BodyState& p = a.bodies[i];
    const BodyState& q = b.bodies[i];
    BodyState& r = out.bodies[i];
    r.id = p.id;
    r.position = (1 - s) * p.position + s * q.position;
    r.velocity = (1 - s) * p.velocity + s * q.velocity;
    r.angularVelocity = (1 - s) * p.angularVelocity + s * q.angularVelocity;
    r.rotation = p.rotation.normalized().slerp(s, q.rotation.normalized());
  }
  out.particles.resize(a.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    out.particles[i].position = (1 - s) * a.particles[i].position + s * b.particles[i].position;
    out.particles[i].velocity = (1 - s) * a.particles[i].velocity + s * b.particles[i].velocity;
  }
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
