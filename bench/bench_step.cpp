// The cost of one step, per engine and case, through the Engine interface (the runner's path).
// Each benchmark loads the case, takes 50 warm-up steps, then times single steps over the first
// kHorizonSeconds of the scene, reloading it (untimed) whenever that horizon is reached, so the
// measured motion is the scene's own and never a blown-up state. An engine error or divergence
// ends that benchmark with the message, not the program. Build metadata (commit, compiler,
// flags, precision) goes into the benchmark context.
//
//   build/release/bench/pbdval_bench [--benchmark_filter=chain] [--benchmark_out=file.json]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "adapters/built_in_engines.h"
#include "pbd/io/scene_loader.h"
#include "pbd/math/types.h"
#include "pbdval/build_info.h"
#include "scaling_scenes.h"

namespace {

constexpr double kHorizonSeconds = 2.0;

void stepScene(benchmark::State& state, const pbdval::EngineRegistry& engines,
               const pbd::Scene& scene, const std::string& method, int warmUpSteps = 50) {
  // "name@key=value": a method with one parameter set (e.g. pbd@threads=2).
  const std::size_t at = method.find('@');
  const std::string name = method.substr(0, at);
  std::map<std::string, std::string> overrides;
  if (at != std::string::npos) {
    const std::string assignment = method.substr(at + 1);
    const std::size_t equals = assignment.find('=');
    overrides[assignment.substr(0, equals)] = assignment.substr(equals + 1);
  }
  const pbdval::Method resolved = engines.resolve(name, overrides);
  std::unique_ptr<pbdval::SteppingEngine> engine =
      engines.makeStepping(engines.method(name).engine);
  const std::vector<std::string> missing = engine->unsupported(scene, resolved);
  if (!missing.empty()) {
    std::string reason = "unsupported:";
    for (const std::string& feature : missing)
      reason += " " + feature + (&feature == &missing.back() ? "" : ";");
    state.SkipWithError(reason.c_str());
    return;
  }
  const long stepsPerLoad = std::max(
      long(warmUpSteps) + 1, long(std::ceil(kHorizonSeconds / scene.simulation.timeStepSize)));
  try {
    engine->load(scene, resolved);
    for (int k = 0; k < warmUpSteps; ++k)
      engine->step();
    long stepsTaken = warmUpSteps;
    for (auto _ : state) {
      if (stepsTaken == stepsPerLoad) {
        state.PauseTiming();
        engine->load(scene, resolved);
        for (int k = 0; k < warmUpSteps; ++k)
          engine->step();
        stepsTaken = warmUpSteps;
        state.ResumeTiming();
      }
      engine->step();
      ++stepsTaken;
    }
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  state.counters["steps_per_s"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["bodies"] = double(scene.rigidBodies.size());
  state.counters["real_time_factor"] =
      benchmark::Counter(double(state.iterations()) * double(scene.simulation.timeStepSize),
                         benchmark::Counter::kIsRate);
}

void stepCase(benchmark::State& state, const pbdval::EngineRegistry& engines,
              const std::string& caseName, const std::string& method) {
  const pbd::Scene scene =
      pbd::loadScene(std::string(PBDVAL_SOURCE_DIR) + "/cases/" + caseName + ".json").scene;
  stepScene(state, engines, scene, method);
}

/// One member of a scaling family (scaling_scenes.h), generated and loaded untimed.
void stepScaling(benchmark::State& state, const pbdval::EngineRegistry& engines,
                 const std::string& family, int bodies, const std::string& method) {
  const std::string models = std::string(PBDVAL_SOURCE_DIR) + "/cases/models";
  const std::string text = family == "chain"
                               ? pbdval::bench::chainScene(bodies, models)
                               : pbdval::bench::pileScene(bodies, family == "boxes", models);
  const pbd::Scene scene = pbd::parseScene(text, "scaling_" + family + ".json").scene;
  // 10 warm-up steps (50 ms: the piles' upper bodies have landed) instead of the cases' 50, as
  // a step of 10,000 bodies can take seconds.
  stepScene(state, engines, scene, method, 10);
}

/// One member of a particle scaling family (cloth: side² particles, solid: side³).
void stepParticleScaling(benchmark::State& state, const pbdval::EngineRegistry& engines,
                         const std::string& family, int side, const std::string& method) {
  pbd::Scene scene;
  if (family == "cloth")
    scene = pbdval::bench::clothScene(side);
  else if (family == "solid")
    scene = pbdval::bench::solidScene(side);
  else if (family == "rod")
    scene = pbd::parseScene(pbdval::bench::rodScene(side), "scaling_rod.json").scene;
  else
    scene = pbd::parseScene(pbdval::bench::fluidScene(side), "scaling_fluid.json").scene;
  stepScene(state, engines, scene, method, 10);
  state.counters["particles"] = double(scene.particles.size());
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> cases = {
      "chain_10",        "chain_100",           "double_pendulum",
      "contact_stack_5", "contact_sphere_pile", "contact_pyramid",
      "xpbd_pyramid_15", "contact_pile",        "car"};
  const std::vector<std::string> methods = {
      "pbd", "pbd.xpbd", "bullet.si", "ode.quickstep", "ode.step", "mujoco.euler", "mujoco.rk4"};
  // No grid cache: built in memory.
  const pbdval::EngineRegistry engines = pbdval::builtInEngines();
  for (const std::string& c : cases)
    for (const std::string& m : methods) {
      const auto run = [&engines, c, m](benchmark::State& s) { stepCase(s, engines, c, m); };
      benchmark::RegisterBenchmark(("step/" + c + "/" + m).c_str(), run)
          ->Unit(benchmark::kMicrosecond);
    }
  // Scaling families: 10 to 10,000 bodies, the PBD methods and the two reference engines whose
  // cost is linear in the body count (MuJoCo's dense factorisation of a 10,000-link tree is not
  // a fair member of this family). Fitted by bench/fit_scaling.py.
  // The piles also with the collision detection on two threads (the `threads` parameter; the
  // XPBD step spends under a tenth of its time in the detection, so only `pbd`).
  const std::vector<std::string> scalingMethods = {"pbd", "pbd.xpbd", "bullet.si", "ode.quickstep"};
  const std::vector<std::string> threadedMethods = {"pbd@threads=2"};
  for (const std::string family : {"chain", "spheres", "boxes"}) {
    std::vector<std::string> familyMethods = scalingMethods;
    if (family != "chain")
      familyMethods.insert(familyMethods.begin() + 2, threadedMethods.begin(),
                           threadedMethods.end());
    for (const std::string& m : familyMethods)
      for (const int n : {10, 30, 100, 300, 1000, 3000, 10000})
        benchmark::RegisterBenchmark(
            ("scaling/" + family + "/" + m + "/" + std::to_string(n)).c_str(),
            [&engines, family, m, n](benchmark::State& s) {
              stepScaling(s, engines, family, n, m);
            })
            ->Unit(benchmark::kMicrosecond)
            // The same 20 steps (0.05 to 0.15 s) for every N: with an adaptive iteration count a
            // small scene would be timed over its whole 2 s and a large one over its first steps,
            // different motions (landing, settling) with different contact counts.
            ->Iterations(20);
  }
  // Particle families: 10² to 10⁵ particles (named by the exact count), the PBD methods only
  // (no reference engine simulates cloth, solids, rods or fluids here).
  // The rod family's "side" is its particle count.
  for (const std::string family : {"cloth", "solid", "rod", "fluid"}) {
    const std::vector<int> sides = family == "cloth" ? std::vector<int>{10, 32, 100, 316}
                                   : family == "rod" ? std::vector<int>{100, 1000, 10000, 100000}
                                                     : std::vector<int>{5, 10, 22, 46};
    for (const std::string m : {"pbd", "pbd.xpbd"})
      for (const int side : sides) {
        const int particles = family == "cloth" ? side * side
                              : family == "rod" ? side
                                                : side * side * side;
        benchmark::RegisterBenchmark(
            ("scaling/" + family + "/" + m + "/" + std::to_string(particles)).c_str(),
            [&engines, family, m, side](benchmark::State& s) {
              stepParticleScaling(s, engines, family, side, m);
            })
            ->Unit(benchmark::kMicrosecond)
            ->Iterations(20);
      }
  }
  benchmark::AddCustomContext("pbdval_version", PBDVAL_VERSION);
  benchmark::AddCustomContext("pbdval_commit",
                              std::string(PBDVAL_GIT_COMMIT) + " (" + PBDVAL_GIT_DIRTY + ")");
  benchmark::AddCustomContext("build_type", PBDVAL_BUILD_TYPE);
  benchmark::AddCustomContext("compiler", PBDVAL_CXX_COMPILER);
  benchmark::AddCustomContext("flags", PBDVAL_CXX_FLAGS);
  benchmark::AddCustomContext("precision", sizeof(pbd::Real) == 8 ? "double" : "float");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
