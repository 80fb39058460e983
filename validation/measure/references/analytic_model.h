// The common shape of the analytic reference models (docs/references.md) and the helpers they
// share to read the Scene: which body a model describes, the static support, defaults taken
// from joints and materials.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "validation/measure/references/parameters.h"
#include "validation/run/case_spec.h"

namespace pbdval {

/// What every model is built from.
struct ModelContext {
  const pbd::Scene* scene = nullptr;
  const ReferenceSpec* spec = nullptr;
  double integrationStep = 0;  ///< the run's effective step, s (discrete closed forms)
};

/// A model of the motion of some of a scene's bodies.
class AnalyticModel {
 public:
  virtual ~AnalyticModel() = default;
  /// One line: the model and its key numbers ("pendulum, period 1.234 s").
  virtual std::string description() const = 0;
  /// Indices (into Scene::rigidBodies) of the bodies it describes.
  virtual std::vector<int> bodies() const = 0;
  /// Whether it gives the orientations of those bodies.
  virtual bool hasRotation() const = 0;
  /// Sets the described bodies of `state` (which holds the Scene's initial state and the time
  /// wanted) to their state at state.time ≥ 0. Called with non-decreasing times, so models
  /// that integrate numerically can continue from the previous call.
  virtual void evaluate(State& state) = 0;
};

/// The index of the single body a model describes: parameter `body` (a scene id), else the
/// one id of Validation.reference.bodies, else the only dynamic body. It must be dynamic.
int describedBody(const ModelContext& context, const ReferenceParameters& parameters);

/// The indices of the bodies a multi-body model describes: Validation.reference.bodies, else
/// every dynamic body.
std::vector<int> describedBodies(const ModelContext& context,
                                 const ReferenceParameters& parameters);

/// The static body a contact model's body rests on: parameter `ground` (a scene id), else the
/// only static body.
int groundBody(const ModelContext& context, const ReferenceParameters& parameters);

/// Parameter `normal` (unit), else the ground body's scene-frame +y axis in the world (the top
/// face of an axis-aligned box, rotated with it).
Vector3 planeNormal(const ModelContext& context, const ReferenceParameters& parameters, int ground);

/// Parameter `radius`, else the radius of the body's sphere collision object.
double sphereRadius(const ModelContext& context, const ReferenceParameters& parameters, int body);

/// The rotation by `angle` (rad) about the unit `axis`.
Quaternion rotationAbout(const Vector3& axis, double angle);

const pbd::RigidBodyDesc& bodyAt(const pbd::Scene& scene, int index);

}  // namespace pbdval
