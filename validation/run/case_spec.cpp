#include "validation/run/case_spec.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>

#include "adapters/engine.h"
#include "pbd/io/input_checks.h"
#include "validation/io/trajectory.h"

namespace pbdval {
namespace {

using Json = nlohmann::json;

// A JSON node with its path, for located errors ("scene.json: Validation.checks[1].max: ...").
struct Node {
  const Json& json;
  std::string path;
  const std::string& file;

  [[noreturn]] void fail(const std::string& expected) const {
    std::string got = json.dump();
    if (got.size() > 60) got = got.substr(0, 57) + "...";
    // The file name may hold any bytes; the message must stay valid UTF-8 (results.json).
    throw std::invalid_argument(
        pbd::printableText(file + ": " + path + ": expected " + expected + ", got " + got));
  }
  // A required key or element that is missing is a located error, not nlohmann's out_of_range
  // (a check without "metric" ended the process: found by the case_spec fuzz target).
  Node at(const std::string& key) const {
    if (!json.is_object() || !json.contains(key))
      throw std::invalid_argument(pbd::printableText(file + ": " + path + "." + key) +
                                  ": missing (required)");
    return {json.at(key), path + "." + key, file};
  }
  Node at(std::size_t i) const {
    if (!json.is_array() || i >= json.size())
      throw std::invalid_argument(
          pbd::printableText(file + ": " + path + "[" + std::to_string(i) + "]") +
          ": missing (required)");
    return {json.at(i), path + "[" + std::to_string(i) + "]", file};
  }

