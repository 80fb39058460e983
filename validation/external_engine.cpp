#include "validation/external_engine.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "pbd/io/number_text.h"
#include "validation/atomic_file.h"
#include "validation/interrupts.h"
#include "validation/json_text.h"
#include "validation/resolved_scene.h"
#include "validation/simulation.h"
#include "validation/trajectory.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr const char* kStatusFile = "status.json";
constexpr const char* kTrajectoryFile = "trajectory.csv";
constexpr const char* kTrajectoryNpyFile = "trajectory.npy";  // the binary alternative
constexpr const char* kParticlesFile = "particles.csv";          // particle states, when any
constexpr const char* kParticlesNpyFile = "particles.npy";
constexpr const char* kStderrFile = "stderr.txt";

constexpr const char* kGroupFile = "engine.pgid";  // the engine's process group, for the runner

/// The prefix of the scratch folders of the runs of process `owner`: the scheduler removes what
/// a run it had to kill could not (removeEngineLeftovers).
std::string scratchPrefix(pid_t owner) {
  return "pbdval-engine-" + std::to_string(static_cast<long>(owner)) + "-";
}

/// A scratch folder for one run, removed with everything in it when the run is over.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::string pattern =
        (fs::temp_directory_path() / (scratchPrefix(::getpid()) + "XXXXXX")).string();
    if (!::mkdtemp(pattern.data()))
      throw EngineError(std::string("cannot create a scratch folder: ") + std::strerror(errno));
    path_ = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// The first line of `text` that names an error the way runtimes print one: an identifier
/// ending in Error or Exception followed by ':' ("TypeError: x is not a function" under a
/// Node.js stack, "ValueError: ..." in Python), or "error:"/"terminate called"; empty if none.
std::string firstErrorLine(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos) continue;
    const std::string trimmed = line.substr(start);
    const std::size_t colon = trimmed.find(':');
    const std::string head = colon == std::string::npos ? "" : trimmed.substr(0, colon);
    const bool named =
        !head.empty() && head.find(' ') == std::string::npos &&
        ((head.size() >= 5 && head.compare(head.size() - 5, 5, "Error") == 0) ||
         (head.size() >= 9 && head.compare(head.size() - 9, 9, "Exception") == 0));
    if (named || trimmed.rfind("error:", 0) == 0 || trimmed.rfind("terminate called", 0) == 0)
      return trimmed.size() > 300 ? trimmed.substr(0, 297) + "..." : trimmed;
  }
  return "";
}

/// The engine's standard error for reasons: the first line that names an error (a message a
/// stack trace would push out of the tail) and the last 400 bytes.
std::string stderrTail(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  if (s.empty()) return "";
  const std::string first = firstErrorLine(s);
  const bool cut = s.size() > 400;
  if (cut) s = "..." + s.substr(s.size() - 400);
  const bool firstShown = first.empty() || s.find(first) != std::string::npos;
  return (firstShown ? "" : "; its standard error says: " + first) +
         "; its standard error ends: " + s;
}

struct Exit {
  bool timedOut = false;
  int interruptedBy = 0;  ///< SIGINT, SIGTERM or SIGHUP taken while it ran (it was stopped)
  int status = 0;         ///< waitpid status
};

