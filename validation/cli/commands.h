// The pbdval subcommands. Each takes its arguments (after the command name) and returns the
// process exit code: 0 success, 1 a run or check failed, 2 bad usage or unreadable input.
#pragma once

#include <string>
#include <vector>

namespace pbdval::cli {

using Arguments = std::vector<std::string>;

int simulateCommand(const Arguments& args);
int methodsCommand(const Arguments& args);
int runCommand(const Arguments& args);
int listCommand(const Arguments& args);
int gateCommand(const Arguments& args);
int sweepCommand(const Arguments& args);
int distanceCommand(const Arguments& args);
int baselineCommand(const Arguments& args);
int exportSceneCommand(const Arguments& args);

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const Arguments& args);
};

/// All commands, in the order `pbdval --help` lists them.
const std::vector<Command>& commands();

}  // namespace pbdval::cli
