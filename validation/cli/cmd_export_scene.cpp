// pbdval export-scene SCENE.json [--out FILE] [--method NAME] [--duration T]
//                                [--sample-interval S] [--strict] [--quiet]
// Writes the resolved scene (validation/external/resolved_scene.h, docs/external-engines.md).
#include <cstdio>
#include <iostream>

#include "pbd/io/scene_loader.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/external/resolved_scene.h"
#include "validation/io/atomic_file.h"
#include "validation/io/json_text.h"

namespace pbdval::cli {
namespace {

ArgParser exportSceneParser() {
  ArgParser parser(
      "export-scene", "SCENE.json [options]",
      "Writes the resolved scene of SCENE.json: the JSON document an external engine is run\n"
      "with (docs/external-engines.md; schema docs/schemas/resolved-scene.schema.json). Mass\n"
      "properties, principal frames, joint anchors and axes in both bodies' frames and every\n"
      "contact pair's friction and restitution are computed, nothing is left to interpret.");
  parser
      .positionals("SCENE.json",
                   "a scene in the PositionBasedDynamics format (docs/scene-format.md)", 1, 1)
      .option("out", "FILE", "write the document here, atomically (default: standard output)")
      .option("method", "NAME",
              "the method name recorded in the document's method block (default: none); its "
              "parameters are left empty")
      .option("duration", "T",
              "simulated seconds (default: the scene's Validation.duration, else its pauseAt "
              "when > 0, else 5)")
      .option("sample-interval", "S",
              "seconds between samples (default: Validation.sampleInterval, else every step)")
      .flag("strict", "treat scene warnings (unknown keys, `gravity`) as errors")
      .flag("quiet", "no warnings on stderr")
      .epilog("example: pbdval export-scene cases/joint_hinge.json --out hinge.resolved.json");
  return parser;
}

}  // namespace

int exportSceneCommand(const Context& context, const Arguments& arguments) {
  const ArgParser parser = exportSceneParser();
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  const std::string scenePath = args.positionals[0];

  std::optional<pbd::LoadedScene> loaded = loadCommandScene(parser, args, scenePath);
  if (!loaded) return 2;

  std::string text;
  try {
    RunLength length = caseRunLength(loaded->scene, context.engines);
    length.duration = args.number("duration", length.duration);
    length.sampleInterval = args.number("sample-interval", length.sampleInterval);
    // With --method, its parameters at their defaults, typed, as the runner would pass them.
    const std::string method = args.value("method", "");
    const nlohmann::json parameters = method.empty()
                                          ? nlohmann::json::object()
                                          : methodParametersJson(context.engines.resolve(method));
    checkOutputsAreNotInputs({{"--out", args.value("out")}}, {{"the scene", scenePath}});
    const nlohmann::json document = resolvedSceneJson(loaded->scene, method, parameters, length);
    text = jsonText(document, 1) + "\n";
  } catch (const UsageError& e) {
    return parser.usageError(e.what());
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  if (args.has("out")) {
    try {
      writeFileAtomically(args.value("out"), text);
    } catch (const std::exception& e) {
      return parser.inputError(e.what());
    }
  } else {
    std::cout << text;
  }
  return 0;
}

}  // namespace pbdval::cli
