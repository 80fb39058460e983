// pbdval distance [SCENE...] [--samples N] [--seed S] [--json FILE]
#include <cstdint>
#include <cstdio>
#include <iostream>

#include "pbd/io/scene_loader.h"
#include "pbdval/build_info.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/io/atomic_file.h"
#include "validation/run/case_library.h"
#include "validation/studies/distance_study.h"

namespace pbdval::cli {

int distanceCommand(const Context& /*context*/, const Arguments& arguments) {
  ArgParser parser(
      "distance", "[SCENE...] [--samples N] [--seed S] [--json FILE]",
      "Compares the PBD library's signed-distance collision detection with FCL's exact distances\n"
      "(docs/cli.md#distance). For every pair of collision shapes (the built-in set: sphere, box,\n"
      "cylinder, torus and a grid SDF of a non-convex mesh; or every body of the SCENEs) and N\n"
      "random relative poses near contact, it prints the max, RMS and mean error of the distance\n"
      "PBD's detection sees (surface samples against the other body's SDF, both ways); for grid\n"
      "SDFs, also the point error at resolutionSDF 8, 16, 32, 64 with the fitted order.");
  parser.positionals("SCENE", "scenes whose bodies to use (default: the built-in shapes)", 0, -1)
      .option("samples", "N", "poses per pair and points per grid resolution (default 200)")
      .option("seed", "S", "seed of the random poses (default 1): same seed, same numbers")
      .option("json", "FILE", "also write the numbers as JSON (atomically)");
  ParsedArgs args;
  DistanceStudyOptions options;
  std::vector<pbd::RigidBodyDesc> shapes;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  try {
    options.samples = int(args.integerIn("samples", 200, 1, 1000000));
    options.seed = std::uint64_t(args.integerIn("seed", 1, 0, INT64_MAX));
    if (args.positionals.empty()) {
      shapes = builtInShapes(defaultCaseFolder() + "/models");
    } else {
      std::vector<pbd::Scene> scenes;
      for (const std::string& path : args.positionals)
        scenes.push_back(pbd::loadScene(path).scene);
      shapes = shapesOfScenes(scenes);
    }
    std::vector<NamedPath> scenes;
    for (const std::string& path : args.positionals)
      scenes.push_back({"the scene", path});
    checkOutputsAreNotInputs({{"--json", args.value("json")}}, scenes);
    if (args.has("json")) checkOutputFile(args.value("json"));  // before the study
  } catch (const UsageError& e) {
    return parser.usageError(e.what());
  } catch (const std::exception& e) {
    return parser.inputError(e.what());
  }
  const DistanceStudy study = runDistanceStudy(shapes, options);
  std::printf(
      "PBD detection distance vs FCL exact distance, %d poses per pair near contact (seed "
      "%llu)\n\n",
      options.samples, static_cast<unsigned long long>(options.seed));
  std::printf("%-34s %-34s %8s %12s %12s %12s\n", "shape A", "shape B", "samples", "max |err| m",
              "RMS m", "mean m");
  for (const PairErrors& p : study.pairs)
    std::printf("%-34s %-34s %8d %12.3e %12.3e %12.3e\n", p.shapeA.c_str(), p.shapeB.c_str(),
                p.samples, p.maxAbsError, p.rmsError, p.meanError);
  for (const GridErrors& g : study.grids) {
    std::printf(
        "\ngrid SDF %s: point error against the exact mesh distance (%d points outside, 5 mm to 10 "
        "cm, inside the grid)\n",
        g.shape.c_str(), g.samples);
    std::printf("  %10s %12s %12s %12s\n", "resolution", "cell m", "max |err| m", "RMS m");
    for (std::size_t k = 0; k < g.resolutions.size(); ++k)
      std::printf("  %10d %12.4f %12.3e %12.3e\n", g.resolutions[k], g.cellSizes[k],
                  g.maxAbsErrors[k], g.rmsErrors[k]);
    std::printf("  fitted order of max |err| in the cell size: %.2f (R^2 %.3f)\n", g.order,
                g.rSquared);
  }
  for (const std::string& note : study.notes)
    std::printf("note: %s\n", note.c_str());
  if (args.has("json")) {
    try {
      writeFileAtomically(args.value("json"), distanceStudyJson(study, options));
    } catch (const std::exception& e) {
      return parser.inputError(e.what());
    }
  }
  return 0;
}

}  // namespace pbdval::cli
