#include "adapters/registry.h"

#include <stdexcept>

#include "pbd/io/suggestion.h"

namespace pbdval {

EngineRegistry::EngineRegistry(EngineOptions options) : options_(std::move(options)) {}

void EngineRegistry::add(EngineEntry entry) {
  for (const EngineEntry& e : entries_)
    if (e.name == entry.name)
      throw std::invalid_argument("engine '" + entry.name + "' is registered twice");
  for (const MethodInfo& m : entry.methods) {
    for (const EngineEntry& e : entries_)
      for (const MethodInfo& other : e.methods)
        if (other.name == m.name)
          throw std::invalid_argument("method '" + m.name + "' of engine " + entry.name +
                                      " is already a method of engine " + e.name);
    for (const ParameterSpec& p : m.parameters)
      parseParameter(p, p.defaultValue, m.name);
  }
  bool hasDefault = false;
  for (const MethodInfo& m : entry.methods)
    hasDefault = hasDefault || m.name == entry.defaultMethod;
  if (!hasDefault)
    throw std::invalid_argument("engine " + entry.name + ": default method '" +
                                entry.defaultMethod + "' is not one of its methods");
  for (const std::string& run : entry.runMethods) {
    bool known = false;
    for (const MethodInfo& m : entry.methods)
      known = known || m.name == run;
    if (!known)
      throw std::invalid_argument("engine " + entry.name + ": run method '" + run +
                                  "' is not one of its methods");
  }
  entries_.push_back(std::move(entry));
}

std::vector<std::string> EngineRegistry::runMethods(const std::string& name) const {
  const EngineEntry& entry = engine(name);
  return entry.runMethods.empty() ? std::vector<std::string>{entry.defaultMethod}
                                  : entry.runMethods;
}

std::vector<std::string> EngineRegistry::engineNames() const {
  std::vector<std::string> names;
  for (const EngineEntry& e : entries_)
    names.push_back(e.name);
  return names;
}

std::vector<std::string> EngineRegistry::defaultEngineNames() const {
  std::vector<std::string> names;
  for (const EngineEntry& e : entries_)
    if (e.runByDefault) names.push_back(e.name);
  return names;
}

const EngineEntry& EngineRegistry::engine(const std::string& name) const {
  for (const EngineEntry& e : entries_)
    if (e.name == name) return e;
  const std::vector<std::string> known = engineNames();
  throw std::invalid_argument("unknown engine '" + name + "' (known: " + pbd::nameList(known) +
                              ")" + pbd::didYouMean(name, known));
}

const MethodInfo& EngineRegistry::method(const std::string& name) const {
  std::vector<std::string> known;
  for (const EngineEntry& e : entries_)
    for (const MethodInfo& m : e.methods) {
      if (m.name == name) return m;
      known.push_back(m.name);
    }
  throw std::invalid_argument("unknown method '" + name + "' (known: " + pbd::nameList(known) +
                              ")" + pbd::didYouMean(name, known));
}

Method EngineRegistry::resolve(const std::string& name,
                               const std::map<std::string, std::string>& overrides) const {
  return resolveMethod(method(name), overrides);
}

std::unique_ptr<Engine> EngineRegistry::make(const std::string& name) const {
  return engine(name).make(options_);
}

std::unique_ptr<SteppingEngine> EngineRegistry::makeStepping(const std::string& name) const {
  std::unique_ptr<Engine> made = make(name);
  if (auto* stepping = dynamic_cast<SteppingEngine*>(made.get())) {
    made.release();
    return std::unique_ptr<SteppingEngine>(stepping);
  }
  throw std::invalid_argument("engine " + name +
                              " runs in another process and cannot be stepped one step at a time: "
                              "run it whole (pbdval simulate, pbdval.simulate, pbdval run)");
}

EngineRegistry EngineRegistry::withOptions(EngineOptions options) const {
  EngineRegistry copy = *this;
  copy.options_ = std::move(options);
  return copy;
}

}  // namespace pbdval
