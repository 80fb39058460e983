// Taking SIGINT, SIGTERM and SIGHUP synchronously, so that a command interrupted while an
// engine runs can stop the engine's processes and remove its temporary files before it exits
// (docs/cli.md#interrupts). A signal that kills a process outright (SIGKILL) leaves what it
// leaves; these three are the ones a user or a batch system sends to ask a command to stop.
#pragma once

#include <signal.h>

#include <stdexcept>
#include <string>

namespace pbdval {

/// The run was interrupted by `signal()` (SIGINT, SIGTERM or SIGHUP); the engine's processes
/// were stopped and its scratch files removed. A command exits with 128 + signal().
class SignalInterrupt : public std::runtime_error {
 public:
  explicit SignalInterrupt(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

/// While it lives, SIGINT, SIGTERM and SIGHUP are blocked in the calling thread and wait as
/// pending signals for pending() or wait() to take them; the previous mask comes back when it
/// is destroyed (a signal still pending then is delivered as usual). Nested watches are fine.
class InterruptWatch {
 public:
  InterruptWatch();
  ~InterruptWatch();
  InterruptWatch(const InterruptWatch&) = delete;
  InterruptWatch& operator=(const InterruptWatch&) = delete;

  /// Takes a pending SIGINT, SIGTERM or SIGHUP and returns it, or 0 when none is pending.
  int pending() const { return wait(0); }
  /// Waits up to `seconds` for one; returns it, or 0.
  int wait(double seconds) const;
  /// Throws SignalInterrupt when one is pending.
  void throwIfInterrupted() const;
  /// For a child process between fork and exec: SIGINT, SIGTERM and SIGHUP unblocked, whatever
  /// the parent's watches (the program it starts gets them as usual).
  void unblockInChild() const;
  /// A file descriptor that poll() sees readable while one of them is pending (a signalfd,
  /// made on first use and closed with the watch; pending() still takes the signal), so that
  /// a wait for a socket wakes for an interrupt without looking every few milliseconds; -1
  /// when the system gives none.
  int descriptor() const;

 private:
  sigset_t signals_;
  sigset_t previous_;
  mutable int descriptor_ = -1;
  mutable bool descriptorTried_ = false;
};

/// "SIGINT", "SIGTERM", "SIGHUP" or "signal N".
std::string signalName(int signal);

}  // namespace pbdval
