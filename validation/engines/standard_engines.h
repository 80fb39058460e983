// The engines every front end sees (the pbdval command and the Python module alike): the
// built-in ones and the external engines of the catalogue (docs/external-engines.md).
#pragma once

#include "adapters/registry.h"
#include <string>

#include "validation/cache_folder.h"

namespace pbdval {

/// The built-in engines (grid SDF cache from sdfCacheFolder(environment)) and the catalogue's
/// external engines: $PBDVAL_ENGINE_CATALOGUE when set, else <source>/engines, run with the
/// project's virtual environment (<source>/.venv/bin/python). Throws std::runtime_error for a
/// malformed catalogue (the message names the file).
EngineRegistry standardEngines(const EnvironmentLookup& environment);

/// The project's Python, by path (<source>/.venv/bin/python, made by scripts/install-deps): the
/// interpreter of the external engines, the Dask client and the report.
std::string projectPython();

}  // namespace pbdval
