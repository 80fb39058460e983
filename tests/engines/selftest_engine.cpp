#include "engines/selftest_engine.h"

#include <chrono>
#include <csignal>
#include <limits>
#include <thread>

#include "adapters/built_in_engines.h"

namespace pbdval {
namespace {

enum class Failure { None, Crash, Hang, Throw, NotANumber };

class SelftestEngine final : public SteppingEngine {
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
    failAtStep_ = static_cast<long>(method.integer("failAtStep"));
    contactMargin_ = method.real("contactMargin");
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

  RunFacts runFacts() const override {
    RunFacts facts;
    facts.engineVersion = "selftest";
    facts.contactMargin = contactMargin_;
    return facts;
  }

 private:
  Failure failure_ = Failure::None;
  long failAtStep_ = 10;
  double contactMargin_ = 0;
  long step_ = 0;
  double stepSize_ = 0;
  State state_;
};

std::vector<MethodInfo> selftestMethods() {
  const std::vector<ParameterSpec> parameters = {
      integerParameter("failAtStep", 10, 1, 1e9, "the step at which the method misbehaves"),
      realParameter("contactMargin", 0, 0, 1, "m",
                    "the contact margin the engine reports in its run facts")};
  return {{"selftest.ok", "selftest", "keeps every body at its initial pose", parameters},
          {"selftest.crash", "selftest", "raises SIGSEGV", parameters},
          {"selftest.hang", "selftest", "never returns from step()", parameters},
          {"selftest.throw", "selftest", "throws an EngineError", parameters},
          {"selftest.nan", "selftest", "reports a NaN position", parameters}};
}

}  // namespace

EngineEntry selftestEngineEntry() {
  EngineEntry entry;
  entry.name = "selftest";
  entry.defaultMethod = "selftest.ok";
  entry.methods = selftestMethods();
  entry.honouredSettings = {"timeStepSize"};
  entry.runByDefault = false;  // run by name only
  entry.make = [](const EngineOptions&) { return std::unique_ptr<Engine>(new SelftestEngine()); };
  return entry;
}

EngineRegistry testEngines(const EngineOptions& options) {
  EngineRegistry registry = builtInEngines(options);
  registry.add(selftestEngineEntry());
  return registry;
}

const EngineRegistry& testRegistry() {
  static const EngineRegistry registry = testEngines();
  return registry;
}

}  // namespace pbdval
