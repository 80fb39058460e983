// The targets that drive what a run does with its inputs, beyond the readers (issue 25):
//   measure      what pbdval.measure does (validation/measure/measure_trajectory.h) with
//                a trajectory built from the bytes: NaN/Inf/huge positions, quaternions of
//                any norm, empty trajectories, NaN or decreasing times, NaN margins; scenes
//                with collision shapes, joints and an analytic reference;
//   simulate     a small scene whose numbers are overwritten from the bytes, loaded and run for
//                a few steps in a built-in engine the first byte chooses (pbd, pbd.xpbd,
//                bullet, ode, mujoco: runSimulation, as `pbdval simulate`);
//   merge_shard  the bytes as a shard's results.json in a shard folder that also holds
//                symbolic links and files outside it: mergeShards and verifiedShardFiles, as
//                `pbdval merge` calls them, then the verified files copied.
// Each accepts a result or the documented error; anything else is a finding.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "adapters/built_in_engines.h"
#include "fuzz_support.h"
#include "fuzz_targets.h"
#include "pbd/io/scene_loader.h"
#include "validation/io/results.h"
#include "validation/measure/measure_trajectory.h"
#include "validation/run/case_spec.h"
#include "validation/run/shard_files.h"
#include "validation/run/sharding.h"
#include "validation/run/simulation.h"

namespace pbdval::fuzz {
namespace {

namespace fs = std::filesystem;

/// Reads the fuzz bytes front to back; past the end, zeros.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return next_ >= size_; }
  std::uint8_t byte() { return next_ < size_ ? data_[next_++] : 0; }
  double raw() { return bitsAs<double>(); }
  std::int64_t integer() { return bitsAs<std::int64_t>(); }  ///< any 64-bit integer
  /// A number that breaks things more often than a uniform one: the specials a probe tries
  /// (±0, denormals, 1e±300, the largest double, NaN, ±Inf, ...), a small integer, or any
  /// 8 bytes.
  double number() {
    static const double specials[] = {0.0,
                                      -0.0,
                                      1.0,
                                      -1.0,
                                      0.5,
                                      1e-300,
                                      1e300,
                                      -1e300,
                                      1e308,
                                      std::numeric_limits<double>::max(),
                                      -std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::denorm_min(),
                                      std::numeric_limits<double>::min(),
                                      std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(),
                                      1e6,
                                      1e7,
                                      -1e7,
                                      1e-7,
                                      1e-9,
                                      2.0,
                                      10.0,
                                      1e12};
    const std::uint8_t selector = byte();
    constexpr std::size_t count = sizeof specials / sizeof specials[0];
    if (selector < count) return specials[selector];
    if (selector < 200) return double(int(selector) - 150);  // -126 ... 49
    return raw();
  }
  /// `base` most of the time (and then nudged by a little), else number().
  double near(double base) {
    const std::uint8_t b = byte();
    if (b < 160) return base + (double(b) - 80.0) * 1e-3;
    return number();
  }

