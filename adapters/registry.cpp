#include "adapters/registry.h"

#include "adapters/pbd/pbd_engine.h"
#include "adapters/selftest/selftest_engine.h"

namespace pbdval {

const std::vector<EngineEntry>& engineEntries() {
  static const std::vector<EngineEntry> entries = {
      pbdEngineEntry(),
      selftestEngineEntry(),
  };
  return entries;
}

}  // namespace pbdval
