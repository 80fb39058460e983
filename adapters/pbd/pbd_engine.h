// The PBD library behind the Engine interface.
//
// Methods:
//   pbd   the seed's algorithm (PositionBasedDynamics 2.2.2 step order). Its parameters default
//         to the scene's Simulation values ("scene") and override them when set.
#pragma once

#include <optional>

#include "adapters/registry.h"
#include "pbd/model/world.h"

namespace pbdval {

class PbdEngine final : public Engine {
 public:
  std::string_view name() const override { return "pbd"; }
  std::vector<std::string> unsupported(const pbd::Scene& scene,
                                       const Method& method) const override;
  void load(const pbd::Scene& scene, const Method& method) override;
  void step() override;
  void read(State& state) const override;
  std::map<std::string, std::string> effectiveSettings() const override;
  std::optional<std::string> stateHash() const override;

  const pbd::World& world() const { return *world_; }

 private:
  std::optional<pbd::World> world_;
  std::vector<int> bodyIds_;
};

/// The scene's Simulation settings with the method's overrides applied.
pbd::SimulationSettings pbdSettingsFor(const pbd::Scene& scene, const Method& method);

EngineEntry pbdEngineEntry();

}  // namespace pbdval
