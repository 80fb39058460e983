#include "adapters/registry.h"

#include "adapters/bullet/bullet_engine.h"
#include "adapters/ode/ode_engine.h"
#include "adapters/mujoco/mujoco_engine.h"
#include "adapters/pbd/pbd_engine.h"
#include "adapters/selftest/selftest_engine.h"

namespace pbdval {

const std::vector<EngineEntry>& engineEntries() {
  static const std::vector<EngineEntry> entries = {
      pbdEngineEntry(),
      bulletEngineEntry(),
      odeEngineEntry(),
      mujocoEngineEntry(),
      selftestEngineEntry(),
  };
  return entries;
}

}  // namespace pbdval
