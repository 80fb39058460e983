#include "validation/measure/references/torque_free.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "validation/measure/references/ballistic.h"

namespace pbdval {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kStepsPerPeriod = 1e4;

/// Index of the moment that differs from the two equal ones (relative tolerance), or −1.
/// For three equal moments: 2.
int symmetryAxisOf(const Vector3& moments, double tolerance) {
  const double scale = moments.maxCoeff();
  const auto equal = [&](int a, int b) {
    return std::abs(moments[a] - moments[b]) <= tolerance * scale;
  };
  if (equal(0, 1)) return 2;
  if (equal(1, 2)) return 0;
  if (equal(0, 2)) return 1;
  return -1;
}

/// (I ω) × ω componentwise divided by I: Euler's equations for a free body.
Vector3 eulerAcceleration(const Vector3& moments, const Vector3& omega) {
  return moments.cwiseProduct(omega).cross(omega).cwiseQuotient(moments);
}

/// Ṗ = P ⊗ [0, ω_b/2] as a coefficient vector.
Eigen::Matrix<pbd::Real, 4, 1> orientationRate(const Quaternion& p, const Vector3& bodyOmega) {
  const Quaternion pure(0, bodyOmega.x(), bodyOmega.y(), bodyOmega.z());
  return 0.5 * (p * pure).coeffs();
}

void moveCentreOfMass(BodyState& b, const Vector3& g, double t) {
  b.position = BallisticModel::position(b.position, b.velocity, g, t, 0);
  b.velocity = b.velocity + g * t;
}

}  // namespace

Quaternion symmetricTopOrientation(const Quaternion& principal0, const Vector3& moments,
                                   int symmetryAxis, const Vector3& bodyOmega0, double t) {
  const int a = (symmetryAxis + 1) % 3;  // one of the two equal moments
  const double transverse = moments[a];
  const double axial = moments[symmetryAxis];
  const Vector3 momentum = principal0 * moments.cwiseProduct(bodyOmega0);
  const double precessionRate = (axial - transverse) / transverse * bodyOmega0[symmetryAxis];
  const Vector3 e3 = Vector3::Unit(symmetryAxis);
  Quaternion around = Quaternion::Identity();
  if (momentum.norm() > 0)
    around = rotationAbout(momentum.normalized(), momentum.norm() / transverse * t);
  return (around * principal0 * rotationAbout(e3, -precessionRate * t)).normalized();
}

SymmetricTorqueFreeModel::SymmetricTorqueFreeModel(const ModelContext& context,
                                                   const ReferenceParameters& parameters)
    : gravity_(context.scene->simulation.gravitation),
      bodies_(describedBodies(context, parameters)) {
  const double tolerance = parameters.positiveNumber("symmetryTolerance").value_or(1e-6);
  for (const int body : bodies_) {
    const pbd::RigidBodyDesc& desc = bodyAt(*context.scene, body);
    Top top;
    top.body = body;
    top.moments = desc.massProperties.principalInertia;
    top.symmetryAxis = symmetryAxisOf(top.moments, tolerance);
    if (top.symmetryAxis < 0) {
      std::ostringstream message;
      message << desc.jsonPath << " is not axisymmetric: principal moments ("
              << top.moments.transpose()
              << ") kg m^2 differ by more than symmetryTolerance = " << tolerance
              << " (use torque_free_asymmetric)";
      parameters.failModel(message.str());
    }
    const int a = (top.symmetryAxis + 1) % 3, b = (top.symmetryAxis + 2) % 3;
    top.moments[a] = top.moments[b] = 0.5 * (top.moments[a] + top.moments[b]);
    top.principal0 = desc.initialPrincipalRotation();
    top.principalInScene = desc.massProperties.principalRotation.normalized();
    top.bodyOmega0 = top.principal0.conjugate() * desc.angularVelocity;
    top.precessionRate = (top.moments[top.symmetryAxis] - top.moments[a]) / top.moments[a] *
                         top.bodyOmega0[top.symmetryAxis];
    tops_.push_back(top);
  }
}

std::string SymmetricTorqueFreeModel::description() const {
  return "torque-free symmetric top (closed form)";
}

