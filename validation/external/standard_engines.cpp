#include "validation/external/standard_engines.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "adapters/built_in_engines.h"
#include "pbdval/build_info.h"
#include "validation/external/engine_catalogue.h"

namespace pbdval {

std::string projectPython() {
  return std::string(PBDVAL_SOURCE_DIR) + "/.venv/bin/python";
}

EngineRegistry standardEngines(const EnvironmentLookup& environment) {
  EngineOptions options;
  options.gridCacheFolder = sdfCacheFolder(environment);
  EngineRegistry engines = builtInEngines(options);
  const std::string root = PBDVAL_SOURCE_DIR;
  // The shipped catalogue, then each folder of $PBDVAL_ENGINE_CATALOGUE (a ':'-separated list)
  // in order: a user's engines add to the shipped ones, they never replace them.
  std::vector<std::string> folders = {root + "/engines"};
  if (const char* extra = environment("PBDVAL_ENGINE_CATALOGUE")) {
    std::string list = extra;
    std::size_t start = 0;
    while (start <= list.size()) {
      const std::size_t end = std::min(list.find(':', start), list.size());
      if (end > start) folders.push_back(list.substr(start, end - start));
      start = end + 1;
    }
  }
  // The Python engines (python/pbdval/external) import pbdval from this source tree and its
  // C++ part (pbdval._core: mujoco-python writes its model with it) from this build: the one
  // place their module path is set (the venv's own .pth may name another checkout).
  const ProjectPython python{projectPython(),
                             root + "/python:" + std::string(PBDVAL_BINARY_DIR) + "/python"};
  for (const std::string& folder : folders)
    for (EngineEntry& entry : readEngineCatalogue(folder, python)) {
      const std::string name = entry.name;
      try {
        engines.add(std::move(entry));
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("engine catalogue " + folder + ": " + e.what() +
                                    (folder == folders.front()
                                         ? std::string()
                                         : " (PBDVAL_ENGINE_CATALOGUE adds engines to the shipped "
                                           "ones in " +
                                               folders.front() + "; give yours another name)"));
      }
    }
  return engines;
}

}  // namespace pbdval