 private:
  template <typename T>
  T bitsAs() {
    std::uint8_t bits[sizeof(T)] = {};
    for (std::uint8_t& b : bits)
      b = byte();
    T value;
    std::memcpy(&value, bits, sizeof value);
    return value;
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t next_ = 0;
};

void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s: %s\n", what, detail.c_str());
  std::abort();
}

// ---- measure ---------------------------------------------------------------------------------

// Scenes with collision shapes (the FCL oracle measures their overlaps), a joint and a spring,
// and an analytic reference (bouncing_ball, projectile) that integrates up to the sample times.
// No mesh files: the shapes are analytic.
const char* const kMeasureScenes[] = {
    R"({"Name": "drop", "Simulation": {"timeStepSize": 0.001, "subSteps": 5, "gravitation": [0, -9.81, 0]},
 "RigidBodies": [
  {"id": 0, "isDynamic": false, "translation": [0, -0.5, 0], "collisionObjectType": 2,
   "collisionObjectScale": [4, 1, 4], "restitution": 0.8, "friction": 0.1},
  {"id": 1, "density": 1000, "translation": [0, 1.1, 0], "collisionObjectType": 1,
   "collisionObjectScale": [0.1, 0.1, 0.1], "restitution": 1.0, "friction": 0.1}],
 "Validation": {"description": "d", "duration": 1.5, "sampleInterval": 0.001, "schema": 1,
  "reference": {"type": "analytic", "model": "bouncing_ball", "bodies": [1]}}})",
    R"({"Name": "hinged", "Simulation": {"timeStepSize": 0.005, "subSteps": 5, "gravitation": [0, -9.81, 0]},
 "RigidBodies": [
  {"id": 0, "isDynamic": false, "translation": [0, -0.5, 0], "collisionObjectType": 2,
   "collisionObjectScale": [4, 1, 4]},
  {"id": 1, "density": 500, "translation": [0, 0.11, 0], "collisionObjectType": 2,
   "collisionObjectScale": [0.3, 0.2, 0.3], "velocity": [3, 8, 1], "angularVelocity": [0, 2, 1]},
  {"id": 2, "density": 500, "translation": [0, 0.4, 0], "collisionObjectType": 1,
   "collisionObjectScale": [0.1, 0.1, 0.1]}],
 "HingeJoints": [{"bodyID1": 1, "bodyID2": 2, "position": [0, 0.3, 0], "axis": [0, 0, 1]}],
 "RigidBodySprings": [{"bodyID1": 0, "bodyID2": 1, "position1": [0, 1, 0], "position2": [0, 0.2, 0],
  "stiffness": 200}],
 "Validation": {"description": "h", "duration": 1, "schema": 1, "conserved": ["energy"],
  "reference": {"type": "analytic", "model": "projectile", "bodies": [1],
   "parameters": {"form": "continuous"}}}})",
};

struct MeasureCase {
  pbd::Scene scene;
  CaseSpec spec;
};

const std::vector<MeasureCase>& measureCases() {
  static const std::vector<MeasureCase> cases = [] {
    static const EngineRegistry engines = builtInEngines();
    std::vector<MeasureCase> all;
    for (const char* text : kMeasureScenes) {
      MeasureCase c;
      c.scene = pbd::parseScene(text, kSceneName).scene;
      c.spec = parseCaseSpec(c.scene, engines);
      all.push_back(std::move(c));
    }
    return all;
  }();
  return cases;
}

/// Up to 8 samples of `scene`'s bodies: each value its initial one (slightly moved) or any
/// number; times k·h, or any number.
std::vector<State> fuzzedSamples(const pbd::Scene& scene, Bytes& in) {
  const std::size_t count = in.byte() % 9;
  std::vector<State> samples(count);
  const double h = double(scene.simulation.timeStepSize);
  for (std::size_t k = 0; k < count; ++k) {
    State& s = samples[k];
    s.time = in.near(double(k) * h);
    for (const pbd::RigidBodyDesc& body : scene.rigidBodies) {
      BodyState b;
      b.id = body.id;
      for (int i = 0; i < 3; ++i) {
        b.position[i] = pbd::Real(in.near(double(body.translation[i])));
        b.velocity[i] = pbd::Real(in.near(0));
        b.angularVelocity[i] = pbd::Real(in.near(0));
      }
      // Any norm: zero, tiny, huge, NaN (the binding passes the four numbers as given).
      b.rotation = Quaternion(pbd::Real(in.near(1)), pbd::Real(in.near(0)), pbd::Real(in.near(0)),
                              pbd::Real(in.near(0)));
      s.bodies.push_back(b);
    }
  }
  // Now and then a sample that does not hold the scene's bodies (the binding checks shapes, not
  // ids): a wrong id or a body missing.
  if (count > 0 && in.byte() == 0xA5) {
    State& s = samples[in.byte() % count];
    if (in.byte() & 1)
      s.bodies.pop_back();
    else
      s.bodies.front().id += 7;
  }
  return samples;
}

}  // namespace

