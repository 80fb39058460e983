#include "validation/engines/standard_engines.h"

#include <string>
#include <utility>

#include "adapters/built_in_engines.h"
#include "pbdval/build_info.h"
#include "validation/external_engine.h"

namespace pbdval {

std::string projectPython() {
  return std::string(PBDVAL_SOURCE_DIR) + "/.venv/bin/python";
}

EngineRegistry standardEngines(const EnvironmentLookup& environment) {
  EngineOptions options;
  options.gridCacheFolder = sdfCacheFolder(environment);
  EngineRegistry engines = builtInEngines(options);
  const std::string root = PBDVAL_SOURCE_DIR;
  const char* catalogue = environment("PBDVAL_ENGINE_CATALOGUE");
  for (EngineEntry& entry : readEngineCatalogue(catalogue ? catalogue : root + "/engines",
                                                projectPython(), root))
    engines.add(std::move(entry));
  return engines;
}

}  // namespace pbdval
