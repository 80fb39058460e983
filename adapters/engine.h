// The Engine interface: every simulator (the PBD library, Bullet, ODE, MuJoCo) loads the same
// Scene with a Method, advances one timeStepSize per step(), and reads back its state in the
// Scene's frames. Metrics are never taken from an engine: validation/ computes them from the
// states read back and the Scene.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbd/model/scene.h"

namespace pbdval {

using pbd::Quaternion;
using pbd::Real;
using pbd::Vector3;

/// A rigid body's state in the Scene's world frame.
struct BodyState {
  int id = 0;                                    ///< the body's scene id
  Vector3 position = Vector3::Zero();            ///< centre of mass
  Quaternion rotation = Quaternion::Identity();  ///< the body's scene frame → world
  Vector3 velocity = Vector3::Zero();            ///< of the centre of mass
  Vector3 angularVelocity = Vector3::Zero();
};

struct ParticleState {
  Vector3 position = Vector3::Zero();
  Vector3 velocity = Vector3::Zero();
};

/// One sample of a run: bodies in Scene::rigidBodies order, particles in Scene order.
struct State {
  double time = 0;
  std::vector<BodyState> bodies;
  std::vector<ParticleState> particles;
};

/// A parameter of a method, with its default as text.
struct MethodParameter {
  std::string name;
  std::string defaultValue;
  std::string description;
};

/// A named solver configuration of one engine ("ode.quickstep").
struct MethodInfo {
  std::string name;
  std::string engine;
  std::string description;
  std::vector<MethodParameter> parameters;
};

/// A method with its parameter values resolved (defaults filled in, overrides applied).
struct Method {
  std::string name;
  std::map<std::string, std::string> parameters;

  /// The value of a numeric parameter; throws std::invalid_argument naming it when missing or
  /// not a number.
  double number(const std::string& parameter) const;
  const std::string& text(const std::string& parameter) const;
};

/// An engine failure with a message (an engine's error callback, a rejected model, ...). The
/// runner turns it into the run status `error`.
class EngineError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The engine detected that its own integration became unstable (MuJoCo's bad qacc, ...). The
/// runner reports the run `diverged`, like a NaN or a blow-up it detects itself.
class EngineDivergence : public EngineError {
 public:
  using EngineError::EngineError;
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string_view name() const = 0;
  /// Features of the scene this engine cannot represent with this method, by name
  /// ("joint TargetVelocityMotorSliderJoints[0]: no native equivalent"). Empty when all is
  /// supported; the runner then reports the run `unsupported`.
  virtual std::vector<std::string> unsupported(const pbd::Scene& scene,
                                               const Method& method) const = 0;
  /// Builds the engine's model. Throws EngineError.
  virtual void load(const pbd::Scene& scene, const Method& method) = 0;
  /// Advances by one Scene timeStepSize. Throws EngineError.
  virtual void step() = 0;
  /// Poses and velocities in the Scene's frames (time included).
  virtual void read(State& state) const = 0;
  /// The settings actually used (solver, iterations, margins, contact softness, ...), recorded
  /// with every run.
  virtual std::map<std::string, std::string> effectiveSettings() const { return {}; }
  /// A hash of the complete final state, for engines that guarantee bitwise determinism
  /// (the PBD library); empty otherwise.
  virtual std::optional<std::string> stateHash() const { return std::nullopt; }
};

/// Every method of every engine compiled in, with parameters and defaults.
const std::vector<MethodInfo>& methodCatalog();
/// The catalogue entry named `name`; throws std::invalid_argument listing the known methods.
const MethodInfo& findMethod(const std::string& name);
/// The default method of an engine ("pbd" → "pbd", "ode" → "ode.quickstep").
std::string defaultMethod(const std::string& engine);
/// Names of the engines compiled in (without the hidden self-test engine).
std::vector<std::string> engineNames();
/// Resolves a method: defaults, then `overrides` (name → value). Throws std::invalid_argument
/// on an unknown parameter (naming the valid ones).
Method resolveMethod(const std::string& name, const std::map<std::string, std::string>& overrides);
/// A new engine instance for the engine of `method`.
std::unique_ptr<Engine> makeEngine(const std::string& engine);

}  // namespace pbdval