/// Runs argv in `folder` with stdout to /dev/null and stderr to `stderrPath`, in a process group
/// of its own whose id is written to `groupFile`; kills it after `limit` seconds (0: none) or
/// when SIGINT, SIGTERM or SIGHUP arrives. Whatever way it ends, its whole process group is
/// killed before it is reaped: a process the engine started and left running (a server, a
/// daemonised helper) ends with it. The engine also dies with the process that started it
/// (PR_SET_PDEATHSIG), should that one be killed outright.
Exit runProcess(const ExternalCommand& command, const std::vector<std::string>& extraArguments,
                const fs::path& stderrPath, const fs::path& groupFile, double limit) {
  std::vector<std::string> arguments = command.argv;
  arguments.insert(arguments.end(), extraArguments.begin(), extraArguments.end());
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  // Composed before the fork: the package folder first, then whatever PYTHONPATH was.
  std::string pythonPath = command.pythonPackageFolder;
  const char* inherited = std::getenv("PYTHONPATH");
  if (!pythonPath.empty() && inherited && *inherited) pythonPath += std::string(":") + inherited;
  const InterruptWatch interrupts;
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw EngineError(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the runner died before prctl
    interrupts.unblockInChild();
    const int err = ::open(stderrPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_RDWR);
    if (err >= 0) ::dup2(err, STDERR_FILENO);
    if (null >= 0) {
      ::dup2(null, STDIN_FILENO);
      ::dup2(null, STDOUT_FILENO);
    }
    ::setenv("PBDVAL_PROTOCOL", "1", 1);
    if (!pythonPath.empty()) ::setenv("PYTHONPATH", pythonPath.c_str(), 1);
    if (!command.workingFolder.empty() && ::chdir(command.workingFolder.c_str()) != 0) {
      std::fprintf(stderr, "pbdval: cannot enter %s: %s\n", command.workingFolder.c_str(),
                   std::strerror(errno));
      ::_exit(127);
    }
    ::execvp(argv[0], argv.data());
    std::fprintf(stderr, "pbdval: cannot start %s: %s\n", argv[0], std::strerror(errno));
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: whichever of the two runs first
  {
    std::ofstream group(groupFile);
    group << pid << "\n";
  }
  const Clock::time_point start = Clock::now();
  Exit exit;
  // Waits for the engine to end without reaping it: while it is a zombie its process group id
  // cannot be reused, so killing the group afterwards reaches only what it left behind.
  const auto ended = [pid]() {
    siginfo_t info{};
    const int result = ::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT);
    // ECHILD: reaped already (a host process that ignores SIGCHLD reaps automatically).
    return (result == 0 && info.si_pid == pid) || (result != 0 && errno == ECHILD);
  };
  for (;;) {
    if (ended()) break;
    if (limit > 0 && std::chrono::duration<double>(Clock::now() - start).count() > limit) {
      exit.timedOut = true;
      break;
    }
    if (const int signal = interrupts.wait(0.002)) {
      exit.interruptedBy = signal;
      break;
    }
  }
  ::kill(-pid, SIGKILL);
  ::waitpid(pid, &exit.status, 0);
  return exit;
}

RunStatus statusNamed(const std::string& name) {
  for (RunStatus s : {RunStatus::Ok, RunStatus::Unsupported, RunStatus::Diverged, RunStatus::Error})
    if (name == runStatusName(s)) return s;
  throw std::invalid_argument("status: expected one of ok, unsupported, diverged, error, got \"" +
                              name + "\"");
}

