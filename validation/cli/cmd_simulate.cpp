// pbdval simulate SCENE.json [--duration T] [--out FILE.csv] [--sample-interval S]
//                            [--engine E] [--method M] [--set key=value ...] [--strict]
//                            [--timeout S]
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <vector>

#include "adapters/engine.h"
#include "pbd/io/scene_loader.h"
#include "validation/cli/args.h"
#include "validation/cli/commands.h"
#include "validation/io/atomic_file.h"
#include "validation/io/mesh_export.h"
#include "validation/io/trajectory.h"
#include "validation/run/case_spec.h"
#include "validation/run/interrupts.h"
#include "validation/run/overrides.h"
#include "validation/run/simulation.h"

namespace pbdval::cli {
namespace {

ArgParser simulateParser() {
  ArgParser parser(
      "simulate", "SCENE.json [options]",
      "Runs SCENE.json headless in one engine and writes one CSV row per rigid body per sample:\n"
      "  t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
      "x,y,z: centre of mass (world); q: the body's scene frame -> world; v, w: linear and\n"
      "angular velocity (world). With --out FILE.npy, the same rows as NPY (float64, shape\n"
      "(rows, 15): no text conversion; numpy.load reads it). Warnings and a summary go to\n"
      "stderr.");
  parser
      .positionals("SCENE.json",
                   "a scene in the PositionBasedDynamics format (docs/scene-format.md)", 1, 1)
      .option("duration", "T",
              "simulated seconds (default: the scene's Validation.duration, else "
              "its pauseAt when > 0, else 5)")
      .option("out", "FILE.csv",
              "write the CSV here, atomically (default: standard output); FILE.npy: as NPY")
      .option("particles", "FILE.csv",
              "also write the particles' states here, one row per particle per sample "
              "(t,index,x,y,z,vx,vy,vz; FILE.npy: as NPY)")
      .option("segments", "FILE.csv",
              "also write the Cosserat-rod segments' orientations here, one row per segment per "
              "sample (t,index,qw,qx,qy,qz,wx,wy,wz: director frame -> world, angular velocity; "
              "FILE.npy: as NPY)")
      .option("sample-interval", "S", "seconds between samples (default: every step)")
      .option("timeout", "S",
              "wall-time limit of the run in seconds, as pbdval run's (default: 600; 0: none); "
              "a run over it ends with the status timeout")
      .option("export-dir", "DIR",
              "write the surface meshes (rigid bodies, cloth, solids) into DIR at the export "
              "frame rate, as the seed's exportOBJ/exportPLY do (docs/cli.md#mesh-export)")
      .option("export-format", "obj|ply|both",
              "the mesh files (default: the scene's exportOBJ/exportPLY, else obj)")
      .option("export-fps", "F", "frames per simulated second (default: the scene's exportFPS, 25)")
      .option("engine", "NAME",
              "pbd (default), bullet, ode or mujoco ('pbdval methods' lists them)")
      .option("method", "NAME", "a method of the engine (default: the engine's default method)")
      .option("set", "KEY=VALUE",
              "a method parameter or a Simulation setting, e.g. subSteps=10, "
              "timeStepSize=0.001",
              true)
      .flag("strict", "treat scene warnings (unknown keys, `gravity`) as errors")
      .flag("quiet", "no warnings, progress or summary on stderr")
      .epilog(
          "exit status: 0 ok; 1 the run failed (diverged, engine error, unsupported, timeout);\n"
          "2 bad usage or scene; 128+N interrupted by signal N (SIGINT, SIGTERM, "
          "SIGHUP).\nexample: pbdval simulate cases/joint_hinge.json --duration 2 --out "
          "hinge.csv");
  return parser;
}

}  // namespace

int simulateCommand(const Context& context, const Arguments& arguments) {
  const ArgParser parser = simulateParser();
  ParsedArgs args;
  if (const auto exit = parser.parseOrExit(arguments, args)) return *exit;
  const bool quiet = args.flags.count("quiet") > 0;
  const std::string scenePath = args.positionals[0];

  std::optional<pbd::LoadedScene> loaded = loadCommandScene(parser, args, scenePath);
  if (!loaded) return 2;
  pbd::Scene& scene = loaded->scene;

  std::string engineName, methodName;
  Method method;
  RunLength length;
  try {
    engineName = args.value("engine", "pbd");
    checkNames(context.engines, "--engine", {engineName});
    methodName = args.value("method", context.engines.defaultMethod(engineName));
    checkNames(context.engines, "--method", {methodName});
    const MethodInfo& info = context.engines.method(methodName);
    if (info.engine != engineName)
      throw UsageError("method " + methodName + " belongs to engine " + info.engine + ", not " +
                       engineName);
    // Every --set must have an effect in this engine and method (EngineEntry::honouredSettings).
    checkAssignments(args.values("set"), {methodName}, context.engines);
    method = resolveMethod(info, applyAssignments(args.values("set"), info, scene));
    // No output may replace the scene or another output (`--out` and `--particles` one file).
    checkOutputsAreNotInputs({{"--out", args.value("out")},
                              {"--particles", args.value("particles")},
                              {"--segments", args.value("segments")}},
                             {{"the scene", scenePath}});
    const CaseSpec spec = parseCaseSpec(scene, context.engines);
    length.duration = args.number("duration", defaultDuration(scene, spec));
    length.sampleInterval = args.number("sample-interval", 0);
    for (const std::string& note : planSteps(length, double(scene.simulation.timeStepSize)).notes)
      if (!quiet) std::fprintf(stderr, "note: %s\n", note.c_str());
  } catch (...) {
    return parser.exitForCurrentException();
  }

  // Mesh export: asked for by --export-dir; the scene's exportOBJ/exportPLY/exportFPS give the
  // defaults (without --export-dir the scene's request is only noted: nothing is written
  // where the user did not say).
  std::optional<MeshExporter> exporter;
  const pbd::ViewerSettings& viewer = scene.viewer;
  if (args.has("export-dir")) {
    try {
      MeshExportOptions options;
      options.directory = args.value("export-dir");
      const std::string format = args.value("export-format", "");
      if (format.empty()) {
        options.obj = viewer.exportOBJ || !viewer.exportPLY;
        options.ply = viewer.exportPLY;
      } else if (format == "obj" || format == "ply" || format == "both") {
        options.obj = format != "ply";
        options.ply = format != "obj";
      } else {
        throw UsageError("--export-format: expected obj, ply or both, got '" + format + "'");
      }
      options.framesPerSecond = args.number("export-fps", double(viewer.exportFPS));
      exporter.emplace(scene, options);
      if (!quiet)
        for (const std::string& note : exporter->notes())
          std::fprintf(stderr, "note: mesh export: %s\n", note.c_str());
    } catch (const std::exception& e) {
      return parser.inputError(e.what());
    }
  } else if ((args.has("export-format") || args.has("export-fps"))) {
    return parser.inputError("--export-format and --export-fps need --export-dir DIR");
  } else if ((viewer.exportOBJ || viewer.exportPLY) && !quiet) {
    std::fprintf(stderr,
                 "note: the scene asks for mesh export (exportOBJ/exportPLY); give --export-dir "
                 "DIR to write the meshes\n");
  }

  double timeout = kDefaultWallTimeLimit;
  try {
    timeout = args.number("timeout", kDefaultWallTimeLimit);
    if (!(timeout >= 0) || !std::isfinite(timeout))
      throw UsageError("--timeout: expected seconds >= 0 (0: no limit), got " +
                       args.value("timeout"));
  } catch (const std::exception& e) {
    return parser.usageError(e.what());
  }

  // SIGINT, SIGTERM and SIGHUP are taken between steps (and while an external engine runs):
  // the engine is stopped, the temporary output files are removed, nothing is written.
  const InterruptWatch interrupts;
  std::optional<AtomicFileWriter> file;
  if (args.has("out")) file.emplace(args.value("out"));
  std::ostream& out = file ? file->stream() : std::cout;
  // NPY needs its row count in the header: the samples are kept and written at the end.
  const bool npy = file && hasNpyExtension(args.value("out"));
  std::optional<AtomicFileWriter> particleFile;
  if (args.has("particles")) particleFile.emplace(args.value("particles"));
  const bool particleNpy = particleFile && hasNpyExtension(args.value("particles"));
  std::optional<AtomicFileWriter> segmentFile;
  if (args.has("segments")) segmentFile.emplace(args.value("segments"));
  const bool segmentNpy = segmentFile && hasNpyExtension(args.value("segments"));
  std::vector<State> kept;  // for the NPY files, whose headers need the row count
  if (!npy) writeCsvHeader(out);
  if (particleFile && !particleNpy) writeParticleCsvHeader(particleFile->stream());
  if (segmentFile && !segmentNpy) writeSegmentCsvHeader(segmentFile->stream());

  const bool showProgress = !quiet && ::isatty(STDERR_FILENO);
  RunCallbacks callbacks;
  long stepsSinceCheck = 0;
  callbacks.onStep = [&](const State& state) {
    if (++stepsSinceCheck >= 16) {  // a system call every 16 steps, not every step
      stepsSinceCheck = 0;
      interrupts.throwIfInterrupted();
    }
    if (exporter) exporter->onState(state);
  };
  std::size_t samples = 0;
  CsvRowWriter rows;
  callbacks.onSample = [&](const State& state) {
    if (npy || particleNpy || segmentNpy) kept.push_back(state);
    if (!npy) rows.write(out, state);
    if (particleFile && !particleNpy) writeParticleCsvRows(particleFile->stream(), state);
    if (segmentFile && !segmentNpy) writeSegmentCsvRows(segmentFile->stream(), state);
    ++samples;
  };
  if (showProgress)
    callbacks.onProgress = [&](double fraction, double elapsed) {
      std::fprintf(stderr, "\r  %s/%s: %5.1f%% of %g s simulated, %.1f s elapsed",
                   engineName.c_str(), methodName.c_str(), 100 * fraction, length.duration,
                   elapsed);
    };

  const std::unique_ptr<Engine> engine = context.engines.make(engineName);
  RunOutcome outcome;
  try {
    outcome = runSimulation(*engine, scene, method, length, callbacks, timeout);
    interrupts.throwIfInterrupted();
  } catch (const SignalInterrupt& e) {
    // The output files' destructors remove their temporary files; a FIFO or device keeps what
    // was written to it.
    if (showProgress) std::fprintf(stderr, "\n");
    std::fprintf(stderr, "pbdval simulate: %s; nothing was written\n", e.what());
    return 128 + e.signal();
  }
  if (showProgress) std::fprintf(stderr, "\r%70s\r", "");

  if (particleFile) {
    if (particleNpy) writeParticleTrajectoryNpy(particleFile->stream(), kept);
    particleFile->commit();
  }
  if (segmentFile) {
    if (segmentNpy) writeSegmentTrajectoryNpy(segmentFile->stream(), kept);
    segmentFile->commit();
  }
  if (file) {
    if (npy) writeTrajectoryNpy(out, kept);
    file->commit();
  } else {
    // `pbdval simulate ... > /dev/full` must not report success either.
    std::cout.flush();
    if (!std::cout) {
      std::fprintf(stderr, "pbdval simulate: error: writing the CSV to standard output failed\n");
      return 2;
    }
  }
  if (!quiet) {
    std::fprintf(
        stderr,
        "%s: %s/%s %s: %ld steps, %g s simulated in %.3f s (%.1fx real time), %zu samples x %zu "
        "bodies%s%s\n",
        scenePath.c_str(), engineName.c_str(), methodName.c_str(), runStatusName(outcome.status),
        outcome.steps, outcome.simulatedTime, outcome.wallTime,
        outcome.wallTime > 0 ? outcome.simulatedTime / outcome.wallTime : 0.0, samples,
        scene.rigidBodies.size(), file ? ", wrote " : "", file ? args.value("out").c_str() : "");
    if (exporter)
      std::fprintf(stderr, "mesh export: %zu frames, %zu files in %s\n", exporter->frames(),
                   exporter->files(), args.value("export-dir").c_str());
    if (outcome.status != RunStatus::Ok)
      std::fprintf(stderr, "reason: %s\n", outcome.reason.c_str());
  }
  return outcome.status == RunStatus::Ok ? 0 : 1;
}

}  // namespace pbdval::cli
