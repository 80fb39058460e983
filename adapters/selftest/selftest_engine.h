// A hidden engine that misbehaves on purpose, to test that the runner isolates runs: its
// methods crash (SIGSEGV), hang, throw an EngineError, or produce NaN, halfway through the
// run. `selftest.ok` keeps every body at its initial pose. Run it by name only:
//   pbdval run CASE --engines selftest --methods selftest.crash
#pragma once

#include "adapters/registry.h"

namespace pbdval {

EngineEntry selftestEngineEntry();

}  // namespace pbdval