/// Reads status.json into `run`; throws std::invalid_argument naming the field.
void readStatus(const fs::path& file, WholeRun& run) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const Json j = Json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw std::invalid_argument("not a JSON object");
  const auto field = [&](const char* key) -> const Json& {
    if (!j.contains(key)) throw std::invalid_argument(std::string(key) + ": missing");
    return j.at(key);
  };
  if (field("protocol") != kExternalProtocolVersion)
    throw std::invalid_argument("protocol: expected 1, got " + field("protocol").dump());
  if (!field("status").is_string()) throw std::invalid_argument("status: expected a string");
  run.status = statusNamed(field("status").get<std::string>());
  if (j.contains("reason") && j.at("reason").is_string()) run.reason = j.at("reason").get<std::string>();
  if (run.status == RunStatus::Unsupported && j.contains("unsupported") && j.at("unsupported").is_array()) {
    std::string features;
    for (const Json& f : j.at("unsupported"))
      if (f.is_string()) features += (features.empty() ? "" : "; ") + f.get<std::string>();
    if (!features.empty()) run.reason = features;
  }
  if (run.status != RunStatus::Ok && run.reason.empty())
    throw std::invalid_argument("reason: a non-ok status needs a reason");
  if (j.contains("engineVersion") && j.at("engineVersion").is_string())
    run.facts.engineVersion = j.at("engineVersion").get<std::string>();
  if (j.contains("integratorStepsPerSceneStep")) {
    const Json& n = j.at("integratorStepsPerSceneStep");
    if (!n.is_number_integer() || n.get<std::int64_t>() < 1)
      throw std::invalid_argument("integratorStepsPerSceneStep: expected an integer >= 1");
    run.facts.integratorStepsPerSceneStep = n.get<int>();
  }
  if (j.contains("initialVelocitiesProjected")) {
    const Json& p = j.at("initialVelocitiesProjected");
    if (!p.is_boolean())
      throw std::invalid_argument("initialVelocitiesProjected: expected true or false");
    run.facts.initialVelocitiesProjected = p.get<bool>();
  }
  if (j.contains("contactMargin") && !j.at("contactMargin").is_null()) {
    const Json& m = j.at("contactMargin");
    if (!m.is_number() || !std::isfinite(m.get<double>()))
      throw std::invalid_argument("contactMargin: expected a number of metres or null");
    run.facts.contactMargin = m.get<double>();
  }
  if (j.contains("effectiveSettings") && j.at("effectiveSettings").is_object())
    for (const auto& item : j.at("effectiveSettings").items())
      run.settings[item.key()] = item.value().is_string() ? item.value().get<std::string>()
                                                          : jsonText(item.value(), -1);
}

/// Checks the samples against what the run asked for: every sample holds every body of the
/// scene in order, at the planned times (t = 0, every stride, the end); a diverged run may end
/// early. Returns a reason, or empty.
std::string checkSamples(const std::vector<State>& samples, const pbd::Scene& scene,
                         const StepPlan& plan, RunStatus status) {
  const double h = double(scene.simulation.timeStepSize);
  std::vector<long> steps;
  for (long n = 0; n <= plan.steps; ++n)
    if (n == 0 || n % plan.stride == 0 || n == plan.steps) steps.push_back(n);
  if (samples.empty()) return "the trajectory has no rows";
  if (status == RunStatus::Ok && samples.size() != steps.size())
    return "the trajectory has " + std::to_string(samples.size()) + " samples, expected " +
           std::to_string(steps.size()) + " (t = 0, every " + std::to_string(plan.stride) +
           " steps, and the end)";
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const State& s = samples[k];
    if (s.bodies.size() != scene.rigidBodies.size())
      return "sample " + std::to_string(k) + " (t = " + pbd::formatReal(s.time) + ") has " +
             std::to_string(s.bodies.size()) + " bodies, expected " +
             std::to_string(scene.rigidBodies.size());
    for (std::size_t i = 0; i < s.bodies.size(); ++i)
      if (s.bodies[i].id != scene.rigidBodies[i].id)
        return "sample " + std::to_string(k) + " row " + std::to_string(i) + " is body " +
               std::to_string(s.bodies[i].id) + ", expected body " +
               std::to_string(scene.rigidBodies[i].id) + " (bodies in scene order)";
    const bool lastOfDiverged = status == RunStatus::Diverged && k + 1 == samples.size();
    if (!lastOfDiverged) {
      if (k >= steps.size()) return "the trajectory has more samples than the run has steps";
      const double expected = double(steps[k]) * h;
      if (std::abs(s.time - expected) > 1e-9 * std::max(1.0, expected))
        return "sample " + std::to_string(k) + " is at t = " + pbd::formatReal(s.time) +
               " s, expected " + pbd::formatReal(expected) + " s";
    }
  }
  return "";
}

