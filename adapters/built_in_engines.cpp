#include "adapters/built_in_engines.h"

#include "adapters/bullet/bullet_engine.h"
#include "adapters/mujoco/mujoco_engine.h"
#include "adapters/ode/ode_engine.h"
#include "adapters/pbd/pbd_engine.h"

namespace pbdval {

EngineRegistry builtInEngines(const EngineOptions& options) {
  EngineRegistry registry(options);
  registry.add(pbdEngineEntry());
  registry.add(bulletEngineEntry());
  registry.add(odeEngineEntry());
  registry.add(mujocoEngineEntry());
  return registry;
}

}  // namespace pbdval