void measureTarget(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  const std::vector<MeasureCase>& cases = measureCases();
  const MeasureCase& c = cases[in.byte() % cases.size()];
  const ReferenceChoice choice = static_cast<ReferenceChoice>(in.byte() % 3);
  const double margin = in.byte() & 1 ? in.number() : 0.0;
  const double integrationStep = in.byte() & 1 ? in.number() : 0.0;
  const std::vector<State> samples = fuzzedSamples(c.scene, in);
  ReferenceTrajectory given;
  given.description = "fuzzed reference";
  if (choice == ReferenceChoice::Given) {
    given.samples = fuzzedSamples(c.scene, in);
    given.hasRotation = in.byte() & 1;
  }
  try {
    MetricSeries series;
    const MeasuredTrajectory measured = measureTrajectory(c.scene, c.spec, samples, choice, &given,
                                                          margin, integrationStep, &series);
    // Measured means the samples were finite (measureSamples names any that is not): a metric
    // may be NaN only where docs/metrics.md says it can be (e.g. a series' missing sample), so
    // only the messages are checked here.
    for (const std::string& note : measured.metrics.notes)
      expectPrintable(note.c_str());
  } catch (const EngineDivergence& e) {  // a non-finite or blown-up sample: pbdval.DivergenceError
    expectPrintable(e.what());
  } catch (const std::invalid_argument& e) {  // a bad argument: pbdval.ArgumentError
    expectPrintable(e.what());
  }
}

// ---- simulate --------------------------------------------------------------------------------

namespace {

// A small scene with something for every engine feature the numbers reach: a static ground box,
// a sphere (density) and a box (mass) in contact range, a hinge and a spring.
const char* const kSimulateScene = R"({"Name": "fuzz_simulate",
 "Simulation": {"timeStepSize": 0.005, "subSteps": 2, "maxIterations": 1, "maxIterationsV": 2,
  "gravitation": [0, -9.81, 0]},
 "RigidBodies": [
  {"id": 0, "isDynamic": false, "translation": [0, -0.5, 0], "collisionObjectType": 2,
   "collisionObjectScale": [4, 1, 4], "restitution": 0.5, "friction": 0.3},
  {"id": 1, "density": 1000, "translation": [0, 0.1, 0], "velocity": [0, -1, 0],
   "angularVelocity": [0, 0, 1], "collisionObjectType": 1, "collisionObjectScale": [0.1, 0.1, 0.1],
   "restitution": 0.5, "friction": 0.3},
  {"id": 2, "mass": 2, "translation": [0.4, 0.3, 0], "velocity": [0, 0, 0],
   "angularVelocity": [0, 5, 0.1], "collisionObjectType": 2, "collisionObjectScale": [0.1, 0.2, 0.3]}],
 "HingeJoints": [{"bodyID1": 1, "bodyID2": 2, "position": [0.2, 0.2, 0], "axis": [0, 0, 1]}],
 "RigidBodySprings": [{"bodyID1": 0, "bodyID2": 2, "position1": [0.4, 1, 0],
  "position2": [0.4, 0.4, 0], "stiffness": 200}]})";

/// The numbers the bytes may overwrite (JSON pointers into kSimulateScene).
const char* const kSimulateFields[] = {
    "/Simulation/timeStepSize",
    "/Simulation/subSteps",
    "/Simulation/maxIterations",
    "/Simulation/maxIterationsV",
    "/Simulation/gravitation/1",
    "/RigidBodies/0/translation/1",
    "/RigidBodies/0/collisionObjectScale/0",
    "/RigidBodies/1/density",
    "/RigidBodies/1/translation/0",
    "/RigidBodies/1/translation/1",
    "/RigidBodies/1/velocity/1",
    "/RigidBodies/1/angularVelocity/2",
    "/RigidBodies/1/collisionObjectScale/0",
    "/RigidBodies/1/restitution",
    "/RigidBodies/1/friction",
    "/RigidBodies/2/mass",
    "/RigidBodies/2/translation/0",
    "/RigidBodies/2/translation/1",
    "/RigidBodies/2/velocity/0",
    "/RigidBodies/2/angularVelocity/0",
    "/RigidBodies/2/angularVelocity/1",
    "/RigidBodies/2/collisionObjectScale/2",
    "/HingeJoints/0/position/0",
    "/HingeJoints/0/axis/2",
    "/HingeJoints/0/axis/0",
    "/RigidBodySprings/0/stiffness",
    "/RigidBodySprings/0/position2/1",
};