/// Moves the particles of `particles` into `samples` (the body trajectory's, already checked):
/// the same number of samples at the same times, each with every particle of the scene.
std::string mergeParticles(std::vector<State>& particles, const pbd::Scene& scene,
                           std::vector<State>& samples) {
  if (particles.size() != samples.size())
    return "it has " + std::to_string(particles.size()) + " samples, the trajectory " +
           std::to_string(samples.size()) + " (the same samples are expected)";
  for (std::size_t k = 0; k < samples.size(); ++k) {
    if (particles[k].time != samples[k].time)
      return "sample " + std::to_string(k) + " is at t = " + pbd::formatReal(particles[k].time) +
             " s, the trajectory's at t = " + pbd::formatReal(samples[k].time) + " s";
    if (particles[k].particles.size() != scene.particles.size())
      return "sample " + std::to_string(k) + " (t = " + pbd::formatReal(particles[k].time) +
             ") has " + std::to_string(particles[k].particles.size()) + " particles, expected " +
             std::to_string(scene.particles.size());
    samples[k].particles = std::move(particles[k].particles);
  }
  return "";
}

}  // namespace

ExternalEngine::ExternalEngine(std::string name, ExternalCommand command, FeatureTable features)
    : name_(std::move(name)), command_(std::move(command)), features_(std::move(features)) {}

std::vector<std::string> ExternalEngine::unsupported(const pbd::Scene& scene,
                                                     const Method& method) const {
  if (features_.entries.empty()) return {};
  return unsupportedFeatures(features_, scene, method.name);
}

void ExternalEngine::load(const pbd::Scene&, const Method& method) {
  throw EngineError("external engine " + name_ + " (method " + method.name +
                    ") runs whole runs in its own process; it cannot be stepped");
}
void ExternalEngine::step() { throw EngineError("external engine " + name_ + ": cannot be stepped"); }
void ExternalEngine::read(State&) const {
  throw EngineError("external engine " + name_ + ": cannot be stepped");
}

