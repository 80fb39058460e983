// Where `pbdval` keeps its grid SDF cache. The PBD library reads no environment: the command
// decides the folder and passes it down (pbd::CollisionShapeOptions::gridCacheFolder).
#pragma once

#include <functional>
#include <string>

namespace pbdval {

/// Looks up an environment variable: its value, or nullptr when it is not set.
using EnvironmentLookup = std::function<const char*(const char* name)>;

/// $PBDVAL_SDF_CACHE when set (an empty value disables the cache), else $XDG_CACHE_HOME/pbdval,
/// else $HOME/.cache/pbdval; empty (no cache) when none is set. Never inside the repository.
std::string sdfCacheFolder(const EnvironmentLookup& lookup);

}  // namespace pbdval
