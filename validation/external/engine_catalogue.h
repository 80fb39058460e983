// The external-engine catalogue (docs/external-engines.md#the-catalogue): one `<name>.json` per
// engine, read into the registry's EngineEntry. What a file must look like is declared once, in
// docs/schemas/catalogue.schema.json, and checked through the runner's schema validator
// (validation/io/json_schema.h); this reader adds only the rules a schema cannot state (method
// names prefixed by the engine's, a default within its own declaration, runMethods among the
// entry's methods, a feature table that covers every feature).
#pragma once

#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

/// The Python that runs the catalogue commands naming "{python}": the interpreter, by path, and
/// the folder put first on those engines' PYTHONPATH, so that `python -m pbdval.external.<name>`
/// imports pbdval from this source tree whatever the interpreter's own path says.
struct ProjectPython {
  std::string interpreter;
  std::string packageFolder;
};

/// The engines of a catalogue folder: one `<name>.json` per engine, in the order of their file
/// names, each command's "{python}" replaced by `python.interpreter` (and such a command run with
/// `python.packageFolder` first on its PYTHONPATH). Every command runs in the catalogue's folder,
/// so that relative paths in it (a program, a script) are relative to the catalogue file. An
/// entry with `serve` (its protocol and command) gets EngineEntry::startServer. Throws
/// std::invalid_argument naming the file and the JSON path of anything malformed (every schema
/// violation, joined by "; "). A missing folder has no engines.
std::vector<EngineEntry> readEngineCatalogue(const std::string& folder,
                                             const ProjectPython& python);

}  // namespace pbdval
