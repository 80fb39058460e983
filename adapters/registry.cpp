#include "adapters/registry.h"

#include "adapters/bullet/bullet_engine.h"
#include "adapters/pbd/pbd_engine.h"

namespace pbdval {

const std::vector<EngineEntry>& engineEntries() {
  static const std::vector<EngineEntry> entries = {
      pbdEngineEntry(),
      bulletEngineEntry(),
  };
  return entries;
}

}  // namespace pbdval
