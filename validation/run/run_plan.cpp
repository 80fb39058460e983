#include "validation/run/run_plan.h"

#include <algorithm>

#include "pbd/io/scene_loader.h"
#include "validation/run/case_library.h"

namespace pbdval {
namespace {

bool contains(const std::vector<std::string>& list, const std::string& item) {
  return std::find(list.begin(), list.end(), item) != list.end();
}

/// The methods one engine runs for a case:
///  - with --methods: those of the engine; an engine named in --engines without a listed method
///    runs its default; other engines none;
///  - else the case's Validation.methods of the engine, else the engine's default.
std::vector<std::string> methodsFor(const std::string& engine, const PlanOptions& options,
                                    const CaseSpec& spec, const EngineRegistry& registry) {
  auto ofEngine = [&](const std::vector<std::string>& methods) {
    std::vector<std::string> selected;
    for (const std::string& m : methods)
      if (registry.method(m).engine == engine) selected.push_back(m);
    return selected;
  };
  if (!options.methods.empty()) {
    std::vector<std::string> selected = ofEngine(options.methods);
    if (selected.empty() && contains(options.engines, engine))
      selected.push_back(registry.defaultMethod(engine));
    return selected;
  }
  std::vector<std::string> selected = ofEngine(spec.methods);
  if (selected.empty()) selected = registry.runMethods(engine);
  return selected;
}

}  // namespace

std::string trajectoryPathFor(const std::string& outFolder, const std::string& caseName,
                              const std::string& engine, const std::string& method,
                              TrajectoryFormat format) {
  return outFolder + "/trajectories/" + caseName + "/" + engine + "-" + method + "." +
         trajectoryFormatName(format);
}

namespace {

/// "DIR/E-M.csv" → "DIR/E-M" + infix + ".csv".
std::string besideTrajectory(const std::string& trajectoryPath, const char* infix) {
  const std::size_t dot = trajectoryPath.find_last_of('.');
  const std::size_t slash = trajectoryPath.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return trajectoryPath + infix;
  return trajectoryPath.substr(0, dot) + infix + trajectoryPath.substr(dot);
}

}  // namespace

std::string particlePathFor(const std::string& trajectoryPath) {
  return besideTrajectory(trajectoryPath, ".particles");
}

std::string segmentPathFor(const std::string& trajectoryPath) {
  return besideTrajectory(trajectoryPath, ".segments");
}

std::vector<std::string> companionPathsFor(const std::string& trajectoryPath) {
  return {particlePathFor(trajectoryPath), segmentPathFor(trajectoryPath)};
}

RunPlan planRuns(const std::vector<std::string>& caseFiles, const PlanOptions& options,
                 const EngineRegistry& registry) {
  for (const std::string& engine : options.engines)
    registry.engine(engine);  // throws if unknown
  for (const std::string& method : options.methods) {
    const MethodInfo& info = registry.method(method);
    if (!options.engines.empty() && !contains(options.engines, info.engine))
      throw std::invalid_argument("method " + method + " belongs to engine " + info.engine +
                                  ", which --engines does not select");
  }
  // Without --engines: the engines that run by default, and those of the --methods named (an
  // engine run by name only, such as newton, is named by its method as well as by --engines).
  std::vector<std::string> engines =
      options.engines.empty() ? registry.defaultEngineNames() : options.engines;
  if (options.engines.empty())
    for (const std::string& method : options.methods)
      if (!contains(engines, registry.method(method).engine))
        engines.push_back(registry.method(method).engine);

  RunPlan plan;
  for (const std::string& file : caseFiles) {
    const std::string name = caseNameOf(file);
    CaseSpec spec;
    try {
      pbd::LoadOptions load;
      load.strict = options.strictScene;
      spec = parseCaseSpec(pbd::loadScene(file, load).scene, registry);
    } catch (const std::exception& e) {
      RunRecord failed;
      failed.request.caseName = name;
      failed.request.caseFile = file;
      failed.request.engine = "-";
      failed.request.method = "-";
      failed.status = RunStatus::Error;
      failed.reason = e.what();
      plan.unreadable.push_back(failed);
      continue;
    }
    plan.cases[name] = {file, spec};
    for (const std::string& engine : engines) {
      if (!spec.engines.empty() && !contains(spec.engines, engine)) continue;
      const std::vector<std::string> methods = methodsFor(engine, options, spec, registry);
      for (const std::string& method : methods) {
        RunRequest r;
        r.caseName = name;
        r.caseFile = file;
        r.engine = engine;
        r.method = method;
        r.assignments = options.assignments;
        r.referenceMode = options.referenceMode;
        r.strictScene = options.strictScene;
        if (options.writeTrajectories)
          r.trajectoryPath =
              trajectoryPathFor(options.outFolder, name, engine, method, options.trajectoryFormat);
        plan.requests.push_back(r);
      }
    }
  }
  return plan;
}

}  // namespace pbdval
