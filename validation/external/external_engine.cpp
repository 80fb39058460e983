#include "validation/external/external_engine.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/un.h>
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
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "pbd/io/number_text.h"
#include "validation/external/process_reaper.h"
#include "validation/external/resolved_scene.h"
#include "validation/io/json_schema.h"
#include "validation/io/json_text.h"
#include "validation/io/trajectory.h"
#include "validation/run/interrupts.h"
#include "validation/run/simulation.h"

namespace pbdval {

/// A whole run as the engine's files give it: its status, samples, facts and settings.
struct WholeRun {
  RunStatus status = RunStatus::Error;
  std::string reason;
  std::vector<State> samples;
  long steps = 0;  ///< steps the engine took
  RunFacts facts;
  std::map<std::string, std::string> settings;
};

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr const char* kStatusFile = "status.json";
constexpr const char* kTrajectoryFile = "trajectory.csv";
constexpr const char* kTrajectoryNpyFile = "trajectory.npy";  // the binary alternative
constexpr const char* kParticlesFile = "particles.csv";       // particle states, when any
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
    const bool named = !head.empty() && head.find(' ') == std::string::npos &&
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
  while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
    s.pop_back();
  if (s.empty()) return "";
  const std::string first = firstErrorLine(s);
  const bool cut = s.size() > 400;
  if (cut) s = "..." + s.substr(s.size() - 400);
  const bool firstShown = first.empty() || s.find(first) != std::string::npos;
  return (firstShown ? "" : "; its standard error says: " + first) +
         "; its standard error ends: " + s;
}

/// How a run's process ended.
struct Exit {
  bool timedOut = false;
  int interruptedBy = 0;  ///< SIGINT, SIGTERM or SIGHUP taken while it ran (it was stopped)
  int signal = 0;         ///< the signal that ended it, or 0
  int code = 0;           ///< its exit status, when it exited
  std::string failure;    ///< a server that could not run it: why (the run is an error)
};

/// The environment of an engine's process (the server's or a single-shot run's): after fork,
/// before exec. Its own process group, SIGKILL when its parent dies, the interrupts unblocked,
/// standard error to `stderrPath`, input and output /dev/null, PBDVAL_PROTOCOL, PYTHONPATH,
/// the working folder. Returns false (having said why on standard error) when the working
/// folder cannot be entered.
bool prepareEngineChild(const ExternalCommand& command, const std::string& pythonPath,
                        const fs::path& stderrPath, pid_t parent) {
  ::setpgid(0, 0);
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(127);  // the runner died before prctl
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
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
    return false;
  }
  return true;
}

/// PYTHONPATH for `command`: its package folder first, then whatever PYTHONPATH was; empty for
/// a command that does not name "{python}".
std::string pythonPathFor(const ExternalCommand& command) {
  std::string pythonPath = command.pythonPackageFolder;
  const char* inherited = std::getenv("PYTHONPATH");
  if (!pythonPath.empty() && inherited && *inherited) pythonPath += std::string(":") + inherited;
  return pythonPath;
}