void SymmetricTorqueFreeModel::evaluate(State& state) {
  const double t = state.time;
  for (const Top& top : tops_) {
    BodyState& b = state.bodies[static_cast<std::size_t>(top.body)];
    moveCentreOfMass(b, gravity_, t);
    const Quaternion principal =
        symmetricTopOrientation(top.principal0, top.moments, top.symmetryAxis, top.bodyOmega0, t);
    const Vector3 bodyOmega =
        rotationAbout(Vector3::Unit(top.symmetryAxis), top.precessionRate * t) * top.bodyOmega0;
    b.rotation = (principal * top.principalInScene.conjugate()).normalized();
    b.angularVelocity = principal * bodyOmega;
  }
}

AsymmetricTorqueFreeModel::AsymmetricTorqueFreeModel(const ModelContext& context,
                                                     const ReferenceParameters& parameters)
    : gravity_(context.scene->simulation.gravitation),
      bodies_(describedBodies(context, parameters)),
      integrateRotation_(parameters.boolean("integrateRotation").value_or(false)) {
  const std::optional<double> step = parameters.positiveNumber("rk4Step");
  for (const int body : bodies_) {
    const pbd::RigidBodyDesc& desc = bodyAt(*context.scene, body);
    Spinner s;
    s.body = body;
    s.moments = desc.massProperties.principalInertia;
    if (!(s.moments.minCoeff() > 0))
      parameters.failModel(desc.jsonPath + " has a zero principal moment of inertia");
    s.principalInScene = desc.massProperties.principalRotation.normalized();
    s.principal0 = s.principal = desc.initialPrincipalRotation();
    s.bodyOmega0 = s.bodyOmega = s.principal0.conjugate() * desc.angularVelocity;
    const double rate = s.moments.cwiseProduct(s.bodyOmega0).norm() / s.moments.minCoeff();
    s.maxStep = step.value_or(rate > 0 ? 2 * kPi / (rate * kStepsPerPeriod) : 0);
    spinners_.push_back(s);
  }
}

std::string AsymmetricTorqueFreeModel::description() const {
  return integrateRotation_
             ? "torque-free body (centre of mass closed form, rotation RK4-integrated)"
             : "torque-free body (centre of mass only; rotation checked by the conserved "
               "energy and angular momentum)";
}

void AsymmetricTorqueFreeModel::advance(Spinner& s, double time) const {
  if (time < s.time) {
    s.time = 0;
    s.principal = s.principal0;
    s.bodyOmega = s.bodyOmega0;
  }
  if (!(s.maxStep > 0) || time == s.time) {
    s.time = time;
    return;
  }
  using Coeffs = Eigen::Matrix<pbd::Real, 4, 1>;
  const long steps = std::max(1L, long(std::ceil((time - s.time) / s.maxStep)));
  const double h = (time - s.time) / double(steps);
  const auto at = [](const Quaternion& p, const Coeffs& dp, double scale) {
    return Quaternion(Coeffs(p.coeffs() + scale * dp));
  };
  for (long i = 0; i < steps; ++i) {
    const Quaternion& p = s.principal;
    const Vector3& w = s.bodyOmega;
    const Coeffs p1 = orientationRate(p, w);
    const Vector3 w1 = eulerAcceleration(s.moments, w);
    const Coeffs p2 = orientationRate(at(p, p1, h / 2), w + h / 2 * w1);
    const Vector3 w2 = eulerAcceleration(s.moments, w + h / 2 * w1);
    const Coeffs p3 = orientationRate(at(p, p2, h / 2), w + h / 2 * w2);
    const Vector3 w3 = eulerAcceleration(s.moments, w + h / 2 * w2);
    const Coeffs p4 = orientationRate(at(p, p3, h), w + h * w3);
    const Vector3 w4 = eulerAcceleration(s.moments, w + h * w3);
    s.principal = at(p, Coeffs(p1 + 2 * p2 + 2 * p3 + p4), h / 6).normalized();
    s.bodyOmega = w + h / 6 * (w1 + 2 * w2 + 2 * w3 + w4);
  }
  s.time = time;
}

void AsymmetricTorqueFreeModel::evaluate(State& state) {
  for (Spinner& s : spinners_) {
    BodyState& b = state.bodies[static_cast<std::size_t>(s.body)];
    moveCentreOfMass(b, gravity_, state.time);
    if (!integrateRotation_) continue;
    advance(s, state.time);
    b.rotation = (s.principal * s.principalInScene.conjugate()).normalized();
    b.angularVelocity = s.principal * s.bodyOmega;
  }
}

}  // namespace pbdval
