// The scene a command is given on its command line: loaded with --strict honoured, its
// warnings printed unless --quiet, a bad scene reported as the command's input error.
#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "validation/cli/commands.h"

namespace pbdval::cli {

std::optional<pbd::LoadedScene> loadCommandScene(const ArgParser& parser, const ParsedArgs& args,
                                                 const std::string& path) {
  pbd::LoadOptions options;
  options.strict = args.flags.count("strict") > 0;
  pbd::LoadedScene loaded;
  try {
    loaded = pbd::loadScene(path, options);
  } catch (const pbd::SceneError& e) {
    parser.inputError(e.what());
    return std::nullopt;
  }
  if (args.flags.count("quiet") == 0)
    for (const auto& warning : loaded.warnings)
      std::fprintf(stderr, "warning: %s\n", warning.text().c_str());
  return loaded;
}

void checkNames(const EngineRegistry& engines, const std::string& option,
                const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    try {
      if (option == "--engines" || option == "--engine")
        engines.engine(name);
      else
        engines.method(name);
    } catch (const std::invalid_argument& e) {
      throw UsageError(option + ": " + e.what());
    }
  }
}

std::vector<std::string> withDefaultEnginesExpanded(const std::vector<std::string>& names,
                                                    const EngineRegistry& engines) {
  std::vector<std::string> expanded;
  auto add = [&](const std::string& name) {
    if (std::find(expanded.begin(), expanded.end(), name) == expanded.end())
      expanded.push_back(name);
  };
  for (const std::string& name : names) {
    if (name == "default")
      for (const std::string& engine : engines.defaultEngineNames())
        add(engine);
    else
      add(name);
  }
  return expanded;
}

}  // namespace pbdval::cli
