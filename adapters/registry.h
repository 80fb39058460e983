// The engines compiled into pbdval. Each adapter folder provides one EngineEntry; registry.cpp
// lists them (one line per engine).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

struct EngineEntry {
  std::string name;           ///< "pbd", "bullet", "ode", "mujoco"
  std::string defaultMethod;  ///< used when a run names the engine only
  std::vector<MethodInfo> (*methods)();
  std::unique_ptr<Engine> (*make)();
  /// Hidden engines (the self-test engine) are not listed or run by default, only by name.
  bool hidden = false;
};

const std::vector<EngineEntry>& engineEntries();

}  // namespace pbdval
