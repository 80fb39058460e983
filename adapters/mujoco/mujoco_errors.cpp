#include "adapters/mujoco/mujoco_errors.h"

#include <mujoco/mujoco.h>

#include <csetjmp>
#include <cstdio>
#include <mutex>

#include "adapters/engine.h"

namespace pbdval::mujoco {
namespace {

/// The guard of the MuJoCo call running on this thread (trivially destructible: it is live
/// while longjmp crosses frames).
struct Route {
  std::jmp_buf* jump = nullptr;
  std::vector<std::string>* warnings = nullptr;
  char error[2048] = {};
};

thread_local Route* currentRoute = nullptr;

[[noreturn]] void jumpToGuard(Route& route, const char* message) {
  std::snprintf(route.error, sizeof route.error, "%s", message);
  std::longjmp(*route.jump, 1);
}

void routeError(const char* message) {
  Route* route = currentRoute;
  if (route != nullptr && route->jump != nullptr) jumpToGuard(*route, message);
  std::fprintf(stderr, "MuJoCo error outside a pbdval call: %s\n", message);
}

void routeWarning(const char* message) {
  Route* route = currentRoute;
  if (route != nullptr && route->warnings != nullptr)
    route->warnings->emplace_back(message);
  else
    std::fprintf(stderr, "MuJoCo warning outside a pbdval call: %s\n", message);
}

void installHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = &routeError;
    mju_user_warning = &routeWarning;
  });
}

/// Returns true when MuJoCo reported an error (route.error holds it). No C++ objects live in
/// this frame across setjmp.
bool callWithJump(Route& route, void (*call)(void*), void* context) {
  std::jmp_buf jump;
  route.jump = &jump;
  if (setjmp(jump) != 0) {
    route.jump = nullptr;
    return true;
  }
  call(context);
  route.jump = nullptr;
  return false;
}

}  // namespace

void guardedCall(const char* what, void (*call)(void*), void* context,
                 std::vector<std::string>& warnings) {
  installHandlers();
  Route route;
  route.warnings = &warnings;
  Route* const enclosing = currentRoute;
  currentRoute = &route;
  const bool failed = callWithJump(route, call, context);
  currentRoute = enclosing;
  if (failed) throw EngineError(std::string("MuJoCo error in ") + what + ": " + route.error);
}

}  // namespace pbdval::mujoco
