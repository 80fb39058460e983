#include "adapters/selftest/selftest_engine.h"

#include <chrono>
#include <csignal>
#include <limits>
#include <thread>

namespace pbdval {
namespace {

enum class Failure { None, Crash, Hang, Throw, NotANumber };

class SelftestEngine final : public Engine {
 public:
  std::string_view name() const override { return "selftest"; }
  std::vector<std::string> unsupported(const pbd::Scene&, const Method&) const override {
    return {};
  }

  void load(const pbd::Scene& scene, const Method& method) override {
    failure_ = method.name == "selftest.crash"   ? Failure::Crash
               : method.name == "selftest.hang"  ? Failure::Hang
               : method.name == "selftest.throw" ? Failure::Throw
               : method.name == "selftest.nan"   ? Failure::NotANumber
                                                 : Failure::None;
    failAtStep_ = static_cast<long>(method.number("failAtStep"));
    step_ = 0;
    stepSize_ = double(scene.simulation.timeStepSize);
    state_ = State{};
    for (const pbd::RigidBodyDesc& body : scene.rigidBodies)
      state_.bodies.push_back(
          {body.id, body.initialCenterOfMass(), body.rotation, Vector3::Zero(), Vector3::Zero()});
  }

  void step() override {
    ++step_;
    state_.time = double(step_) * stepSize_;
    if (step_ < failAtStep_) return;
    switch (failure_) {
      case Failure::None:
        break;
      case Failure::Crash:
        std::raise(SIGSEGV);
        break;
      case Failure::Hang:
        for (;;)
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
      case Failure::Throw:
        throw EngineError("selftest engine: deliberate failure at step " + std::to_string(step_));
      case Failure::NotANumber:
        if (!state_.bodies.empty())
          state_.bodies[0].position.x() = std::numeric_limits<Real>::quiet_NaN();
        break;
    }
  }

  void read(State& state) const override { state = state_; }

 private:
  Failure failure_ = Failure::None;
  long failAtStep_ = 10;
  long step_ = 0;
  double stepSize_ = 0;
  State state_;
};

std::vector<MethodInfo> selftestMethods() {
  const MethodParameter failAt{"failAtStep", "10", "the step at which the method misbehaves"};
  return {{"selftest.ok", "selftest", "keeps every body at its initial pose", {failAt}},
          {"selftest.crash", "selftest", "raises SIGSEGV", {failAt}},
          {"selftest.hang", "selftest", "never returns from step()", {failAt}},
          {"selftest.throw", "selftest", "throws an EngineError", {failAt}},
          {"selftest.nan", "selftest", "reports a NaN position", {failAt}}};
}

}  // namespace

EngineEntry selftestEngineEntry() {
  return {"selftest", "selftest.ok", &selftestMethods,
          [] { return std::unique_ptr<Engine>(new SelftestEngine()); }, true};
}

}  // namespace pbdval
