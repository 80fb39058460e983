// The engines every front end sees (the pbdval command and the Python module alike): the
// built-in ones and the external engines of the catalogue (docs/external-engines.md).
#pragma once

#include <string>

#include "adapters/registry.h"
#include "validation/io/cache_folder.h"

namespace pbdval {

/// The built-in engines (grid SDF cache from sdfCacheFolder(environment)) and the catalogue's
/// external engines: <source>/engines, then each folder of $PBDVAL_ENGINE_CATALOGUE (a
/// ':'-separated list) added to them, run with the project's virtual environment
/// (<source>/.venv/bin/python) with <source>/python first on their PYTHONPATH. Throws
/// std::invalid_argument for a malformed catalogue or an engine named like one already registered
/// (the message names the file or folder).
EngineRegistry standardEngines(const EnvironmentLookup& environment);

/// The project's Python, by path (<source>/.venv/bin/python, made by scripts/install-deps): the
/// interpreter of the external engines, the Dask client and the report.
std::string projectPython();

}  // namespace pbdval
