#include "validation/measure/references/ballistic.h"

#include <sstream>

namespace pbdval {

BallisticModel::BallisticModel(const ModelContext& context, const ReferenceParameters& parameters)
    : bodies_(describedBodies(context, parameters)),
      gravity_(context.scene->simulation.gravitation) {
  const std::string form =
      parameters.choice("form", {"continuous", "semi_implicit_euler"}).value_or("continuous");
  if (form == "semi_implicit_euler") {
    if (!(context.integrationStep > 0))
      parameters.fail("form", "\"continuous\": the run's integration step is not known");
    step_ = context.integrationStep;
  }
  hasRotation_ = true;
  for (const int body : bodies_)
    hasRotation_ = hasRotation_ && bodyAt(*context.scene, body).angularVelocity.isZero(0);
}

std::string BallisticModel::description() const {
  std::ostringstream out;
  out << "ballistic motion";
  if (step_ > 0) {
    out << " (semi-implicit Euler, h = " << step_ << " s)";
  } else {
    out << " (continuous parabola)";
  }
  return out.str();
}

Vector3 BallisticModel::position(const Vector3& x0, const Vector3& v0, const Vector3& g, double t,
                                 double step) {
  return x0 + v0 * t + 0.5 * g * t * (t + step);
}

void BallisticModel::evaluate(State& state) {
  const double t = state.time;
  for (const int body : bodies_) {
    BodyState& b = state.bodies[static_cast<std::size_t>(body)];
    b.position = position(b.position, b.velocity, gravity_, t, step_);
    b.velocity = b.velocity + gravity_ * t;
  }
}

}  // namespace pbdval
