#include "validation/measure/references/pendulum.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "validation/measure/mechanics.h"

namespace pbdval {

namespace {

constexpr double kPi = 3.14159265358979323846;
/// RK4 steps per fastest time scale 2π/rate (error ~10⁻¹² rad per period, see the header).
constexpr double kStepsPerPeriod = 1e4;

/// A joint tying the body to something static: where, and the hinge axis if any.
struct PivotJoint {
  Vector3 pivot;
  std::optional<Vector3> axis;
};

bool isStaticBody(const pbd::Scene& scene, int index) {
  return index >= 0 && !bodyAt(scene, index).isDynamic;
}

std::vector<PivotJoint> pivotJoints(const pbd::Scene& scene, int body) {
  std::vector<PivotJoint> out;
  for (const pbd::JointDesc& j : scene.joints) {
    const bool tiesBody = (j.body1 == body && isStaticBody(scene, j.body2)) ||
                          (j.body2 == body && isStaticBody(scene, j.body1));
    if (j.type == pbd::JointType::Hinge && tiesBody) {
      out.push_back({j.position, Vector3(j.axis.normalized())});
    } else if (j.type == pbd::JointType::Ball && tiesBody) {
      out.push_back({j.position, std::nullopt});
    } else if (j.type == pbd::JointType::RigidBodyParticleBall && j.body1 == body &&
               j.particle >= 0 && std::size_t(j.particle) < scene.particles.size() &&
               !(scene.particles[std::size_t(j.particle)].mass > 0)) {
      out.push_back({scene.particles[std::size_t(j.particle)].position, std::nullopt});
    }
  }
  return out;
}

/// A unit vector perpendicular to the unit `v`.
Vector3 anyPerpendicular(const Vector3& v) {
  const Vector3 helper = std::abs(v.x()) < 0.9 ? Vector3::UnitX() : Vector3::UnitY();
  return v.cross(helper).normalized();
}

Vector3 defaultAxis(const std::optional<PivotJoint>& joint, const Vector3& omega0,
                    const Vector3& offset, const Vector3& g) {
  if (joint && joint->axis) return *joint->axis;
  if (omega0.norm() > 0) return omega0.normalized();
  const Vector3 normal = offset.cross(g);
  if (normal.norm() > 1e-12 * (1 + offset.norm() * g.norm())) return normal.normalized();
  if (offset.norm() > 0) return anyPerpendicular(offset.normalized());
  return Vector3::UnitZ();
}

}  // namespace

double completeEllipticK(double modulus) {
  if (!(std::abs(modulus) < 1))
    throw std::invalid_argument("completeEllipticK: the modulus must be in (−1, 1)");
  double a = 1, b = std::sqrt(1 - modulus * modulus);
  for (int i = 0; i < 64 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double mean = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = mean;
  }
  return kPi / (2 * a);
}

double pendulumPeriod(double naturalFrequency, double amplitude) {
  return 4 * completeEllipticK(std::sin(0.5 * amplitude)) / naturalFrequency;
}

PendulumModel::PendulumModel(const ModelContext& context, const ReferenceParameters& parameters,
                             bool pointMass)
    : pointMass_(pointMass), body_(describedBody(context, parameters)) {
  const pbd::Scene& scene = *context.scene;
  const pbd::RigidBodyDesc& desc = bodyAt(scene, body_);
  const std::vector<PivotJoint> joints = pivotJoints(scene, body_);
  std::optional<PivotJoint> joint;
  if (joints.size() == 1) joint = joints.front();

  if (const std::optional<Vector3> pivot = parameters.vector3("pivot")) {
    pivot_ = *pivot;
  } else if (joint) {
    pivot_ = joint->pivot;
  } else {
    parameters.fail("pivot", "[x, y, z] (" + std::to_string(joints.size()) +
                                 " hinge or ball joints tie " + desc.jsonPath +
                                 " to something static; one is needed to infer it)");
  }
  const Vector3 x0 = desc.initialCenterOfMass();
  const Vector3 g = scene.simulation.gravitation;
  offset0_ = x0 - pivot_;
  rotation0_ = desc.rotation.normalized();
  axis_ =
      parameters.direction("axis").value_or(defaultAxis(joint, desc.angularVelocity, offset0_, g));

  const Vector3 radial = offset0_ - offset0_.dot(axis_) * axis_;
  const double d = radial.norm();
  if (!(d > 1e-12 * (1 + offset0_.norm())))
    parameters.failModel("the centre of mass of " + desc.jsonPath +
                         " lies on the axis: it cannot swing");
  const Vector3 gPerp = g - g.dot(axis_) * axis_;
  const Vector3 down = gPerp.norm() > 0 ? Vector3(gPerp.normalized()) : Vector3(radial / d);
  theta0_ = std::atan2(down.cross(radial).dot(axis_), down.dot(radial));

  const Vector3 omega = desc.angularVelocity;
  rate0_ = omega.dot(axis_);
  if ((omega - rate0_ * axis_).norm() > 1e-6 * (1 + omega.norm()))
    parameters.failModel("the initial angular velocity of " + desc.jsonPath +
                         " is not along the pendulum axis");
  const Vector3 slip = desc.velocity - omega.cross(offset0_);
  if (slip.norm() > 1e-6 * (1 + desc.velocity.norm() + omega.norm() * offset0_.norm())) {
    std::ostringstream message;
    message << "the initial motion of " << desc.jsonPath
            << " is not a rotation about the pivot: v0 - w0 x (x0 - pivot) = (" << slip.transpose()
            << ") m/s";
    parameters.failModel(message.str());
  }

  const double m = double(desc.massProperties.mass);
  const double inertia =
      m * d * d + (pointMass ? 0.0 : axis_.dot(worldInertia(desc, desc.rotation) * axis_));
  omega0_ = std::sqrt(m * d * gPerp.norm() / inertia);
  const double fastestRate = std::max(
      omega0_, std::sqrt(rate0_ * rate0_ + 2 * omega0_ * omega0_ * (1 - std::cos(theta0_))));
  maxStep_ = parameters.positiveNumber("rk4Step").value_or(
      fastestRate > 0 ? 2 * kPi / (fastestRate * kStepsPerPeriod) : 0);
  time_ = 0;
  theta_ = theta0_;
  rate_ = rate0_;
}

std::optional<double> PendulumModel::period() const {
  if (!(omega0_ > 0)) return std::nullopt;
  const double cosAmplitude = std::cos(theta0_) - rate0_ * rate0_ / (2 * omega0_ * omega0_);
  if (!(cosAmplitude > -1)) return std::nullopt;
  return pendulumPeriod(omega0_, std::acos(std::min(1.0, cosAmplitude)));
}

std::string PendulumModel::description() const {
  std::ostringstream out;
  out << (pointMass_ ? "simple" : "physical") << " pendulum (Omega0 = " << omega0_
      << " rad/s, theta0 = " << theta0_ << " rad";
  if (const std::optional<double> t = period()) out << ", period " << *t << " s";
  out << ")";
  return out.str();
}

void PendulumModel::advanceTo(double time) {
  if (time < time_) {  // restart: times went backwards
    time_ = 0;
    theta_ = theta0_;
    rate_ = rate0_;
  }
  if (!(maxStep_ > 0) || time == time_) {
    theta_ += rate_ * (time - time_);  // no restoring torque: uniform rotation
    time_ = time;
    return;
  }
  const double w2 = omega0_ * omega0_;
  const auto acceleration = [w2](double theta) { return -w2 * std::sin(theta); };
  const long steps = std::max(1L, long(std::ceil((time - time_) / maxStep_)));
  const double h = (time - time_) / double(steps);
  for (long i = 0; i < steps; ++i) {
    const double k1x = rate_, k1v = acceleration(theta_);
    const double k2x = rate_ + 0.5 * h * k1v, k2v = acceleration(theta_ + 0.5 * h * k1x);
    const double k3x = rate_ + 0.5 * h * k2v, k3v = acceleration(theta_ + 0.5 * h * k2x);
    const double k4x = rate_ + h * k3v, k4v = acceleration(theta_ + h * k3x);
    theta_ += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    rate_ += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  time_ = time;
}

void PendulumModel::evaluate(State& state) {
  advanceTo(state.time);
  const Quaternion turn = rotationAbout(axis_, theta_ - theta0_);
  BodyState& b = state.bodies[static_cast<std::size_t>(body_)];
  b.position = pivot_ + turn * offset0_;
  b.rotation = (turn * rotation0_).normalized();
  b.angularVelocity = rate_ * axis_;
  b.velocity = b.angularVelocity.cross(b.position - pivot_);
}

}  // namespace pbdval
