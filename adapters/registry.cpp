#include "adapters/registry.h"

#include "adapters/mujoco/mujoco_engine.h"
#include "adapters/pbd/pbd_engine.h"

namespace pbdval {

const std::vector<EngineEntry>& engineEntries() {
  static const std::vector<EngineEntry> entries = {
      pbdEngineEntry(),
      mujocoEngineEntry(),
  };
  return entries;
}

}  // namespace pbdval
