// The pbdval subcommands. Each takes its arguments (after the command name) and returns the
// process exit code: 0 success, 1 a run or check failed, 2 bad usage or unreadable input.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "adapters/registry.h"
#include "pbd/io/scene_loader.h"
#include "validation/cli/args.h"

namespace pbdval::cli {

using Arguments = std::vector<std::string>;

/// What every command is given besides its arguments: the engines of this process (built-in,
/// created with the grid cache folder the command chose).
struct Context {
  const EngineRegistry& engines;
};

int simulateCommand(const Context& context, const Arguments& args);
int methodsCommand(const Context& context, const Arguments& args);
int runCommand(const Context& context, const Arguments& args);
int listCommand(const Context& context, const Arguments& args);
int gateCommand(const Context& context, const Arguments& args);
int sweepCommand(const Context& context, const Arguments& args);
int distanceCommand(const Context& context, const Arguments& args);
int baselineCommand(const Context& context, const Arguments& args);
int exportSceneCommand(const Context& context, const Arguments& args);
int mergeCommand(const Context& context, const Arguments& args);
int reportCommand(const Context& context, const Arguments& args);
int importCommand(const Context& context, const Arguments& args);

/// The scene named on a command's command line, loaded with `--strict` honoured and its
/// warnings printed unless `--quiet`; nullopt after printing the error (the command exits 2).
std::optional<pbd::LoadedScene> loadCommandScene(const ArgParser& parser, const ParsedArgs& args,
                                                 const std::string& path);

/// Checks that every name of `option` ("--engines", "--methods") names an engine or a method of
/// `engines`; throws UsageError with the registry's message (known names, "did you mean").
void checkNames(const EngineRegistry& engines, const std::string& option,
                const std::vector<std::string>& names);

/// `--engines` with the word `default` replaced by the engines that run when none is named
/// (EngineRegistry::defaultEngineNames, in their order), each engine once: `--engines
/// default,newton` is the default set plus an engine run by name only.
std::vector<std::string> withDefaultEnginesExpanded(const std::vector<std::string>& names,
                                                    const EngineRegistry& engines);

struct Command {
  const char* name;
  const char* summary;
  int (*run)(const Context& context, const Arguments& args);
};

/// All commands, in the order `pbdval --help` lists them.
const std::vector<Command>& commands();

}  // namespace pbdval::cli
