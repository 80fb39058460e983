// ODE 0.16 (double precision) behind the Engine interface.
//
// Methods: `ode.step` (dWorldStep, direct LCP) and `ode.quickstep` (dWorldQuickStep, the
// default); parameters in ode_settings.h, the mapping of every scene feature in
// docs/parity-ode.md. One scene step is one ODE step: motors take their set points for the end
// of the step (ode_joints.h), collision detection creates the contact joints (ode_world.h),
// ODE steps, the contact joints are removed.
//
// Errors: ODE's process-wide handlers turn an ODE error into EngineError (ode_runtime.h); after
// one, the world is in an undefined state and step() refuses to continue. ODE's warnings are kept
// in messages(). Nothing is written to files.
#pragma once

#include <memory>

#include "adapters/engine.h"
#include "adapters/ode/ode_joints.h"
#include "adapters/ode/ode_runtime.h"
#include "adapters/ode/ode_settings.h"
#include "adapters/ode/ode_world.h"

namespace pbdval {

class OdeEngine final : public SteppingEngine {
 public:
  OdeEngine() = default;
  ~OdeEngine() override;
  OdeEngine(const OdeEngine&) = delete;
  OdeEngine& operator=(const OdeEngine&) = delete;

  std::string_view name() const override { return "ode"; }
  std::vector<std::string> unsupported(const pbd::Scene& scene,
                                       const Method& method) const override;
  void load(const pbd::Scene& scene, const Method& method) override;
  void step() override;
  void read(State& state) const override;
  RunFacts runFacts() const override;
  std::map<std::string, std::string> effectiveSettings() const override;

  // Inspection, for tests and diagnostics (valid after load()).
  /// The ODE body of scene body `sceneIndex`; null for a static body.
  dBodyID body(int sceneIndex) const { return world_->body(sceneIndex); }
  /// The geom of scene body `sceneIndex`; null when it has no collision shape.
  dGeomID geom(int sceneIndex) const { return world_->geom(sceneIndex); }
  /// The contacts handed to ODE in the last step.
  const std::vector<ode::ContactRecord>& lastContacts() const { return world_->contacts(); }
  /// Bodies ODE simulates that are not in the scene (ball-on-line carriages).
  std::size_t auxiliaryBodyCount() const { return world_->auxiliaryBodyCount(); }
  /// ODE's warnings during this engine's calls.
  const ode::OdeMessageLog& messages() const { return context_.messages; }

 private:
  void destroyModel() noexcept;

  ode::OdeLibrary library_;  // first member: released after everything below
  ode::OdeContext context_;
  pbd::Scene scene_;  // the world refers to it
  OdeSettings settings_;
  std::string methodName_;
  std::unique_ptr<ode::OdeWorld> world_;
  std::unique_ptr<ode::OdeJoints> joints_;
  long steps_ = 0;
  std::string failure_;  ///< the ODE error that made the world unusable; empty when fine
};

/// How the engine maps every scene feature (ode_features.cpp; adapters/features.h).
FeatureTable odeFeatures();
EngineEntry odeEngineEntry();

}  // namespace pbdval
