// Convergence of the particle solvers against substeps and iterations (issue: "error against
// substeps and against iterations for PBD and XPBD on the oscillator, the chain and the beam").
// Each study's error is against a closed form or an independent solution:
//   oscillator  XPBD spring, m = 1 kg, k = 100 N/m (ω = 10 rad/s), released 1 cm stretched,
//               no gravity, 10 ms frames, 2 s: max |x − A cos ωt| / A over the frames.
//   chain       20 particles of 0.1 kg, 5 cm links, hanging from a static one, 5 ms frames,
//               settled by mass-proportional damping (c = 20/s, below the lowest axial mode's
//               25 rad/s; it moves no fixed point) for 3 s. XPBD links of 10⁴ N/m: the total
//               stretch against the closed form m g/k · n(n+1)/2 = 20.6 mm, relative. PBD links
//               of stiffness 1 (rigid in the limit): the total stretch relative to the length.
//   beam        tests/common/cantilever_beam.h (2 cells across, 240 tets): the static tip
//               deflection of XPBD FEM (solid method 3) and PBD FEM (method 2) against the
//               linear FEM solution of the same mesh, relative.
// For every study the grid substeps × iterations ∈ {1, 2, 4, 8, 16}²; the cost of a frame is
// proportional to their product, so the anti-diagonals compare equal cost. Writes JSON with the
// build's metadata (--json PATH, atomically) and prints Markdown tables (docs/convergence.md).
//   pbdval_particle_convergence [--json PATH]
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/cantilever_beam.h"
#include "pbd/constraints/particle_distance.h"
#include "pbd/model/world.h"
#include "pbdval/build_info.h"
#include "validation/io/atomic_file.h"

namespace {

using pbd::Real;
using pbd::Vector3;

Real oscillatorError(int substeps, int iterations) {
  pbd::Scene scene;
  scene.simulation.gravitation = Vector3::Zero();
  scene.simulation.timeStepSize = Real(0.01);
  scene.simulation.subSteps = substeps;
  scene.simulation.maxIterations = iterations;
  const Real mass = 1, stiffness = 100, amplitude = Real(0.01);
  scene.particles.push_back({Vector3::Zero(), Vector3::Zero(), 0});
  scene.particles.push_back({Vector3(1 + amplitude, 0, 0), Vector3::Zero(), mass});
  pbd::World world = pbd::buildWorld(scene);
  pbd::ParticleDistanceConstraint c;
  c.particle1 = 0;
  c.particle2 = 1;
  c.restLength = 1;
  c.xpbd = true;
  c.stiffness = stiffness;
  world.constraints.particleDistances.push_back(c);
  const Real omega = std::sqrt(stiffness / mass);
  Real worst = 0;
  while (world.time < 2) {
    world.step();
    const Real exact = amplitude * std::cos(omega * world.time);
    worst = std::max(worst, std::abs(world.bodies.particles.position[1].x() - 1 - exact));
  }
  return worst / amplitude;
}

Real chainError(bool xpbd, int substeps, int iterations) {
  pbd::Scene scene;
  scene.simulation.timeStepSize = Real(0.005);
  scene.simulation.subSteps = substeps;
  scene.simulation.maxIterations = iterations;
  const int count = 20;
  const Real mass = Real(0.1), spacing = Real(0.05), stiffness = Real(1e4);
  for (int i = 0; i <= count; ++i)
    scene.particles.push_back(
        {Vector3(0, -spacing * Real(i), 0), Vector3::Zero(), i == 0 ? Real(0) : mass});
  pbd::World world = pbd::buildWorld(scene);
  for (int i = 0; i < count; ++i) {
    pbd::ParticleDistanceConstraint c;
    c.particle1 = i;
    c.particle2 = i + 1;
    c.restLength = spacing;
    c.xpbd = xpbd;
    c.stiffness = xpbd ? stiffness : Real(1);
    world.constraints.particleDistances.push_back(c);
  }
  const Real decay = std::exp(-Real(20) * scene.simulation.timeStepSize);
  while (world.time < 3) {
    world.step();
    for (Vector3& v : world.bodies.particles.velocity)
      v *= decay;
  }
  const Real length = Real(count) * spacing;
  const Real stretch = -world.bodies.particles.position.back().y() - length;
  if (!xpbd) return std::abs(stretch) / length;
  const Real expected =
      mass * -scene.simulation.gravitation.y() / stiffness * count * (count + 1) / 2;
  return std::abs(stretch - expected) / expected;
}

Real beamError(int solidMethod, int substeps, int iterations, Real linear) {
  namespace beam = pbd::test::beam;
  const beam::Deflection d = beam::staticTipDeflection(
      beam::beamScene(2, substeps, iterations, solidMethod), 64, Real(1e-5), 2000);
  return std::abs(d.tip - linear) / linear;
}

/// The machine the study ran on: host name and CPU model (from /proc/cpuinfo where it exists).
std::string machineDescription() {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) host[0] = 0;
  std::string cpu;
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; cpu.empty() && std::getline(info, line);)
    if (line.rfind("model name", 0) == 0) cpu = line.substr(line.find(':') + 2);
  return std::string(host) + (cpu.empty() ? "" : ", " + cpu) + ", " +
         std::to_string(std::thread::hardware_concurrency()) + " threads";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