WholeRun ExternalEngine::runWhole(const pbd::Scene& scene, const Method& method,
                                  const RunLength& length, double wallTimeLimit) {
  WholeRun run;
  const auto fail = [&](const std::string& reason) {
    run.status = RunStatus::Error;
    run.reason = "external engine " + name_ + ": " + reason;
    run.samples.clear();
    return run;
  };
  const StepPlan plan = planSteps(length, double(scene.simulation.timeStepSize));
  const ScratchFolder scratch;
  const Json parameters = methodParametersJson(method);
  const fs::path scenePath = scratch.path() / "resolved-scene.json";
  const fs::path outFolder = scratch.path() / "out";
  fs::create_directory(outFolder);
  writeFileAtomically(scenePath.string(),
                      jsonText(resolvedSceneJson(scene, method.name, parameters, length)) + "\n");

  const Exit exit =
      runProcess(command_, {"--scene", scenePath.string(), "--out", outFolder.string()},
                 scratch.path() / kStderrFile, scratch.path() / kGroupFile, wallTimeLimit);
  if (exit.interruptedBy != 0) throw SignalInterrupt(exit.interruptedBy);  // scratch removed
  const std::string errors = stderrTail(scratch.path() / kStderrFile);
  if (exit.timedOut) {
    run.status = RunStatus::Timeout;
    run.reason = "external engine " + name_ + " exceeded the wall-time limit of " +
                 pbd::formatReal(wallTimeLimit) + " s and was stopped";
    return run;
  }
  if (WIFSIGNALED(exit.status))
    return fail("its process died with signal " + std::to_string(WTERMSIG(exit.status)) + " (" +
                ::strsignal(WTERMSIG(exit.status)) + ")" + errors);
  const int code = WEXITSTATUS(exit.status);
  if (code == 127 && !fs::exists(outFolder / kStatusFile))
    return fail("its command could not be started (" + command_.argv.front() + ")" + errors);
  if (!fs::exists(outFolder / kStatusFile))
    return fail("it exited with status " + std::to_string(code) + " without writing " +
                kStatusFile + errors);
  if (code != 0)
    return fail("it exited with status " + std::to_string(code) + " (the protocol asks for 0 "
                "whenever status.json is written)" + errors);
  try {
    readStatus(outFolder / kStatusFile, run);
  } catch (const std::exception& e) {
    return fail(std::string(kStatusFile) + ": " + e.what());
  }
  facts_ = run.facts;
  if (run.status != RunStatus::Ok && run.status != RunStatus::Diverged) return run;
  // The trajectory: trajectory.csv, or its binary form trajectory.npy; never both.
  const bool csv = fs::exists(outFolder / kTrajectoryFile);
  const bool npy = fs::exists(outFolder / kTrajectoryNpyFile);
  if (csv && npy)
    return fail(std::string("it wrote both ") + kTrajectoryFile + " and " + kTrajectoryNpyFile +
                " (the protocol asks for one)");
  const std::string trajectoryFile = npy ? kTrajectoryNpyFile : kTrajectoryFile;
  try {
    const std::string file = (outFolder / trajectoryFile).string();
    run.samples = (npy ? readTrajectoryNpy(file) : readTrajectoryCsv(file)).samples;
  } catch (const std::exception& e) {
    return fail(trajectoryFile + ": " + e.what());
  }
  // The particles: particles.csv or particles.npy, at the trajectory's samples, exactly when the
  // scene has particles.
  const bool particleCsv = fs::exists(outFolder / kParticlesFile);
  const bool particleNpy = fs::exists(outFolder / kParticlesNpyFile);
  if (particleCsv && particleNpy)
    return fail(std::string("it wrote both ") + kParticlesFile + " and " + kParticlesNpyFile +
                " (the protocol asks for one)");
  if (scene.particles.empty()) {
    if (particleCsv || particleNpy)
      return fail(std::string("it wrote ") + (particleNpy ? kParticlesNpyFile : kParticlesFile) +
                  " for a scene without particles");
    if (const std::string wrong = checkSamples(run.samples, scene, plan, run.status); !wrong.empty())
      return fail(trajectoryFile + ": " + wrong);
  } else {
    if (!particleCsv && !particleNpy)
      return fail("the scene has " + std::to_string(scene.particles.size()) +
                  " particles and it wrote neither " + kParticlesNpyFile + " nor " + kParticlesFile);
    const std::string particleFile = particleNpy ? kParticlesNpyFile : kParticlesFile;
    Trajectory particles;
    try {
      particles = readParticleTrajectory((outFolder / particleFile).string());
    } catch (const std::exception& e) {
      return fail(particleFile + ": " + e.what());
    }
    // A scene without rigid bodies has a trajectory of zero rows per sample: its sample times
    // are the particles'.
    if (scene.rigidBodies.empty() && run.samples.empty())
      for (const State& p : particles.samples) {
        State s;
        s.time = p.time;
        run.samples.push_back(s);
      }
    if (const std::string wrong = checkSamples(run.samples, scene, plan, run.status); !wrong.empty())
      return fail((scene.rigidBodies.empty() ? particleFile : trajectoryFile) + ": " + wrong);
    if (const std::string wrong = mergeParticles(particles.samples, scene, run.samples); !wrong.empty())
      return fail(particleFile + ": " + wrong);
  }
  run.steps = plan.steps;
  return run;
}

void removeEngineLeftovers(pid_t owner) {
  const std::string prefix = scratchPrefix(owner);
  std::error_code error;
  std::vector<fs::path> folders;
  for (const auto& item : fs::directory_iterator(fs::temp_directory_path(), error))
    if (item.path().filename().string().rfind(prefix, 0) == 0) folders.push_back(item.path());
  for (const fs::path& folder : folders) {
    std::ifstream group(folder / kGroupFile);
    long id = 0;
    if (group >> id && id > 1) ::kill(-static_cast<pid_t>(id), SIGKILL);
    std::error_code ignored;
    fs::remove_all(folder, ignored);
  }
}

// --- The catalogue ---------------------------------------------------------------------------

namespace {

struct CatalogueNode {
  const Json& json;
  std::string path;
  const std::string& file;