  void requireObject(const std::set<std::string>& allowed) const {
    if (!json.is_object()) fail("an object");
    for (const auto& item : json.items())
      if (!allowed.count(item.key())) {
        std::string keys;
        for (const auto& k : allowed)
          keys += (keys.empty() ? "" : ", ") + k;
        throw std::invalid_argument(pbd::printableText(file + ": " + path + "." + item.key()) +
                                    ": unknown key (known: " + keys + ")");
      }
  }
  double positive() const {
    if (!json.is_number() || !std::isfinite(json.get<double>()) || !(json.get<double>() > 0))
      fail("a positive number");
    return json.get<double>();
  }
  double finite() const {
    if (!json.is_number() || !std::isfinite(json.get<double>())) fail("a finite number");
    return json.get<double>();
  }
  std::string text() const {
    if (!json.is_string()) fail("a string");
    return json.get<std::string>();
  }
  std::vector<std::string> texts() const {
    if (!json.is_array()) fail("an array of strings");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < json.size(); ++i)
      out.push_back(at(i).text());
    return out;
  }
  /// A number or a string, as text (sweep values).
  std::string value() const {
    if (json.is_string()) return json.get<std::string>();
    return formatNumber(finite());
  }
};

void checkEngineName(const Node& node, const EngineRegistry& registry) {
  const std::string name = node.text();
  const std::vector<std::string> known = registry.engineNames();
  if (std::find(known.begin(), known.end(), name) != known.end()) return;
  std::string list;
  for (const auto& e : known)
    list += (list.empty() ? "" : ", ") + e;
  node.fail("an engine (" + list + ")");
}

void checkMethodName(const Node& node, const EngineRegistry& registry) {
  try {
    registry.method(node.text());
  } catch (const std::invalid_argument& e) {
    node.fail(std::string("a method: ") + e.what());
  }
}

/// Reads an array of engine or method names, each checked.
std::vector<std::string> names(const Node& node, const EngineRegistry& registry,
                               void (*check)(const Node&, const EngineRegistry&)) {
  const std::vector<std::string> values = node.texts();
  for (std::size_t i = 0; i < values.size(); ++i)
    check(node.at(i), registry);
  return values;
}

ReferenceSpec parseReference(const Node& node, const pbd::Scene& scene,
                             const EngineRegistry& registry) {
  node.requireObject({"type", "model", "parameters", "bodies", "stepDivisor", "engine", "method"});
  ReferenceSpec r;
  const std::string type = node.at("type").text();
  if (type == "none") {
    r.kind = ReferenceSpec::Kind::None;
  } else if (type == "analytic") {
    r.kind = ReferenceSpec::Kind::Analytic;
    r.model = node.at("model").text();
    if (node.json.contains("parameters")) {
      const Node parameters = node.at("parameters");
      if (!parameters.json.is_object()) parameters.fail("an object");
      r.parametersJson = parameters.json.dump();
    }
    if (node.json.contains("bodies")) {
      const Node bodies = node.at("bodies");
      if (!bodies.json.is_array()) bodies.fail("an array of body ids");
      for (std::size_t i = 0; i < bodies.json.size(); ++i) {
        const Node id = bodies.at(i);
        if (!id.json.is_number_integer()) id.fail("a body id (integer)");
        const int bodyId = id.json.get<int>();
        const bool exists =
            std::any_of(scene.rigidBodies.begin(), scene.rigidBodies.end(),
                        [&](const pbd::RigidBodyDesc& b) { return b.id == bodyId; });
        if (!exists) id.fail("the id of a rigid body of the scene");
        r.bodyIds.push_back(bodyId);
      }
    }
  } else if (type == "fine") {
    r.kind = ReferenceSpec::Kind::Fine;
    if (node.json.contains("stepDivisor")) {
      const Node divisor = node.at("stepDivisor");
      if (!divisor.json.is_number_integer() || divisor.json.get<int>() < 2)
        divisor.fail("an integer ≥ 2");
      r.stepDivisor = divisor.json.get<int>();
    }
  } else if (type == "engine") {
    r.kind = ReferenceSpec::Kind::Engine;
    checkMethodName(node.at("method"), registry);
    r.method = node.at("method").text();
    r.engine = registry.method(r.method).engine;
    if (node.json.contains("stepDivisor")) {
      const Node divisor = node.at("stepDivisor");
      if (!divisor.json.is_number_integer() || divisor.json.get<int>() < 1)
        divisor.fail("an integer ≥ 1");
      r.stepDivisor = divisor.json.get<int>();
    } else {
      r.stepDivisor = 1;
    }
  } else {
    node.at("type").fail("\"analytic\", \"fine\", \"engine\" or \"none\"");
  }
  return r;
}

CheckSpec parseCheck(const Node& node, const EngineRegistry& registry) {
  node.requireObject(
      {"metric", "max", "min", "engines", "methods", "better", "worse", "description"});
  CheckSpec c;
  c.jsonPath = node.path;
  c.metric = node.at("metric").text();
  if (node.json.contains("max")) c.max = node.at("max").finite();
  if (node.json.contains("min")) c.min = node.at("min").finite();
  if (node.json.contains("engines"))
    c.engines = names(node.at("engines"), registry, checkEngineName);
  if (node.json.contains("methods"))
    c.methods = names(node.at("methods"), registry, checkMethodName);
  if (node.json.contains("better")) c.better = node.at("better").text();
  if (node.json.contains("worse")) c.worse = node.at("worse").text();
  if (node.json.contains("description")) c.description = node.at("description").text();
  const bool ordering = !c.better.empty() || !c.worse.empty();
  if (ordering && (c.better.empty() || c.worse.empty()))
    node.fail("both \"better\" and \"worse\" (an ordering check)");
  if (ordering) {
    checkMethodName(node.at("better"), registry);
    checkMethodName(node.at("worse"), registry);
  }
  if (!ordering && !c.max && !c.min) node.fail("\"max\", \"min\", or \"better\"/\"worse\"");
  return c;
}

SweepSpec parseSweep(const Node& node, const EngineRegistry& registry) {
  node.requireObject({"parameters", "methods", "metric"});
  SweepSpec s;
  const Node parameters = node.at("parameters");
  if (!parameters.json.is_object() || parameters.json.empty())
    parameters.fail("an object of parameter → array of values");
  for (const auto& item : parameters.json.items()) {
    const Node values = parameters.at(item.key());
    if (!values.json.is_array() || values.json.empty()) values.fail("a non-empty array of values");
    for (std::size_t i = 0; i < values.json.size(); ++i)
      s.parameters[item.key()].push_back(values.at(i).value());
  }
  if (node.json.contains("methods"))
    s.methods = names(node.at("methods"), registry, checkMethodName);
  if (node.json.contains("metric")) s.metric = node.at("metric").text();
  return s;
}

pbd::Vector3 vector3(const Node& node) {
  if (!node.json.is_array() || node.json.size() != 3) node.fail("an array of 3 numbers");
  return pbd::Vector3(pbd::Real(node.at(0).finite()), pbd::Real(node.at(1).finite()),
                      pbd::Real(node.at(2).finite()));
}

StaticDisplacementSpec parseStaticDisplacement(const Node& node, const pbd::Scene& scene,
                                               double duration) {
  node.requireObject({"region", "direction", "from", "expected", "description"});
  StaticDisplacementSpec d;
  d.jsonPath = node.path;
  const Node region = node.at("region");
  region.requireObject({"min", "max"});
  d.regionMin = vector3(region.at("min"));
  d.regionMax = vector3(region.at("max"));
  if (!(d.regionMin.array() <= d.regionMax.array()).all())
    region.fail("min ≤ max in every coordinate");
  for (std::size_t i = 0; i < scene.particles.size(); ++i) {
    const pbd::Vector3& x = scene.particles[i].position;
    if ((x.array() >= d.regionMin.array()).all() && (x.array() <= d.regionMax.array()).all())
      d.particles.push_back(int(i));
  }
  if (d.particles.empty())
    region.fail("a box holding at least one particle of the scene (" +
                std::to_string(scene.particles.size()) + " particles)");
  const Node direction = node.at("direction");
  d.direction = vector3(direction);
  if (!(d.direction.norm() > 0)) direction.fail("a non-zero vector");
  d.direction.normalize();
  const Node from = node.at("from");
  d.from = from.finite();
  if (d.from < 0 || d.from >= duration)
    from.fail("a time in [0, " + formatNumber(duration) + ") s (the case's duration)");
  const Node expected = node.at("expected");
  d.expected = expected.finite();
  if (d.expected == 0) expected.fail("a non-zero displacement (m)");
  if (node.json.contains("description")) d.description = node.at("description").text();
  return d;
}

}  // namespace