/// Steps per run: enough for contacts, joints and the spring to act on the fuzzed values.
constexpr int kSimulateSteps = 3;
/// The work bound per input (so that executions stay above ~10/s): constraint passes per step,
/// subSteps × (maxIterations + maxIterationsV). A scene beyond it is loaded but not stepped.
/// The loader admits 10^4 × 2·10^4; the cases use ≤ 5 × 6.
constexpr double kMaxPassesPerStep = 400;

}  // namespace

void simulateTarget(const std::uint8_t* data, std::size_t size) {
  static const nlohmann::json seed = nlohmann::json::parse(kSimulateScene);
  static const EngineRegistry engines = builtInEngines();
  Bytes in(data, size);
  // The engine: one per input, chosen by the first byte, so that the fuzzer's coverage guidance
  // explores each (every engine once per input: 151 executions in 23 s under the sanitizers,
  // below the 10/s a fuzzer needs).
  const std::string methods[] = {engines.defaultMethod("pbd"), "pbd.xpbd",
                                 engines.defaultMethod("bullet"), engines.defaultMethod("ode"),
                                 engines.defaultMethod("mujoco")};
  const std::string& methodName = methods[in.byte() % 5];
  nlohmann::json scene = seed;
  const std::size_t edits = in.byte() % 8;
  for (std::size_t e = 0; e < edits && !in.empty(); ++e) {
    const char* field =
        kSimulateFields[in.byte() % (sizeof kSimulateFields / sizeof kSimulateFields[0])];
    const std::uint8_t kind = in.byte();
    nlohmann::json& value = scene[nlohmann::json::json_pointer(field)];
    if (kind < 32)
      value = in.integer();
    else
      value = in.number();  // NaN and ±Inf are written as null: a type error the loader names
  }
  pbd::LoadedScene loaded;
  try {
    loaded = pbd::parseScene(scene.dump(), kSceneName);
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
    return;
  }
  const pbd::SimulationSettings& parameters = loaded.scene.simulation;
  if (double(parameters.subSteps) * double(parameters.maxIterations + parameters.maxIterationsV) >
      kMaxPassesPerStep)
    return;
  {
    const MethodInfo& info = engines.method(methodName);
    const std::unique_ptr<Engine> engine = engines.make(info.engine);
    const RunLength length{kSimulateSteps * double(parameters.timeStepSize), 0};
    RunOutcome outcome;
    std::vector<State> samples;
    RunCallbacks callbacks;
    callbacks.onSample = [&samples](const State& s) { samples.push_back(s); };
    try {
      outcome =
          runSimulation(*engine, loaded.scene, engines.resolve(methodName), length, callbacks);
    } catch (const std::invalid_argument& e) {  // the run cannot be planned (planSteps)
      expectPrintable(e.what());
      return;
    }
    expectPrintable(outcome.reason.c_str());
    if (outcome.status != RunStatus::Ok && outcome.status != RunStatus::Suspect) return;
    // An ok run holds finite states with unit quaternions: "ok" with a zero or NaN quaternion
    // was a finding of issue 25. 1e-3: every engine renormalises its orientations each step
    // (round-off ~1e-15); a broken one is off by order 1.
    for (const State& s : samples) {
      if (const std::string reason = divergenceReason(s); !reason.empty())
        fail("simulate", methodName + ": status ok with " + reason);
      for (const BodyState& b : s.bodies)
        if (!(std::abs(double(b.rotation.norm()) - 1.0) < 1e-3))
          fail("simulate", methodName + ": status ok with a quaternion of norm " +
                               std::to_string(double(b.rotation.norm())) +
                               " at t = " + std::to_string(s.time));
    }
  }
}

// ---- merge_shard -----------------------------------------------------------------------------

