// `--set KEY=VALUE`, the one route from text to a run's configuration: a key that is a
// parameter of the run's method becomes a method parameter (parsed and checked against its
// declaration by the registry); a key of the scene's Simulation block is applied to the scene
// with the scene loader's own checks (pbd::applySimulationSetting), so a value is accepted
// from `--set` exactly when it would be accepted in the scene file.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "adapters/engine.h"
#include "adapters/registry.h"
#include "pbd/model/scene.h"

namespace pbdval {

/// A command-line value that names nothing known, or that a run would ignore or reject (`--set`,
/// sweep `--param` and `--metric`): commands report it as bad usage (exit 2).
class OptionError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Splits "key=value"; throws std::invalid_argument when there is no '=' or no key.
std::pair<std::string, std::string> splitAssignment(const std::string& text);

/// Applies the Simulation-setting assignments to `scene` and returns the method-parameter ones
/// (key → text, for resolveMethod). Throws std::invalid_argument for a key that is neither (naming
/// both lists) and for a Simulation value the loader would reject (naming the accepted range).
std::map<std::string, std::string> applyAssignments(const std::vector<std::string>& assignments,
                                                    const MethodInfo& method, pbd::Scene& scene);

/// Whether `key` is a parameter of `method` or a Simulation setting that `engine` honours
/// (a sweep over a setting the engine ignores would measure nothing).
bool assignmentApplies(const std::string& key, const MethodInfo& method, const EngineEntry& engine);

/// Checks `assignments` (`--set KEY=VALUE`) against the methods a command will run, before
/// anything runs, so that no run is made with a setting it ignores or rejects:
///  - each is KEY=VALUE, and no KEY is given twice;
///  - KEY is a parameter of every method, or a Simulation setting that every method's engine
///    honours (EngineEntry::honouredSettings). A key none of them knows is an error naming the
///    accepted keys with a "did you mean"; a key that some of the methods would ignore is an error
///    naming them and the methods it applies to (restrict --engines or --methods to those);
///  - VALUE is accepted by the parameter's declaration or by the scene loader's checks.
/// Throws OptionError with that message; `option` names the option ("--set").
void checkAssignments(const std::vector<std::string>& assignments,
                      const std::vector<std::string>& methods, const EngineRegistry& registry,
                      const std::string& option = "--set");

/// Checks one value of `key` for one method: as its parameter, else as a Simulation setting
/// (with the loader's checks). Throws OptionError naming `origin` and the range.
void checkAssignmentValue(const std::string& key, const std::string& value,
                          const MethodInfo& method, const std::string& origin);

/// "unknown setting 'KEY' (parameters of M1: ...; Simulation settings honoured: ...); did you
/// mean ...": the message for a key that none of `methods` knows.
std::string unknownSettingMessage(const std::string& key, const std::vector<std::string>& methods,
                                  const EngineRegistry& registry);

/// A reference engine (`pbdval run` and `pbdval sweep` `--reference METHOD[:KEY=VALUE,...]`,
/// docs/convergence.md#a-converged-reference): every run is measured against METHOD's run of the
/// same scene, at the run's step and sample times, with these method parameters (drake.rk3 at
/// targetAccuracy=1e-10: the converged reference).
struct EngineReference {
  std::string method;
  std::vector<std::string> assignments;  ///< KEY=VALUE, parameters of `method`
};

/// Whether a RunRequest::referenceMode names an engine reference (not "", "fine" or "none").
bool isEngineReference(const std::string& referenceMode);

/// Parses `text` (METHOD[:KEY=VALUE,...]): METHOD a registered method, each KEY one of its
/// parameters, given once, with a value its declaration accepts. Throws OptionError naming
/// `option`, the text and what was expected.
EngineReference parseEngineReference(const std::string& text, const EngineRegistry& registry,
                                     const std::string& option = "--reference");

}  // namespace pbdval
