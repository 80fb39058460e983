// pbdval import MODEL.urdf|MODEL.xml [--out SCENE.json] [--mesh-folder DIR] [--fixed-base]
//               [--no-collision] [--collision-links A,B] [--inertia-from-collision]
//               [--joint NAME=VALUE ...] [--quiet]
//
// A URDF or MJCF robot as a scene in the seed's format (docs/models.md). Written in Python
// (python/pbdval/import_model.py, the project's virtual environment): this command hands over
// to it.
#include "validation/cli/commands.h"
#include "validation/cli/python_module.h"
#include "validation/external/standard_engines.h"

namespace pbdval::cli {

int importCommand(const Context& /*context*/, const Arguments& arguments) {
  std::vector<std::string> argv = {projectPython(), "-m", "pbdval.import_model"};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return execPython(argv);
}

}  // namespace pbdval::cli
