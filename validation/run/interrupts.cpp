#include "validation/run/interrupts.h"

#include <pthread.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <ctime>

namespace pbdval {

std::string signalName(int signal) {
  switch (signal) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "signal " + std::to_string(signal);
  }
}

SignalInterrupt::SignalInterrupt(int signal)
    : std::runtime_error("interrupted by " + signalName(signal) +
                         ": the engine was stopped and its temporary files removed"),
      signal_(signal) {}

InterruptWatch::InterruptWatch() {
  sigemptyset(&signals_);
  sigaddset(&signals_, SIGINT);
  sigaddset(&signals_, SIGTERM);
  sigaddset(&signals_, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &signals_, &previous_);
}

InterruptWatch::~InterruptWatch() {
  if (descriptor_ >= 0) ::close(descriptor_);
  pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
}

int InterruptWatch::descriptor() const {
  if (!descriptorTried_) {
    descriptorTried_ = true;
    descriptor_ = ::signalfd(-1, &signals_, SFD_NONBLOCK | SFD_CLOEXEC);
  }
  return descriptor_;
}

int InterruptWatch::wait(double seconds) const {
  const double whole = std::floor(std::max(0.0, seconds));
  timespec timeout{static_cast<time_t>(whole),
                   static_cast<long>((std::max(0.0, seconds) - whole) * 1e9)};
  for (;;) {
    const int signal = sigtimedwait(&signals_, nullptr, &timeout);
    if (signal > 0) return signal;
    if (errno != EINTR) return 0;  // EAGAIN: none within the time
  }
}

void InterruptWatch::throwIfInterrupted() const {
  if (const int signal = pending()) throw SignalInterrupt(signal);
}

void InterruptWatch::unblockInChild() const {
  pthread_sigmask(SIG_UNBLOCK, &signals_, nullptr);
}

}  // namespace pbdval
