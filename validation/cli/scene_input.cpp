// The scene a command is given on its command line: loaded with --strict honoured, its
// warnings printed unless --quiet, a bad scene reported as the command's input error.
#include <cstdio>

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

}  // namespace pbdval::cli
