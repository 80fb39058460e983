// pbdval list [CASES or folders ...]: the cases with a one-line description each.
#include <cstdio>
#include <iostream>

#include "pbd/io/scene_loader.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/run/case_library.h"
#include "validation/run/case_spec.h"

namespace pbdval::cli {
namespace {

const char* referenceKind(ReferenceSpec::Kind kind) {
  switch (kind) {
    case ReferenceSpec::Kind::None:
      return "-";
    case ReferenceSpec::Kind::Analytic:
      return "analytic";
    case ReferenceSpec::Kind::Fine:
      return "fine step";
    case ReferenceSpec::Kind::Engine:
      return "engine";
  }
  return "-";
}

}  // namespace

int listCommand(const Context& context, const Arguments& arguments) {
  ArgParser parser("list", "[CASES or folders ...]",
                   "Prints the cases (default: cases/) with their duration, reference and a\n"
                   "one-line description (Validation.description).");
  parser.positionals("CASES", "scene files or folders of them (default: cases/)", 0, -1);
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  std::vector<std::string> files;
  try {
    files =
        collectCaseFiles(args.positionals.empty() ? std::vector<std::string>{defaultCaseFolder()}
                                                  : args.positionals);
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  int unreadable = 0;
  for (const std::string& file : files) {
    try {
      const pbd::Scene scene = pbd::loadScene(file).scene;
      const CaseSpec spec = parseCaseSpec(scene, context.engines);
      std::string reference = referenceKind(spec.reference.kind);
      if (spec.reference.kind == ReferenceSpec::Kind::Analytic)
        reference += " " + spec.reference.model;
      std::printf("%-36s %6.2f s  %-22s %s\n", caseNameOf(file).c_str(),
                  defaultDuration(scene, spec), reference.c_str(),
                  spec.description.empty() ? "(no description)" : spec.description.c_str());
    } catch (const std::exception& e) {
      ++unreadable;
      std::printf("%-36s error: %s\n", caseNameOf(file).c_str(), e.what());
    }
  }
  std::printf("%zu cases%s\n", files.size(),
              unreadable ? (", " + std::to_string(unreadable) + " unreadable").c_str() : "");
  return unreadable ? 1 : 0;
}

}  // namespace pbdval::cli
