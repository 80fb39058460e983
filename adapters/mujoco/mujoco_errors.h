// MuJoCo 2.2.2 reports errors and warnings through two process-wide function pointers,
// mju_user_error and mju_user_warning. Without them it writes MUJOCO_LOG.TXT into the working
// directory, and mju_error waits for Enter and calls exit(). With a handler installed,
// mju_error calls it and, if it returns, *continues* with the failed operation (measured:
// a returning handler gets control back in the caller), so the handler must not return.
//
// The adapter installs two stateless handlers once per process. They route every message to
// the guard of the MuJoCo call running on the same thread (a thread-local pointer, set and
// restored around each call): warnings are appended to the guard's list; an error is copied
// into the guard and left through longjmp back to the guard's setjmp, which then throws
// EngineError. longjmp is well defined here because only MuJoCo's C frames and one trampoline
// without C++ objects lie between setjmp and the handler (MuJoCo's C++ model compiler installs
// its own throwing handlers while it runs and restores ours afterwards). The mjData of a call
// that failed is left inconsistent (its stack mark is never released): the engine refuses
// further steps.
//
// Messages outside a guard (another library calling MuJoCo on this thread) go to stderr; an
// error there returns, as MuJoCo's documented contract for a returning handler allows.
//
// Threads: stepping engines on several threads is safe (each thread has its own route).
// Compiling models on several threads at once is not: MuJoCo 2.2.2's compiler itself swaps the
// process-wide handlers while it runs.
#pragma once

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace pbdval::mujoco {

/// Runs `call(context)` with MuJoCo's messages routed to this thread: warnings are appended to
/// `warnings`, an error throws EngineError("MuJoCo error in <what>: <message>"). `call` must
/// not hold C++ objects with non-trivial destructors while it calls MuJoCo.
void guardedCall(const char* what, void (*call)(void*), void* context,
                 std::vector<std::string>& warnings);

/// guardedCall for a callable: `function` is invoked through a trampoline.
template <class Function>
void guarded(const char* what, std::vector<std::string>& warnings, Function&& function) {
  using Stored = std::remove_reference_t<Function>;
  guardedCall(
      what, [](void* context) { (*static_cast<Stored*>(context))(); },
      const_cast<void*>(static_cast<const void*>(&function)), warnings);
}

}  // namespace pbdval::mujoco