namespace {

/// A folder with a shard and what a tampered results.json may point at, made once per
/// process and removed at exit (the seeds are the results of `pbdval run cases/projectile.json
/// --engines pbd,ode,bullet,mujoco --shard 1/1`, whose trajectories these names are):
///   shard/trajectories/projectile/{pbd-pbd.csv, pbd-pbd.particles.csv, pbd-pbd.xpbd.csv}
///   shard/trajectories/projectile/ode-ode.quickstep.csv → ../../../outside/secret.csv
///   shard/trajectories/projectile/bullet-bullet.si.csv/         a folder
///   shard/trajectories/projectile/mujoco-mujoco.euler.csv       missing
///   shard/trajectories/linked → ../../outside/trajectories/projectile   (a folder link)
///   outside/secret.csv, outside/trajectories/projectile/mujoco-mujoco.euler.csv
class MergeFixture {
 public:
  MergeFixture() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/pbdval-fuzz-merge-XXXXXX";
    if (!::mkdtemp(pattern.data())) fail("merge_shard", "cannot create " + pattern);
    base = pattern;
    shard = base + "/shard";
    const std::string cases = shard + "/trajectories/projectile";
    fs::create_directories(cases + "/bullet-bullet.si.csv");
    fs::create_directories(base + "/outside/trajectories/projectile");
    write(cases + "/pbd-pbd.csv", "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");
    write(cases + "/pbd-pbd.particles.csv", "t,index,x,y,z,vx,vy,vz\n");
    write(cases + "/pbd-pbd.xpbd.csv", "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");
    write(base + "/outside/secret.csv", "secret\n");
    write(base + "/outside/trajectories/projectile/mujoco-mujoco.euler.csv", "secret\n");
    fs::create_symlink("../../../outside/secret.csv", cases + "/ode-ode.quickstep.csv");
    fs::create_symlink("../../outside/trajectories/projectile", shard + "/trajectories/linked");
    canonicalShard = fs::canonical(shard).string() + "/";
  }
  ~MergeFixture() {
    std::error_code ignored;
    fs::remove_all(base, ignored);
  }
  static void write(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
  }
  std::string base, shard, canonicalShard;
};

/// Every component of `path` below the shard folder is a real folder or, last, a regular file.
bool insideWithoutLinks(const std::string& shard, const std::string& path) {
  if (path.compare(0, shard.size() + 1, shard + "/") != 0) return false;
  std::string walked = shard;
  for (const fs::path& part : fs::path(path.substr(shard.size() + 1))) {
    if (part == ".." || part == ".") return false;
    walked += "/" + part.string();
    struct stat info {};
    if (::lstat(walked.c_str(), &info) != 0 || S_ISLNK(info.st_mode)) return false;
  }
  struct stat info {};
  return ::lstat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

void mergeShardTarget(const std::uint8_t* data, std::size_t size) {
  static const MergeFixture fixture;
  ShardResults shard;
  shard.folder = fixture.shard;
  try {
    shard.results = parseResultsText(text(data, size), fixture.shard + "/results.json");
  } catch (const std::invalid_argument& e) {
    expectPrintable(e.what());
    return;
  }
  // `pbdval merge` merges, then verifies every shard's files, then carries them: each step on
  // its own here, so that a shard the merge refuses still has its paths fuzzed.
  try {
    (void)mergeShards({shard}, "pbdval merge fuzz");
  } catch (const std::invalid_argument& e) {
    expectPrintable(e.what());
  }
  std::vector<ShardFile> files;
  try {
    files = verifiedShardFiles(shard);
  } catch (const std::invalid_argument& e) {
    expectPrintable(e.what());
    return;
  }
  for (const ShardFile& file : files) {
    if (!insideWithoutLinks(fixture.shard, file.path) ||
        fs::canonical(file.path).string().compare(0, fixture.canonicalShard.size(),
                                                  fixture.canonicalShard) != 0)
      fail("merge_shard", "verified a file outside the shard or behind a link: " + file.path);
    bool leaves = file.relative.empty() || file.relative.front() == '/';
    for (const fs::path& part : fs::path(file.relative))
      leaves = leaves || part == ".." || part == ".";
    if (leaves)
      fail("merge_shard", "a merged path that leaves the merged folder: " + file.relative);
  }
  const std::string out = fixture.base + "/merged";
  carryShardFiles(files, out, /*move=*/false);
  std::error_code ignored;
  fs::remove_all(out, ignored);
}

}  // namespace pbdval::fuzz
