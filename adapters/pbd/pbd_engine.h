// The PBD library behind the Engine interface.
//
// Methods:
//   pbd   the seed's algorithm (PositionBasedDynamics 2.2.2 step order). It has no method
//         parameters: its solver settings (subSteps, maxIterations, maxIterationsV,
//         velocityUpdateMethod, contactModel, ...) are the scene's Simulation settings, declared
//         and range-checked once by the scene loader and set per run with `--set KEY=VALUE`.
//   pbd.xpbd  XPBD rigid bodies (Mueller et al. 2020), docs/methods.md: typed parameters
//         substeps and the compliances per constraint family.
#pragma once

#include <optional>

#include "adapters/engine.h"
#include "pbd/model/world.h"

namespace pbdval {

class PbdEngine final : public SteppingEngine {
 public:
  explicit PbdEngine(EngineOptions options = {}) : options_(std::move(options)) {}

  std::string_view name() const override { return "pbd"; }
  std::vector<std::string> unsupported(const pbd::Scene& scene,
                                       const Method& method) const override;
  void load(const pbd::Scene& scene, const Method& method) override;
  void step() override;
  void read(State& state) const override;
  RunFacts runFacts() const override;
  std::map<std::string, std::string> effectiveSettings() const override;
  std::optional<std::string> stateHash() const override;

  const pbd::World& world() const { return *world_; }

 private:
  EngineOptions options_;
  std::optional<pbd::World> world_;
  std::vector<int> bodyIds_;
  std::vector<int> motorBodies_;  ///< dynamic bodies of motor joints (RunFacts)
};

/// The simulation settings of a run: the scene's, with the step method and XPBD parameters of
/// `method` (pbd: the seed's step; pbd.xpbd: XPBD with the method's substeps and compliances).
pbd::SimulationSettings pbdSettingsFor(const pbd::Scene& scene, const Method& method);

/// How the engine maps every scene feature (pbd_features.cpp; adapters/features.h).
FeatureTable pbdFeatures();
EngineEntry pbdEngineEntry();

}  // namespace pbdval