  [[noreturn]] void fail(const std::string& expected) const {
    std::string got = json.is_discarded() ? "nothing" : jsonText(json, -1);
    if (got.size() > 60) got = got.substr(0, 57) + "...";
    throw std::invalid_argument(file + ": " + path + ": expected " + expected + ", got " + got);
  }
  CatalogueNode at(const std::string& key) const {
    static const Json missing(nlohmann::json::value_t::discarded);
    const std::string p = path.empty() ? key : path + "." + key;
    return {json.is_object() && json.contains(key) ? json.at(key) : missing, p, file};
  }
  CatalogueNode at(std::size_t i) const { return {json.at(i), path + "[" + std::to_string(i) + "]", file}; }
  bool has(const std::string& key) const { return json.is_object() && json.contains(key); }
  std::string text() const {
    if (!json.is_string() || json.get<std::string>().empty()) fail("a non-empty string");
    return json.get<std::string>();
  }
  double number() const {
    if (!json.is_number()) fail("a number");
    return json.get<double>();
  }
  const Json& array() const {
    if (!json.is_array()) fail("an array");
    return json;
  }
};

/// Refuses a key outside `allowed` (docs/schemas/catalogue.schema.json: no other keys), naming
/// its JSON path and the keys that are allowed.
void onlyKeys(const CatalogueNode& node, std::initializer_list<const char*> allowed) {
  if (!node.json.is_object()) node.fail("a JSON object");
  for (const auto& item : node.json.items()) {
    bool known = false;
    std::string list;
    for (const char* key : allowed) {
      known = known || item.key() == key;
      list += (list.empty() ? "" : ", ") + std::string(key);
    }
    if (!known) node.at(item.key()).fail("no such key (allowed: " + list + ")");
  }
}

ParameterSpec catalogueParameter(const CatalogueNode& node, const std::string& method) {
  onlyKeys(node, {"name", "kind", "default", "min", "max", "choices", "unit", "description"});
  ParameterSpec p;
  p.name = node.at("name").text();
  const std::string kind = node.at("kind").text();
  const CatalogueNode value = node.at("default");
  if (kind == "real") {
    p.kind = ParameterKind::Real;
    p.defaultValue = pbd::formatReal(value.number());
  } else if (kind == "integer") {
    p.kind = ParameterKind::Integer;
    if (!value.json.is_number_integer()) value.fail("an integer");
    p.defaultValue = std::to_string(value.json.get<std::int64_t>());
  } else if (kind == "bool") {
    p.kind = ParameterKind::Bool;
    if (!value.json.is_boolean()) value.fail("true or false");
    p.defaultValue = value.json.get<bool>() ? "true" : "false";
  } else if (kind == "choice") {
    p.kind = ParameterKind::Choice;
    p.defaultValue = value.text();
    const CatalogueNode choices = node.at("choices");
    for (std::size_t i = 0; i < choices.array().size(); ++i) p.choices.push_back(choices.at(i).text());
  } else {
    node.at("kind").fail("one of real, integer, bool, choice");
  }
  if (node.has("min")) p.minimum = node.at("min").number();
  if (node.has("max")) p.maximum = node.at("max").number();
  if (node.has("unit") && node.at("unit").json.is_string()) p.unit = node.at("unit").json.get<std::string>();
  p.description = node.has("description") ? node.at("description").text() : "";
  try {
    parseParameter(p, p.defaultValue, method);
  } catch (const std::invalid_argument& e) {
    value.fail(std::string("a default within its own declaration (") + e.what() + ")");
  }
  return p;
}

/// The catalogue's feature table (adapters/features.h; docs/external-engines.md#features):
/// every entry checked, then the table as a whole (each problem named by its JSON path).
FeatureTable catalogueFeatures(const CatalogueNode& node, const std::vector<std::string>& methods) {
  FeatureTable table;
  for (std::size_t i = 0; i < node.array().size(); ++i) {
    const CatalogueNode e = node.at(i);
    onlyKeys(e, {"feature", "support", "text", "methods"});
    FeatureSupport support;
    support.key = e.at("feature").text();
    const std::string level = e.at("support").text();
    try {
      support.support = supportNamed(level);
    } catch (const std::invalid_argument&) {
      e.at("support").fail("one of native, approximated, unsupported");
    }
    if (e.has("text")) {
      if (!e.at("text").json.is_string()) e.at("text").fail("a string");
      support.text = e.at("text").json.get<std::string>();
    }
    if (e.has("methods")) {
      const CatalogueNode list = e.at("methods");
      if (list.array().empty()) list.fail("a non-empty array of method names (leave it out for every method)");
      for (std::size_t k = 0; k < list.json.size(); ++k) support.methods.push_back(list.at(k).text());
    }
    table.entries.push_back(std::move(support));
  }
  const std::vector<std::string> problems = checkFeatureTable(table, methods);
  if (!problems.empty()) {
    std::string text = problems.front();
    // checkFeatureTable names entries "features[3]..." and the table "features: ...".
    throw std::invalid_argument(node.file + ": " + text +
                                (problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) +
                                                           " more)"
                                                     : std::string()));
  }
  return table;
}

