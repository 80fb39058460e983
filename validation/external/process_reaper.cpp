#include "validation/external/process_reaper.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

namespace pbdval {
namespace {

using Clock = std::chrono::steady_clock;

/// The environment of process `pid` (NUL-separated entries), or empty when it cannot be read
/// (gone, a zombie, another user's).
std::string environmentOf(const std::string& pid) {
  const std::string path = "/proc/" + pid + "/environ";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n > 0) {
      text.append(buffer, std::size_t(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fd);
  return text;
}

/// The processes (other than this one) whose environment holds `entry` ("NAME=value").
std::vector<pid_t> processesMarked(const std::string& entry) {
  std::vector<pid_t> found;
  DIR* proc = ::opendir("/proc");
  if (!proc) return found;
  const pid_t self = ::getpid();
  while (const dirent* item = ::readdir(proc)) {
    const std::string name = item->d_name;
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = pid_t(std::strtol(name.c_str(), nullptr, 10));
    if (pid == self) continue;
    const std::string environment = environmentOf(name);
    std::size_t start = 0;
    while (start < environment.size()) {
      std::size_t end = environment.find('\0', start);
      if (end == std::string::npos) end = environment.size();
      if (environment.compare(start, end - start, entry) == 0) {
        found.push_back(pid);
        break;
      }
      start = end + 1;
    }
  }
  ::closedir(proc);
  return found;
}

}  // namespace

ProcessReaper::ProcessReaper() {
  std::ostringstream value;
  value << ::getpid() << "-" << Clock::now().time_since_epoch().count() << "-"
        << static_cast<const void*>(this);
  value_ = value.str();
  ::prctl(PR_GET_CHILD_SUBREAPER, &previousSubreaper_);
  ::prctl(PR_SET_CHILD_SUBREAPER, 1);
}

ProcessReaper::~ProcessReaper() {
  ::prctl(PR_SET_CHILD_SUBREAPER, previousSubreaper_);
}

void ProcessReaper::mark() const {
  ::setenv(kVariable, value_.c_str(), 1);
}

namespace {

/// Kills every marked process, round after round, until none is left or `deadline`.
std::set<pid_t> killMarked(const std::string& value, Clock::time_point deadline) {
  const std::string entry = std::string(ProcessReaper::kVariable) + "=" + value;
  std::set<pid_t> killed;
  for (;;) {
    const std::vector<pid_t> marked = processesMarked(entry);
    bool fresh = false;
    for (const pid_t pid : marked) {
      ::kill(pid, SIGKILL);
      fresh = killed.insert(pid).second || fresh;
    }
    if (marked.empty() || Clock::now() > deadline) break;
    if (!fresh) std::this_thread::sleep_for(std::chrono::milliseconds(2));  // dying: wait
  }
  return killed;
}

}  // namespace

int killProcessesMarked(const std::string& value) {
  if (value.empty()) return 0;
  return int(killMarked(value, Clock::now() + std::chrono::seconds(2)).size());
}

int ProcessReaper::killRemaining(pid_t engine) const {
  // 2 s: a process that forks in a loop faster than it can be killed is stopped trying after
  // it; every round kills what the previous one left, so a normal process tree ends in one or two.
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(2);
  const std::set<pid_t> killed = killMarked(value_, deadline);
  // Reap the ones that are (or become, as their parents die) this subreaper's children; the
  // others are reaped by their own parents or by init.
  std::set<pid_t> waiting = killed;
  waiting.erase(engine);  // the caller reaps it, for its exit status
  while (!waiting.empty() && Clock::now() <= deadline + std::chrono::seconds(1)) {
    for (auto it = waiting.begin(); it != waiting.end();) {
      const pid_t result = ::waitpid(*it, nullptr, WNOHANG);
      // ECHILD: not this process's child, or not yet (its parent is still exiting): done once
      // the process is gone (init or its parent reaped it).
      const bool gone =
          result == *it || (result < 0 && errno == ECHILD &&
                            ::access(("/proc/" + std::to_string(*it)).c_str(), F_OK) != 0);
      if (gone)
        it = waiting.erase(it);
      else
        ++it;
    }
    if (!waiting.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return int(killed.size());
}

}  // namespace pbdval
