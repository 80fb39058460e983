// pbdval report RESULTS_DIR [--out DIR] [--baseline FILE] [--sweeps DIR...] [--quiet]
//
// The HTML and Markdown report of a results folder (docs/report.md). Written in Python
// (python/pbdval/report.py, the project's virtual environment): this command hands over to it.
#include "validation/cli/commands.h"
#include "validation/cli/python_module.h"
#include "validation/external/standard_engines.h"

namespace pbdval::cli {

int reportCommand(const Context& /*context*/, const Arguments& arguments) {
  std::vector<std::string> argv = {projectPython(), "-m", "pbdval.report"};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return execPython(argv);
}

}  // namespace pbdval::cli
