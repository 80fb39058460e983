// The engines compiled into pbdval. The only place that knows every adapter: adding an engine
// is one line in built_in_engines.cpp (docs/engines.md).
#pragma once

#include "adapters/registry.h"

namespace pbdval {

/// A registry of pbd, bullet, ode and mujoco, created with `options`.
EngineRegistry builtInEngines(const EngineOptions& options = {});

}  // namespace pbdval
