// The scene a command is given on its command line: loaded with --strict honoured, its
// warnings printed unless --quiet, a bad scene reported as the command's input error.
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

}  // namespace pbdval::cli
