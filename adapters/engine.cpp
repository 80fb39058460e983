#include "adapters/engine.h"

#include <cstdlib>
#include <sstream>

#include "adapters/registry.h"

namespace pbdval {

double Method::number(const std::string& parameter) const {
  const std::string& value = text(parameter);
  char* end = nullptr;
  const double result = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size())
    throw std::invalid_argument("method " + name + ": parameter " + parameter +
                                " must be a number, got '" + value + "'");
  return result;
}

const std::string& Method::text(const std::string& parameter) const {
  const auto it = parameters.find(parameter);
  if (it == parameters.end())
    throw std::invalid_argument("method " + name + " has no parameter '" + parameter + "'");
  return it->second;
}

const std::vector<MethodInfo>& methodCatalog() {
  static const std::vector<MethodInfo> catalog = [] {
    std::vector<MethodInfo> all;
    for (const EngineEntry& entry : engineEntries())
      for (MethodInfo& m : entry.methods())
        all.push_back(std::move(m));
    return all;
  }();
  return catalog;
}

const MethodInfo& findMethod(const std::string& name) {
  for (const MethodInfo& m : methodCatalog())
    if (m.name == name) return m;
  std::ostringstream known;
  for (const MethodInfo& m : methodCatalog())
    known << (known.tellp() > 0 ? ", " : "") << m.name;
  throw std::invalid_argument("unknown method '" + name + "' (known: " + known.str() + ")");
}

std::string defaultMethod(const std::string& engine) {
  for (const EngineEntry& entry : engineEntries())
    if (entry.name == engine) return entry.defaultMethod;
  throw std::invalid_argument("unknown engine '" + engine + "'");
}

std::vector<std::string> engineNames() {
  std::vector<std::string> names;
  for (const EngineEntry& entry : engineEntries())
    if (!entry.hidden) names.push_back(entry.name);
  return names;
}

Method resolveMethod(const std::string& name, const std::map<std::string, std::string>& overrides) {
  const MethodInfo& info = findMethod(name);
  Method method;
  method.name = name;
  for (const MethodParameter& p : info.parameters)
    method.parameters[p.name] = p.defaultValue;
  for (const auto& [key, value] : overrides) {
    if (method.parameters.count(key) == 0) {
      std::ostringstream valid;
      for (const MethodParameter& p : info.parameters)
        valid << (valid.tellp() > 0 ? ", " : "") << p.name;
      throw std::invalid_argument(
          "method " + name + " has no parameter '" + key +
          "' (parameters: " + (info.parameters.empty() ? "none" : valid.str()) + ")");
    }
    method.parameters[key] = value;
  }
  return method;
}

std::unique_ptr<Engine> makeEngine(const std::string& engine) {
  for (const EngineEntry& entry : engineEntries())
    if (entry.name == engine) return entry.make();
  throw std::invalid_argument("unknown engine '" + engine + "'");
}

}  // namespace pbdval
