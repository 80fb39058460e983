#include "adapters/ode/ode_runtime.h"

#include <ode/ode.h>

#include <cstdarg>
#include <cstdio>

#include "adapters/engine.h"

namespace pbdval::ode {
namespace {

static_assert(sizeof(dReal) == 8, "pbdval needs ODE built in double precision (dDOUBLE)");

// The one lock around ODE (see the header). Recursive, so that an engine may take it while it
// already holds it (load() calling helpers that open their own OdeCall).
std::recursive_mutex& odeMutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

// The library's reference count and the handlers that were installed before ours.
struct LibraryState {
  int references = 0;
  dMessageFunction* previousError = nullptr;
  dMessageFunction* previousDebug = nullptr;
  dMessageFunction* previousMessage = nullptr;
};

LibraryState& libraryState() {
  static LibraryState state;
  return state;
}

// The context of the OdeCall running on this thread (null outside calls).
thread_local OdeContext* activeContext = nullptr;

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"  // ODE's own format strings
std::string formatOdeText(const char* format, va_list args) {
  char buffer[1024];
  std::vsnprintf(buffer, sizeof buffer, format, args);
  std::string text = buffer;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
    text.pop_back();
  return text;
}
#pragma GCC diagnostic pop

[[noreturn]] void throwOdeFailure(const char* kind, int code, const char* format, va_list args) {
  throw EngineError(std::string(kind) + " " + std::to_string(code) + ": " +
                    formatOdeText(format, args));
}

// dError: ODE would exit(1) when this returns, so it never returns.
void onOdeError(int code, const char* format, va_list args) {
  throwOdeFailure("ODE error", code, format, args);
}

// dDebug (failed internal or argument assertions): ODE would abort() when this returns.
void onOdeDebug(int code, const char* format, va_list args) {
  throwOdeFailure("ODE internal error", code, format, args);
}

// dMessage: a warning; ODE continues.
void onOdeMessage(int code, const char* format, va_list args) {
  if (activeContext == nullptr) return;
  OdeMessageLog& log = activeContext->messages;
  ++log.total;
  if (log.kept.size() < OdeMessageLog::kMaxKeptMessages)
    log.kept.push_back("ODE message " + std::to_string(code) + ": " + formatOdeText(format, args));
}

void installHandlers(LibraryState& state) {
  state.previousError = dGetErrorHandler();
  state.previousDebug = dGetDebugHandler();
  state.previousMessage = dGetMessageHandler();
  dSetErrorHandler(&onOdeError);
  dSetDebugHandler(&onOdeDebug);
  dSetMessageHandler(&onOdeMessage);
}

void restoreHandlers(const LibraryState& state) {
  dSetErrorHandler(state.previousError);
  dSetDebugHandler(state.previousDebug);
  dSetMessageHandler(state.previousMessage);
}

void acquireLibrary() {
  const std::lock_guard<std::recursive_mutex> lock(odeMutex());
  LibraryState& state = libraryState();
  if (state.references == 0) {
    installHandlers(state);
    if (!dInitODE2(0)) {
      restoreHandlers(state);
      throw EngineError("ODE: dInitODE2 failed");
    }
    if (!dCheckConfiguration("ODE_double_precision")) {
      const std::string configuration = dGetConfiguration();
      dCloseODE();
      restoreHandlers(state);
      throw EngineError("ODE is not built in double precision (configuration: " + configuration +
                        ")");
    }
  }
  ++state.references;
}

void releaseLibrary() noexcept {
  const std::lock_guard<std::recursive_mutex> lock(odeMutex());
  LibraryState& state = libraryState();
  if (--state.references > 0) return;
  dCloseODE();
  restoreHandlers(state);
}

}  // namespace

OdeLibrary::OdeLibrary() {
  acquireLibrary();
}
OdeLibrary::OdeLibrary(const OdeLibrary& /*other*/) {
  acquireLibrary();
}
OdeLibrary::~OdeLibrary() {
  releaseLibrary();
}

int OdeLibrary::references() {
  const std::lock_guard<std::recursive_mutex> lock(odeMutex());
  return libraryState().references;
}

OdeCall::OdeCall(OdeContext& context)
    : lock_(odeMutex()),
      context_(context),
      previous_(activeContext),
      previousSeed_(dRandGetSeed()) {
  // Per-thread collision data (the trimesh colliders' cache); a no-op once allocated.
  if (!dAllocateODEDataForThread(dAllocateMaskAll))
    throw EngineError("ODE: dAllocateODEDataForThread failed");
  activeContext = &context;
  dRandSetSeed(context.randomSeed);
}

OdeCall::~OdeCall() {
  context_.randomSeed = dRandGetSeed();
  dRandSetSeed(previousSeed_);
  activeContext = previous_;
}

}  // namespace pbdval::ode