CaseSpec parseCaseSpec(const pbd::Scene& scene, const EngineRegistry& registry) {
  CaseSpec spec;
  if (scene.validationJson.empty()) return spec;
  const Json block = Json::parse(scene.validationJson);
  const Node root{block, "Validation", scene.sourceFile};
  root.requireObject({"schema", "description", "duration", "sampleInterval", "energyScale",
                      "conserved", "engines", "methods", "reference", "checks", "tolerances",
                      "sweeps", "staticDisplacement", "notes"});
  if (block.contains("schema")) {
    const Node schema = root.at("schema");
    if (!schema.json.is_number_integer() || schema.json.get<int>() != kValidationSchemaVersion)
      schema.fail("schema version " + std::to_string(kValidationSchemaVersion));
  }
  if (block.contains("description")) spec.description = root.at("description").text();
  // Notes for the reader (what an imported model lost, docs/models.md): strings, not read.
  if (block.contains("notes")) (void)root.at("notes").texts();
  if (block.contains("duration")) spec.duration = root.at("duration").positive();
  if (block.contains("sampleInterval")) spec.sampleInterval = root.at("sampleInterval").positive();
  if (block.contains("energyScale")) spec.energyScale = root.at("energyScale").positive();
  if (block.contains("conserved")) {
    const Node conserved = root.at("conserved");
    const std::vector<std::string> names = conserved.texts();
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (names[i] == "energy")
        spec.energyConserved = true;
      else if (names[i] == "linearMomentum")
        spec.linearMomentumConserved = true;
      else if (names[i] == "angularMomentum")
        spec.angularMomentumConserved = true;
      else
        conserved.at(i).fail("\"energy\", \"linearMomentum\" or \"angularMomentum\"");
    }
  }
  if (block.contains("engines"))
    spec.engines = names(root.at("engines"), registry, checkEngineName);
  if (block.contains("methods"))
    spec.methods = names(root.at("methods"), registry, checkMethodName);
  if (block.contains("reference"))
    spec.reference = parseReference(root.at("reference"), scene, registry);
  if (block.contains("checks")) {
    const Node checks = root.at("checks");
    if (!checks.json.is_array()) checks.fail("an array of checks");
    for (std::size_t i = 0; i < checks.json.size(); ++i)
      spec.checks.push_back(parseCheck(checks.at(i), registry));
  }
  if (block.contains("tolerances")) {
    const Node tolerances = root.at("tolerances");
    if (!tolerances.json.is_object()) tolerances.fail("an object of metric → tolerance");
    for (const auto& item : tolerances.json.items()) {
      const Node t = tolerances.at(item.key());
      if (!t.json.is_number() || !(t.json.get<double>() >= 0)) t.fail("a tolerance ≥ 0");
      spec.tolerances[item.key()] = t.json.get<double>();
    }
  }
  if (block.contains("sweeps")) {
    const Node sweeps = root.at("sweeps");
    if (!sweeps.json.is_array()) sweeps.fail("an array of sweeps");
    for (std::size_t i = 0; i < sweeps.json.size(); ++i)
      spec.sweeps.push_back(parseSweep(sweeps.at(i), registry));
  }
  if (block.contains("staticDisplacement"))
    spec.staticDisplacement =
        parseStaticDisplacement(root.at("staticDisplacement"), scene, defaultDuration(scene, spec));
  return spec;
}

double defaultDuration(const pbd::Scene& scene, const CaseSpec& spec) {
  if (spec.duration) return *spec.duration;
  if (scene.viewer.pauseAt > 0) return double(scene.viewer.pauseAt);
  return 5.0;
}

}  // namespace pbdval
