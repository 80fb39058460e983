// pbdval methods [ENGINE...]: the solver methods of every engine, with parameters and defaults.
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "adapters/registry.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"

namespace pbdval::cli {

int methodsCommand(const Context& context, const Arguments& arguments) {
  ArgParser parser(
      "methods", "[ENGINE...]",
      "Lists the solver methods of every engine compiled in (or of the engines\n"
      "named), with their parameters and defaults. Select one with\n"
      "'pbdval simulate --engine E --method M --set PARAM=VALUE'. See docs/methods.md.");
  parser.positionals("ENGINE", "engines to list (default: all)", 0, -1);
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  const EngineRegistry& registry = context.engines;
  for (const std::string& wanted : args.positionals) {
    try {
      registry.engine(wanted);
    } catch (const std::invalid_argument& e) {
      return parser.usageError(e.what());
    }
  }
  for (const EngineEntry& engine : registry.entries()) {
    bool listed = args.positionals.empty();
    for (const std::string& wanted : args.positionals)
      listed = listed || wanted == engine.name;
    if (!listed) continue;
    std::printf("%s (default method: %s)\n", engine.name.c_str(), engine.defaultMethod.c_str());
    std::string settings;
    for (const std::string& key : engine.honouredSettings)
      settings += (settings.empty() ? "" : ", ") + key;
    std::printf(
        "  scene settings it honours (--set KEY=VALUE, ranges in docs/scene-format.md):\n"
        "      %s\n",
        settings.c_str());
    for (const MethodInfo& m : engine.methods) {
      std::printf("  %s\n      %s\n", m.name.c_str(), m.description.c_str());
      for (const ParameterSpec& p : m.parameters)
        std::printf("      --set %s=%s  (%s%s%s) %s\n", p.name.c_str(), p.defaultValue.c_str(),
                    p.expectation().c_str(), p.unit.empty() ? "" : ", unit ", p.unit.c_str(),
                    p.description.c_str());
    }
  }
  return 0;
}

}  // namespace pbdval::cli
