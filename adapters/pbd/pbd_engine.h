// The PBD library behind the Engine interface.
//
// Methods:
//   pbd   the seed's algorithm (PositionBasedDynamics 2.2.2 step order). It has no method
//         parameters: its solver settings (subSteps, maxIterations, maxIterationsV,
//         velocityUpdateMethod, contactModel, ...) are the scene's Simulation settings, declared
//         and range-checked once by the scene loader and set per run with `--set KEY=VALUE`.
#pragma once

#include <optional>

#include "adapters/engine.h"
#include "pbd/model/world.h"

namespace pbdval {

class PbdEngine final : public Engine {
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
};

EngineEntry pbdEngineEntry();

}  // namespace pbdval
