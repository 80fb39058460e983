// ODE's process-wide state, confined to the adapter.
//
// ODE has three pieces of global state, and this file owns all of them:
//
//  * Library initialisation. dInitODE2/dCloseODE must bracket every use of ODE. OdeLibrary is a
//    reference to the library: the first reference initialises ODE, the last one closes it, so
//    any number of engines can exist at once and be destroyed in any order.
//  * Message handlers. dSetErrorHandler/dSetDebugHandler/dSetMessageHandler are process-wide, and
//    ODE calls exit(1) after the error handler returns and abort() after the debug handler
//    returns. The handlers installed here are stateless functions: an ODE error or internal error
//    (a failed assertion, an invalid argument) throws EngineError, which unwinds out of ODE
//    before it can end the process; the engine then refuses to step again. A warning
//    (dMessage, e.g. "LCP internal error") goes to the message log of the engine whose call is
//    running on this thread. The first reference installs them, the last one restores the
//    handlers that were there before.
//  * The random generator. dWorldQuickStep reorders constraints with ODE's one global generator
//    (dRandInt), so a run would depend on every ODE run before it in the process. Each engine
//    keeps its own generator state, starting from ODE's initial seed 0: OdeCall swaps it in and
//    saves it back.
//  * Collision caches. Debian's ODE is built without thread-local storage (no ODE_OU in
//    dGetConfiguration), so its trimesh collider cache is shared by the process. OdeCall
//    therefore serialises every entry into ODE.
//
// Every entry into ODE runs inside an OdeCall with the calling engine's OdeContext: it holds the
// lock, swaps in the engine's generator state, and routes warnings to the engine's log (a
// thread-local pointer, set for the call's duration only).
#pragma once

#include <mutex>
#include <string>
#include <vector>

namespace pbdval::ode {

/// ODE's warnings during one engine's calls: the first kMaxKeptMessages in full, all counted.
struct OdeMessageLog {
  static constexpr std::size_t kMaxKeptMessages = 32;
  std::vector<std::string> kept;
  std::size_t total = 0;
};

/// The part of ODE's process-wide state that belongs to one engine.
struct OdeContext {
  OdeMessageLog messages;
  unsigned long randomSeed = 0;  ///< ODE's generator state between this engine's calls
};

/// A reference to the initialised ODE library (see the file comment). Copying adds a reference.
class OdeLibrary {
 public:
  OdeLibrary();
  OdeLibrary(const OdeLibrary& other);
  OdeLibrary& operator=(const OdeLibrary&) = default;
  ~OdeLibrary();

  /// The number of live references (for tests).
  static int references();
};

/// One entry into ODE: holds the process-wide ODE lock, runs ODE's random generator from the
/// context's state (saved back at the end) and sends ODE's warnings to the context's log while
/// it lives. Nested calls on one thread are allowed (the innermost context wins).
class OdeCall {
 public:
  explicit OdeCall(OdeContext& context);
  ~OdeCall();
  OdeCall(const OdeCall&) = delete;
  OdeCall& operator=(const OdeCall&) = delete;

 private:
  std::unique_lock<std::recursive_mutex> lock_;
  OdeContext& context_;
  OdeContext* previous_;
  unsigned long previousSeed_;
};

}  // namespace pbdval::ode
