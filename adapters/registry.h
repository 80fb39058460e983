// The engines one pbdval process knows: an explicit object, built by the command (built-in
// engines, and the external engines of a catalogue) or by a test (which may add its own), and
// passed to whatever plans or runs. No engine is registered globally.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

class EngineRegistry {
 public:
  explicit EngineRegistry(EngineOptions options = {});

  /// Adds an engine; throws std::invalid_argument when its name or a method name is taken, or a
  /// parameter's default does not satisfy its own declaration.
  void add(EngineEntry entry);

  const std::vector<EngineEntry>& entries() const { return entries_; }
  /// Engine names in registration order.
  std::vector<std::string> engineNames() const;
  /// The engines a run uses when none is named: all but the examples (runByDefault).
  std::vector<std::string> defaultEngineNames() const;
  /// Throws std::invalid_argument naming the known engines.
  const EngineEntry& engine(const std::string& name) const;
  /// Throws std::invalid_argument naming the known methods.
  const MethodInfo& method(const std::string& name) const;
  std::string defaultMethod(const std::string& engine) const {
    return this->engine(engine).defaultMethod;
  }
  /// EngineEntry::runMethods, or the default method alone.
  std::vector<std::string> runMethods(const std::string& engine) const;

  /// Defaults, then `overrides` (parameter → text), each parsed and checked against its
  /// declaration. Throws std::invalid_argument for an unknown parameter (naming the valid ones)
  /// or a value out of range (naming the range).
  Method resolve(const std::string& method,
                 const std::map<std::string, std::string>& overrides = {}) const;

  /// A new instance of `engine`, created with this registry's options.
  std::unique_ptr<Engine> make(const std::string& engine) const;
  /// A new instance of `engine` to step one step at a time (pbdval.Simulation, tests); throws
  /// std::invalid_argument for an engine that runs in another process.
  std::unique_ptr<SteppingEngine> makeStepping(const std::string& engine) const;

  const EngineOptions& options() const { return options_; }
  /// The same engines, created with `options` (a worker's server folder, for one).
  EngineRegistry withOptions(EngineOptions options) const;

 private:
  EngineOptions options_;
  std::vector<EngineEntry> entries_;
};

}  // namespace pbdval
