// A test engine that misbehaves on purpose, to test that the runner isolates runs: its
// methods crash (SIGSEGV), hang, throw an EngineError, or produce NaN, halfway through the
// run. `selftest.ok` keeps every body at its initial pose. Registered by the tests only
// (testEngines() in tests/engines), never by the pbdval command.
#pragma once

#include "adapters/registry.h"

namespace pbdval {

EngineEntry selftestEngineEntry();

/// The built-in engines plus the self-test engine.
EngineRegistry testEngines(const EngineOptions& options = {});

/// The registry the tests share: testEngines() without a grid cache, created on first use and
/// never changed (test support only; the pbdval command builds its own and passes it down).
const EngineRegistry& testRegistry();

}  // namespace pbdval