struct Study {
  std::string name, method, error;
  std::function<Real(int, int)> measure;
};

}  // namespace

int main(int argc, char** argv) {
  std::string jsonPath;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--json" && a + 1 < argc) {
      jsonPath = argv[++a];
    } else {
      std::fprintf(stderr, "usage: pbdval_particle_convergence [--json PATH]\n");
      return 2;
    }
  }
  try {
    if (!jsonPath.empty()) pbdval::checkOutputFile(jsonPath);
    const Real linear =
        pbd::test::beam::linearFemTipDeflection(pbd::test::beam::beamScene(2, 1, 1));
    const std::vector<Study> studies = {
        {"oscillator", "XPBD distance", "max |x − A cos ωt| / A over 2 s",
         [](int s, int i) { return oscillatorError(s, i); }},
        {"chain", "XPBD distance", "|total stretch − closed form| / closed form",
         [](int s, int i) { return chainError(true, s, i); }},
        {"chain", "PBD distance, k = 1", "total stretch / length (0 for rigid links)",
         [](int s, int i) { return chainError(false, s, i); }},
        {"beam", "XPBD FEM tets", "|tip − linear FEM tip| / linear FEM tip",
         [linear](int s, int i) { return beamError(3, s, i, linear); }},
        {"beam", "PBD FEM tets", "|tip − linear FEM tip| / linear FEM tip",
         [linear](int s, int i) { return beamError(2, s, i, linear); }},
    };
    const std::vector<int> counts = {1, 2, 4, 8, 16};
    nlohmann::json out;
    out["metadata"] = {{"program", "pbdval_particle_convergence"},
                       {"date", utcNow()},
                       {"machine", machineDescription()},
                       {"pbdval_version", PBDVAL_VERSION},
                       {"commit", std::string(PBDVAL_GIT_COMMIT) + " (" + PBDVAL_GIT_DIRTY + ")"},
                       {"build_type", PBDVAL_BUILD_TYPE},
                       {"compiler", PBDVAL_CXX_COMPILER},
                       {"flags", PBDVAL_CXX_FLAGS},
                       {"precision", sizeof(Real) == 8 ? "double" : "float"},
                       {"substeps", counts},
                       {"iterations", counts}};
    for (const Study& study : studies) {
      std::fprintf(stderr, "%s / %s ...\n", study.name.c_str(), study.method.c_str());
      std::vector<std::vector<double>> grid;
      for (int s : counts) {
        grid.emplace_back();
        for (int i : counts)
          grid.back().push_back(double(study.measure(s, i)));
      }
      // Equal cost N = substeps × iterations: all substeps against all iterations.
      std::printf("\n**%s, %s** (error: %s)\n\n| substeps \\ iterations |", study.name.c_str(),
                  study.method.c_str(), study.error.c_str());
      for (int i : counts)
        std::printf(" %d |", i);
      std::printf("\n|---|");
      for (std::size_t k = 0; k < counts.size(); ++k)
        std::printf("---|");
      std::printf("\n");
      for (std::size_t r = 0; r < counts.size(); ++r) {
        std::printf("| %d |", counts[r]);
        for (double e : grid[r])
          std::printf(" %.2e |", e);
        std::printf("\n");
      }
      nlohmann::json equalCost = nlohmann::json::array();
      for (std::size_t k = 1; k < counts.size(); ++k)
        equalCost.push_back(
            {{"cost", counts[k]}, {"substeps_only", grid[k][0]}, {"iterations_only", grid[0][k]}});
      out["studies"].push_back({{"case", study.name},
                                {"method", study.method},
                                {"error", study.error},
                                {"errors", grid},
                                {"equal_cost", equalCost}});
    }
    if (!jsonPath.empty()) pbdval::writeFileAtomically(jsonPath, out.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pbdval_particle_convergence: %s\n", e.what());
    return 1;
  }
  return 0;
}