EngineEntry catalogueEntry(const std::string& file, const ProjectPython& python,
                           const std::string& workingFolder) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const Json document = Json::parse(text.str(), nullptr, false);
  const CatalogueNode root{document, "", file};
  if (document.is_discarded()) throw std::invalid_argument(file + ": not valid JSON");
  if (!document.is_object()) root.fail("a JSON object");
  if (root.at("protocol").json != kExternalProtocolVersion) root.at("protocol").fail("1");
  onlyKeys(root, {"protocol", "name", "description", "example", "command", "defaultMethod",
                  "version", "methods", "features"});
  EngineEntry entry;
  entry.name = root.at("name").text();
  ExternalCommand command;
  command.workingFolder = workingFolder;
  const CatalogueNode argv = root.at("command");
  if (argv.array().empty()) argv.fail("a non-empty array of strings");
  for (std::size_t i = 0; i < argv.json.size(); ++i) {
    std::string word = argv.at(i).text();
    if (word == "{python}") {
      word = python.interpreter;
      command.pythonPackageFolder = python.packageFolder;
    }
    command.argv.push_back(word);
  }
  entry.defaultMethod = root.at("defaultMethod").text();
  const CatalogueNode methods = root.at("methods");
  for (std::size_t i = 0; i < methods.array().size(); ++i) {
    const CatalogueNode m = methods.at(i);
    onlyKeys(m, {"name", "description", "parameters"});
    MethodInfo info;
    info.name = m.at("name").text();
    if (info.name.rfind(entry.name + ".", 0) != 0)
      m.at("name").fail("a name starting with \"" + entry.name + ".\"");
    info.engine = entry.name;
    info.description = m.has("description") ? m.at("description").text() : "";
    if (m.has("parameters")) {
      const CatalogueNode parameters = m.at("parameters");
      for (std::size_t k = 0; k < parameters.array().size(); ++k)
        info.parameters.push_back(catalogueParameter(parameters.at(k), info.name));
    }
    entry.methods.push_back(std::move(info));
  }
  entry.honouredSettings = {"timeStepSize", "gravitation"};
  if (root.has("features")) {
    std::vector<std::string> methodNames;
    for (const MethodInfo& info : entry.methods) methodNames.push_back(info.name);
    entry.features = catalogueFeatures(root.at("features"), methodNames);
  }
  entry.runByDefault = !(root.has("example") && root.at("example").json == true);
  const std::string name = entry.name;
  const FeatureTable features = entry.features;
  entry.make = [name, command, features](const EngineOptions&) {
    return std::unique_ptr<Engine>(new ExternalEngine(name, command, features));
  };
  return entry;
}

}  // namespace

std::vector<EngineEntry> readEngineCatalogue(const std::string& folder, const ProjectPython& python,
                                             const std::string& workingFolder) {
  std::vector<std::string> files;
  std::error_code error;
  for (const auto& item : fs::directory_iterator(folder, error))
    if (item.path().extension() == ".json") files.push_back(item.path().string());
  std::sort(files.begin(), files.end());
  std::vector<EngineEntry> entries;
  for (const std::string& file : files) entries.push_back(catalogueEntry(file, python, workingFolder));
  return entries;
}

}  // namespace pbdval
