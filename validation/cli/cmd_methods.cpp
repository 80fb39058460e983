// pbdval methods [ENGINE...]: the solver methods of every engine, with parameters and defaults.
#include <cstdio>
#include <iostream>

#include "adapters/engine.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"

namespace pbdval::cli {

int methodsCommand(const Arguments& arguments) {
  ArgParser parser(
      "methods", "[ENGINE...]",
      "Lists the solver methods of every engine compiled in (or of the engines\n"
      "named), with their parameters and defaults. Select one with\n"
      "'pbdval simulate --engine E --method M --set PARAM=VALUE'. See docs/methods.md.");
  parser.positionals("ENGINE", "engines to list (default: all)", 0, -1);
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  const std::vector<std::string> engines = engineNames();
  for (const std::string& wanted : args.positionals) {
    bool known = false;
    for (const std::string& e : engines)
      known = known || e == wanted;
    if (!known) {
      return parser.usageError("unknown engine '" + wanted + "'");
    }
  }
  for (const std::string& engine : engines) {
    bool listed = args.positionals.empty();
    for (const std::string& wanted : args.positionals)
      listed = listed || wanted == engine;
    if (!listed) continue;
    std::printf("%s (default method: %s)\n", engine.c_str(), defaultMethod(engine).c_str());
    for (const MethodInfo& m : methodCatalog()) {
      if (m.engine != engine) continue;  // (hidden engines are not in engineNames())
      std::printf("  %s\n      %s\n", m.name.c_str(), m.description.c_str());
      for (const MethodParameter& p : m.parameters)
        std::printf("      --set %s=%s  %s\n", p.name.c_str(), p.defaultValue.c_str(),
                    p.description.c_str());
    }
  }
  return 0;
}

}  // namespace pbdval::cli