/// Runs argv in `folder` with stdout to /dev/null and stderr to `stderrPath`, in a process group
/// of its own whose id is written to `groupFile`; kills it after `limit` seconds (0: none) or
/// when SIGINT, SIGTERM or SIGHUP arrives. Whatever way it ends, its whole process group is
/// killed before it is reaped, and every process it started elsewhere (a setsid() child, a
/// daemon: ProcessReaper): a process the engine started and left running ends with it. The
/// engine also dies with the process that started it (PR_SET_PDEATHSIG), should that one be
/// killed outright.
Exit runProcess(const ExternalCommand& command, const std::vector<std::string>& extraArguments,
                const fs::path& stderrPath, const fs::path& groupFile, double limit) {
  std::vector<std::string> arguments = command.argv;
  arguments.insert(arguments.end(), extraArguments.begin(), extraArguments.end());
  std::vector<char*> argv;
  for (std::string& a : arguments)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  const std::string pythonPath = pythonPathFor(command);  // composed before the fork
  const InterruptWatch interrupts;
  const ProcessReaper reaper;  // what the engine starts outside its process group, too
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw EngineError(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    if (!prepareEngineChild(command, pythonPath, stderrPath, parent)) ::_exit(127);
    reaper.mark();
    ::execvp(argv[0], argv.data());
    std::fprintf(stderr, "pbdval: cannot start %s: %s\n", argv[0], std::strerror(errno));
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: whichever of the two runs first
  {
    std::ofstream group(groupFile);
    group << pid << "\n" << reaper.value() << "\n";  // and the mark: removeEngineLeftovers
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
  // e.g. a child that called setsid() (validation/external/process_reaper.h)
  reaper.killRemaining(pid);
  ::kill(-pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) exit.signal = WTERMSIG(status);
  if (WIFEXITED(status)) exit.code = WEXITSTATUS(status);
  return exit;
}

// --- Runs through a server -------------------------------------------------------------------

/// A file descriptor closed when it goes.
class Descriptor {
 public:
  explicit Descriptor(int fd = -1) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

/// A connection to the Unix socket `path`, or -1 with errno set.
int connectToSocket(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof(address.sun_path)) {
    errno = ENAMETOOLONG;
    return -1;
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  return fd;
}

/// The milliseconds from now to `deadline`, rounded up, at most a second (poll's timeout).
int millisecondsUntil(Clock::time_point deadline) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return int(std::clamp<decltype(left)>(left, 0, 1000));
}

/// Reads a server's replies, one JSON object per line.
class ReplyReader {
 public:
  enum class Result { Line, Ended, TimedOut, Interrupted };

  ReplyReader(int fd, const InterruptWatch& interrupts) : fd_(fd), interrupts_(interrupts) {}

  /// Waits for the next line until `deadline` (none when it is max()), watching for interrupts.
  Result next(Clock::time_point deadline, Json& reply) {
    for (;;) {
      const std::size_t end = buffer_.find('\n');
      if (end != std::string::npos) {
        reply = Json::parse(buffer_.substr(0, end), nullptr, false);
        buffer_.erase(0, end + 1);
        if (reply.is_discarded() || !reply.is_object()) reply = Json::object();
        return Result::Line;
      }
      if (ended_) return Result::Ended;
      if (Clock::now() > deadline) return Result::TimedOut;
      if (const int caught = interrupts_.pending()) {
        signal_ = caught;
        return Result::Interrupted;
      }
      // Asleep until the reply, an interrupt or the deadline: without a signal descriptor, an
      // interrupt is looked for every 2 ms (a wake-up every 2 ms of every served run cost the
      // runner 8-12 ms of CPU per 24 runs: docs/benchmarks.md, seventh pass).
      pollfd items[2] = {{fd_, POLLIN, 0}, {interrupts_.descriptor(), POLLIN, 0}};
      const nfds_t count = items[1].fd >= 0 ? 2 : 1;
      if (::poll(items, count, count == 2 ? millisecondsUntil(deadline) : 2) <= 0 ||
          items[0].revents == 0)
        continue;
      char chunk[512];
      const ssize_t n = ::read(fd_, chunk, sizeof(chunk));
      if (n > 0)
        buffer_.append(chunk, std::size_t(n));
      else if (n == 0 || (errno != EINTR && errno != EAGAIN))
        ended_ = true;
    }
  }
  int signal() const { return signal_; }

 private:
  int fd_;
  const InterruptWatch& interrupts_;
  std::string buffer_;
  bool ended_ = false;
  int signal_ = 0;
};

/// One run through the server listening at `socket` (docs/external-engines.md#persistent-engines):
/// the request, the forked child's process group (written to `groupFile` as soon as known, for
/// removeEngineLeftovers), its end. Past `limit` seconds (0: none) or on SIGINT, SIGTERM or
/// SIGHUP the child's group is killed; the server reaps it and reports.
Exit runServed(const std::string& socketPath, const std::string& serverLog,
               const std::vector<std::string>& extraArguments, const fs::path& stderrPath,
               const fs::path& groupFile, double limit) {
  Exit exit;
  const auto serverSays = [&]() { return stderrTail(serverLog); };
  if (!fs::exists(socketPath)) {
    exit.failure = "its server did not start (no socket at " + socketPath + ")" + serverSays();
    return exit;
  }
  const Descriptor connection(connectToSocket(socketPath));
  if (connection.get() < 0) {
    exit.failure = "its server does not accept runs (" + socketPath + ": " + std::strerror(errno) +
                   ")" + serverSays();
    return exit;
  }
  Json request = {{"protocol", kExternalProtocolVersion}, {"stderr", stderrPath.string()}};
  for (std::size_t i = 0; i + 1 < extraArguments.size(); i += 2)
    request[extraArguments[i].substr(2)] = extraArguments[i + 1];  // --scene, --out
  const std::string line = request.dump() + "\n";
  if (::send(connection.get(), line.data(), line.size(), MSG_NOSIGNAL) != ssize_t(line.size())) {
    exit.failure = std::string("its server did not take the run (") + std::strerror(errno) + ")" +
                   serverSays();
    return exit;
  }
  const InterruptWatch interrupts;
  ReplyReader replies(connection.get(), interrupts);
  const Clock::time_point start = Clock::now();
  const Clock::time_point none = Clock::time_point::max();
  const Clock::time_point deadline = limit > 0
                                         ? start + std::chrono::duration_cast<Clock::duration>(
                                                       std::chrono::duration<double>(limit))
                                         : none;
  Json reply;
  ReplyReader::Result got = replies.next(deadline, reply);
  long child = 0;
  if (got == ReplyReader::Result::Line && reply.contains("started") &&
      reply.at("started").is_number_integer())
    child = reply.at("started").get<long>();
  if (child > 1) {
    std::ofstream group(groupFile);
    group << child << "\n";
    got = replies.next(deadline, reply);
  }
  if (got == ReplyReader::Result::TimedOut || got == ReplyReader::Result::Interrupted) {
    if (child > 1) ::kill(-pid_t(child), SIGKILL);
    exit.timedOut = got == ReplyReader::Result::TimedOut;
    exit.interruptedBy = replies.signal();
    // The server reaps the child and says so; the next run waits for that anyway.
    if (child > 1) replies.next(Clock::now() + std::chrono::seconds(10), reply);
    return exit;
  }
  if (got == ReplyReader::Result::Ended) {
    if (child > 1) ::kill(-pid_t(child), SIGKILL);
    exit.failure = "its server ended during the run" + serverSays();
    return exit;
  }
  if (reply.contains("exited") && reply.at("exited").is_number_integer()) {
    exit.code = reply.at("exited").get<int>();
  } else if (reply.contains("signaled") && reply.at("signaled").is_number_integer()) {
    exit.signal = reply.at("signaled").get<int>();
  } else {
    if (child > 1) ::kill(-pid_t(child), SIGKILL);
    exit.failure =
        "its server replied " + reply.dump() +
        (reply.contains("error") ? ""
                                 : " (expected {\"exited\": code} or {\"signaled\": signal})") +
        serverSays();
    return exit;
  }
  // The run is over and the server has ended its group, or keeps its child for a later run
  // (serve.runsPerChild): nothing may kill that group from this run's folder any more.
  std::error_code ignored;
  fs::remove(groupFile, ignored);
  return exit;
}

/// A server process (EngineEntry::startServer): started, awaited until it listens, stopped
/// when it goes.
class ExternalServer final : public EngineServer {
 public:
  ExternalServer(const std::string& name, const ExternalCommand& serve, const std::string& folder,
                 double startLimit)
      : socket_(serverSocketPath(folder, name)),
        logPath_(serverLogPath(folder, name)),
        startLimit_(startLimit) {
    std::error_code ignored;
    fs::create_directories(folder, ignored);
    fs::remove(socket_, ignored);  // a socket an earlier server left
    std::vector<std::string> arguments = serve.argv;
    arguments.push_back("--socket");
    arguments.push_back(socket_);
    std::vector<char*> argv;
    for (std::string& a : arguments)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string pythonPath = pythonPathFor(serve);
    std::fflush(nullptr);
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ < 0) return;
    if (pid_ == 0) {
      if (!prepareEngineChild(serve, pythonPath, logPath_, parent)) ::_exit(127);
      ::execvp(argv[0], argv.data());
      std::fprintf(stderr, "pbdval: cannot start %s: %s\n", argv[0], std::strerror(errno));
      ::_exit(127);
    }
    ::setpgid(pid_, pid_);
  }

  void awaitListening() override {
    while (!listening_ && running()) {
      const int probe = connectToSocket(socket_);
      if (probe >= 0) {
        ::close(probe);  // an empty connection: the server reads no request and goes on
        listening_ = true;
        return;
      }
      if (std::chrono::duration<double>(Clock::now() - started_).count() > startLimit_) {
        std::ofstream(logPath_, std::ios::app)
            << "pbdval: the server did not listen within " << startLimit_ << " s; stopped\n";
        break;
      }
      ::usleep(2000);
    }
    if (!listening_) stop();
  }
  ~ExternalServer() override {
    if (::getpid() == owner_) stop();  // a forked copy leaves the server to its owner
  }

  bool running() const override {
    if (pid_ <= 0) return false;
    siginfo_t info{};
    const int result = ::waitid(P_PID, id_t(pid_), &info, WEXITED | WNOHANG | WNOWAIT);
    return result == 0 && info.si_pid == 0;
  }

 private:
  void stop() {
    if (pid_ > 0) {
      ::kill(-pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
    std::error_code ignored;
    if (listening_) fs::remove(socket_, ignored);
  }

  std::string socket_;
  std::string logPath_;
  double startLimit_;
  Clock::time_point started_ = Clock::now();
  pid_t owner_ = ::getpid();  ///< the process that started the server
  pid_t pid_ = -1;
  bool listening_ = false;
};

RunStatus statusNamed(const std::string& name) {
  for (RunStatus s : {RunStatus::Ok, RunStatus::Unsupported, RunStatus::Diverged, RunStatus::Error})
    if (name == runStatusName(s)) return s;
  throw std::invalid_argument("status: expected one of ok, unsupported, diverged, error, got \"" +
                              name + "\"");
}

/// The schema of status.json (docs/schemas/status.schema.json), read from the source tree.
Json statusSchema() {
  try {
    return projectSchema("status.schema.json");
  } catch (const std::runtime_error& e) {
    throw EngineError(e.what());
  }
}

/// Reads status.json into `run`, validated against its schema; throws std::invalid_argument
/// naming the JSON path of each violation.
void readStatus(const fs::path& file, WholeRun& run) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const Json j = Json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw std::invalid_argument("not a JSON object");
  const std::vector<std::string> violations = schemaViolations(statusSchema(), j);
  if (!violations.empty()) {
    std::string message;
    for (const std::string& v : violations)
      message += (message.empty() ? "" : "; ") + v;
    throw std::invalid_argument(message + " (docs/schemas/status.schema.json)");
  }
  // The types and the rules between fields are the schema's; what follows only reads.
  run.status = statusNamed(j.at("status").get<std::string>());
  run.reason = j.at("reason").get<std::string>();
  if (run.status == RunStatus::Unsupported) {
    std::string features;
    for (const Json& f : j.at("unsupported"))
      features += (features.empty() ? "" : "; ") + f.get<std::string>();
    run.reason = features;
  }
  run.facts.engineVersion = j.at("engineVersion").get<std::string>();
  run.facts.integratorStepsPerSceneStep = j.at("integratorStepsPerSceneStep").get<int>();
  run.facts.initialVelocitiesProjected = j.value("initialVelocitiesProjected", false);
  const Json& margin = j.at("contactMargin");
  if (!margin.is_null()) {
    if (!std::isfinite(margin.get<double>()))
      throw std::invalid_argument("contactMargin: expected a finite number of metres or null");
    run.facts.contactMargin = margin.get<double>();
  }
  for (const auto& item : j.at("effectiveSettings").items())
    run.settings[item.key()] =
        item.value().is_string() ? item.value().get<std::string>() : jsonText(item.value(), -1);
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

ExternalEngine::ExternalEngine(std::string name, ExternalCommand command, FeatureTable features,
                               std::string serverFolder)
    : name_(std::move(name)),
      command_(std::move(command)),
      features_(std::move(features)),
      serverFolder_(std::move(serverFolder)) {}

std::string serverSocketPath(const std::string& serverFolder, const std::string& name) {
  return (fs::path(serverFolder) / (name + ".socket")).string();
}

std::string serverLogPath(const std::string& serverFolder, const std::string& name) {
  return (fs::path(serverFolder) / (name + ".stderr")).string();
}

std::unique_ptr<EngineServer> startExternalServer(const std::string& name,
                                                  const ExternalCommand& serve,
                                                  const std::string& serverFolder,
                                                  double startLimit) {
  std::unique_ptr<EngineServer> server =
      launchExternalServer(name, serve, serverFolder, startLimit);
  server->awaitListening();
  return server;
}

std::unique_ptr<EngineServer> launchExternalServer(const std::string& name,
                                                   const ExternalCommand& serve,
                                                   const std::string& serverFolder,
                                                   double startLimit) {
  return std::make_unique<ExternalServer>(name, serve, serverFolder, startLimit);
}

EngineRunResult ExternalEngine::run(const pbd::Scene& scene, const Method& method,
                                    const RunLength& length, const StepPlan& plan,
                                    double wallTimeLimit, RunObserver& observer) {
  const Clock::time_point started = Clock::now();
  WholeRun run;
  const EngineRunResult result = runWhole(scene, method, length, plan, wallTimeLimit, run);
  // The samples, checked by the observer like a stepped run's states.
  observer.begin(run.facts, run.settings, StateCadence::SamplesOnly);
  for (std::size_t k = 0; k < run.samples.size(); ++k)
    if (!observer.state(run.samples[k], k == 0 ? 0 : std::min(plan.steps, long(k) * plan.stride)))
      break;
  EngineRunResult done = result;
  done.busySeconds = std::chrono::duration<double>(Clock::now() - started).count();
  return done;
}

EngineRunResult ExternalEngine::runWhole(const pbd::Scene& scene, const Method& method,
                                         const RunLength& length, const StepPlan& plan,
                                         double wallTimeLimit, WholeRun& run) {
  const auto finish = [&]() {
    EngineRunResult result;
    result.status = run.status;
    result.reason = run.reason;
    result.steps = run.status == RunStatus::Ok ? plan.steps : run.steps;
    return result;
  };
  const auto fail = [&](const std::string& reason) {
    run.status = RunStatus::Error;
    run.reason = "external engine " + name_ + ": " + reason;
    run.samples.clear();
    return finish();
  };
  const ScratchFolder scratch;
  const Json parameters = methodParametersJson(method);
  const fs::path scenePath = scratch.path() / "resolved-scene.json";
  const fs::path outFolder = scratch.path() / "out";
  fs::create_directory(outFolder);
  {
    // Written whole before the engine starts, into a folder only this run uses, and removed
    // with it: no rename or fsync needed (an fsync costs milliseconds per run).
    std::ofstream file(scenePath);
    file << jsonText(resolvedSceneJson(scene, method.name, parameters, length)) << "\n";
    file.close();
    if (!file) throw EngineError("cannot write the resolved scene " + scenePath.string());
  }

  const std::vector<std::string> arguments = {"--scene", scenePath.string(), "--out",
                                              outFolder.string()};
  const Exit exit =
      serverFolder_.empty()
          ? runProcess(command_, arguments, scratch.path() / kStderrFile,
                       scratch.path() / kGroupFile, wallTimeLimit)
          : runServed(serverSocketPath(serverFolder_, name_), serverLogPath(serverFolder_, name_),
                      arguments, scratch.path() / kStderrFile, scratch.path() / kGroupFile,
                      wallTimeLimit);
  if (exit.interruptedBy != 0) throw SignalInterrupt(exit.interruptedBy);  // scratch removed
  const std::string errors = stderrTail(scratch.path() / kStderrFile);
  if (exit.timedOut) {
    run.status = RunStatus::Timeout;
    run.reason = "external engine " + name_ + " exceeded the wall-time limit of " +
                 pbd::formatReal(wallTimeLimit) + " s and was stopped";
    return finish();
  }
  if (!exit.failure.empty()) return fail(exit.failure);
  if (exit.signal != 0)
    return fail("its process died with signal " + std::to_string(exit.signal) + " (" +
                ::strsignal(exit.signal) + ")" + errors);
  const int code = exit.code;
  if (code == 127 && !fs::exists(outFolder / kStatusFile))
    return fail("its command could not be started (" + command_.argv.front() + ")" + errors);
  if (!fs::exists(outFolder / kStatusFile))
    return fail("it exited with status " + std::to_string(code) + " without writing " +
                kStatusFile + errors);
  if (code != 0)
    return fail("it exited with status " + std::to_string(code) +
                " (the protocol asks for 0 "
                "whenever status.json is written)" +
                errors);
  try {
    readStatus(outFolder / kStatusFile, run);
  } catch (const std::exception& e) {
    return fail(std::string(kStatusFile) + ": " + e.what());
  }
  if (run.status != RunStatus::Ok && run.status != RunStatus::Diverged) return finish();
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
    if (const std::string wrong = checkSamples(run.samples, scene, plan, run.status);
        !wrong.empty())
      return fail(trajectoryFile + ": " + wrong);
  } else {
    if (!particleCsv && !particleNpy)
      return fail("the scene has " + std::to_string(scene.particles.size()) +
                  " particles and it wrote neither " + kParticlesNpyFile + " nor " +
                  kParticlesFile);
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
    if (const std::string wrong = checkSamples(run.samples, scene, plan, run.status);
        !wrong.empty())
      return fail((scene.rigidBodies.empty() ? particleFile : trajectoryFile) + ": " + wrong);
    if (const std::string wrong = mergeParticles(particles.samples, scene, run.samples);
        !wrong.empty())
      return fail(particleFile + ": " + wrong);
  }
  run.steps = plan.steps;
  return finish();
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
    std::string mark;  // what the engine started outside its group (process_reaper.h)
    if (group >> id && id > 1) ::kill(-static_cast<pid_t>(id), SIGKILL);
    if (group >> mark) killProcessesMarked(mark);
    std::error_code ignored;
    fs::remove_all(folder, ignored);
  }
}

}  // namespace pbdval
