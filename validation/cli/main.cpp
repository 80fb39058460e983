// pbdval: the command-line front end (docs/cli.md).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "pbd/io/suggestion.h"
#include "pbd/math/types.h"
#include "pbdval/build_info.h"
#include "validation/cli/commands.h"
#include "validation/external/standard_engines.h"
#include "validation/run/run_scheduler.h"

namespace pbdval::cli {

const std::vector<Command>& commands() {
  static const std::vector<Command> all = {
      {"run", "run cases in every engine, isolated, and write results.json with the metrics",
       &runCommand},
      {"list", "list the cases with a one-line description each", &listCommand},
      {"sweep", "convergence study: a case over parameter values per method, with fitted orders",
       &sweepCommand},
      {"gate", "compare results with a baseline and the cases' checks; exit 1 on regression",
       &gateCommand},
      {"baseline", "write a baseline from a results folder", &baselineCommand},
      {"merge", "join the results folders of 'pbdval run --shard K/N' into one", &mergeCommand},
      {"report", "an HTML and Markdown report of a results folder (and sweeps)", &reportCommand},
      {"distance", "compare the PBD library's SDF collision distances with FCL's exact distances",
       &distanceCommand},
      {"simulate", "run one scene headless in one engine and write its trajectory as CSV",
       &simulateCommand},
      {"methods", "list the solver methods of every engine, with parameters and defaults",
       &methodsCommand},
      {"import", "a URDF or MJCF robot as a scene in the seed's format (docs/models.md)",
       &importCommand},
      {"export-scene", "write a scene resolved for an external engine (docs/external-engines.md)",
       &exportSceneCommand},
  };
  return all;
}

}  // namespace pbdval::cli

namespace {

void printOverview() {
  std::printf(
      "usage: pbdval COMMAND [ARGS...]\n\n"
      "pbdval runs the same scene files (rigid bodies and every joint of PositionBasedDynamics,\n"
      "contacts, cloth, solids, rods and fluids) in a position-based dynamics library and in\n"
      "reference engines, measures every engine the same way (energy, momentum, joint error,\n"
      "penetration, error against analytic references) and gates releases on the results.\n");
  // The engines are the registry's, never a list written here; a broken catalogue must not
  // take the help text down with it (the commands report it).
  try {
    const pbdval::EngineRegistry engines =
        pbdval::standardEngines([](const char* v) { return std::getenv(v); });
    // One line per 96 columns, as the rest of the help text.
    std::string line = "\nengines:";
    for (const auto& entry : engines.entries()) {
      const std::string name =
          " " + entry.name + (entry.runByDefault ? "" : " (by name only)") + ",";
      if (line.size() + name.size() > 96) {
        std::printf("%s\n", line.c_str());
        line = "        ";
      }
      line += name;
    }
    line.back() = '.';
    std::printf("%s\n'pbdval methods' lists their methods and parameters.\n", line.c_str());
  } catch (const std::exception& e) {
    std::printf("engines: the catalogue could not be read: %s\n", e.what());
  }
  std::printf("\ncommands:\n");
  for (const auto& c : pbdval::cli::commands())
    std::printf("  %-12s %s\n", c.name, c.summary);
  std::printf(
      "\n'pbdval help COMMAND' (or 'pbdval COMMAND --help') describes a command; 'pbdval "
      "--version' prints\nthe build. Documentation: docs/cli.md\n");
}

void printVersion() {
  std::printf("pbdval %s\n", PBDVAL_VERSION);
  std::printf("commit: %s (%s)\n", PBDVAL_GIT_COMMIT, PBDVAL_GIT_DIRTY);
  std::printf("build: %s, %s\n", PBDVAL_BUILD_TYPE, PBDVAL_CXX_COMPILER);
  std::printf("precision: pbd::Real = %s\n", sizeof(pbd::Real) == 8 ? "double" : "float");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && !std::strcmp(argv[1], "--version")) {
    printVersion();
    return 0;
  }
  const bool help = argc >= 2 && !std::strcmp(argv[1], "help");
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      (help && argc == 2)) {
    printOverview();
    return argc < 2 ? 2 : 0;
  }
  if (help && argc > 3) {
    std::fprintf(stderr, "pbdval help: expected one command name (see 'pbdval --help')\n");
    return 2;
  }
  // "pbdval help CMD" is "pbdval CMD --help".
  const std::string name = help ? argv[2] : argv[1];
  const pbdval::cli::Arguments arguments =
      help ? pbdval::cli::Arguments{"--help"} : pbdval::cli::Arguments(argv + 2, argv + argc);
  for (const auto& command : pbdval::cli::commands()) {
    if (name != command.name) continue;
    try {
      // The command, not the library, reads the environment (the grid SDF cache folder, the
      // engine catalogue).
      pbdval::EngineRegistry engines =
          pbdval::standardEngines([](const char* v) { return std::getenv(v); });
      return command.run(pbdval::cli::Context{engines}, arguments);
    } catch (const pbdval::RunInterrupted& e) {
      std::fprintf(stderr,
                   "\npbdval %s: %s; nothing was written (the previous results are as they were)\n",
                   command.name, e.what());
      return 128 + e.signal();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pbdval %s: error: %s\n", command.name, e.what());
      return 2;
    }
  }
  std::vector<std::string> names;
  for (const auto& command : pbdval::cli::commands())
    names.push_back(command.name);
  std::fprintf(stderr, "pbdval: unknown command '%s'%s (see 'pbdval --help')\n", name.c_str(),
               pbd::didYouMean(name, names).c_str());
  return 2;
}
