#include "validation/external/engine_catalogue.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "pbd/io/number_text.h"
#include "validation/external/external_engine.h"
#include "validation/io/json_schema.h"
#include "validation/io/json_text.h"

namespace pbdval {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr const char* kSchemaName = "catalogue.schema.json";
// 2^53: every integer up to it is a double exactly.
constexpr double kLargestExactInteger = 9007199254740992.0;

/// A rule beyond the schema broken: "FILE: PATH: expected ..., got ..." (the schema
/// validator's form, with the file in front).
[[noreturn]] void fail(const std::string& file, const std::string& path, const Json& value,
                       const std::string& expected) {
  std::string got = jsonText(value, -1);
  if (got.size() > 60) got = got.substr(0, 57) + "...";
  throw std::invalid_argument(file + ": " + path + ": expected " + expected + ", got " + got);
}

std::string optionalText(const Json& object, const char* key) {
  return object.contains(key) ? object.at(key).get<std::string>() : std::string();
}

/// A parameter the schema has accepted (`$defs/parameter`: its kind, a default of that kind,
/// `choices` for a choice), its default then parsed by the registry's own parser.
ParameterSpec catalogueParameter(const Json& node, const std::string& path,
                                 const std::string& method, const std::string& file) {
  ParameterSpec p;
  p.name = node.at("name").get<std::string>();
  const std::string kind = node.at("kind").get<std::string>();
  const Json& value = node.at("default");
  if (kind == "real") {
    p.kind = ParameterKind::Real;
    p.defaultValue = pbd::formatReal(value.get<double>());
  } else if (kind == "integer") {
    p.kind = ParameterKind::Integer;
    // The schema's integer is mathematical (10.0 is one); as a float it must also be exact.
    if (value.is_number_float() && !(std::fabs(value.get<double>()) <= kLargestExactInteger))
      fail(file, path + ".default", value, "an integer of at most 2^53 in magnitude");
    p.defaultValue = std::to_string(value.get<std::int64_t>());
  } else if (kind == "bool") {
    p.kind = ParameterKind::Bool;
    p.defaultValue = value.get<bool>() ? "true" : "false";
  } else {  // "choice": the schema's enum admits no other kind
    p.kind = ParameterKind::Choice;
    p.defaultValue = value.get<std::string>();
    for (const Json& choice : node.at("choices"))
      p.choices.push_back(choice.get<std::string>());
  }
  if (node.contains("min")) p.minimum = node.at("min").get<double>();
  if (node.contains("max")) p.maximum = node.at("max").get<double>();
  p.unit = optionalText(node, "unit");
  p.description = optionalText(node, "description");
  try {
    parseParameter(p, p.defaultValue, method);
  } catch (const std::invalid_argument& e) {
    fail(file, path + ".default", value,
         std::string("a default within its own declaration (") + e.what() + ")");
  }
  return p;
}

/// The feature table (adapters/features.h; docs/external-engines.md#features), each entry
/// typed by the schema, then the table as a whole checked by the function the built-in
/// engines' tables go through (each problem named by its JSON path).
FeatureTable catalogueFeatures(const Json& node, const std::vector<std::string>& methods,
                               const std::string& file) {
  FeatureTable table;
  for (const Json& e : node) {
    FeatureSupport support;
    support.key = e.at("feature").get<std::string>();
    support.support = supportNamed(e.at("support").get<std::string>());
    support.text = optionalText(e, "text");
    if (e.contains("methods"))
      for (const Json& method : e.at("methods"))
        support.methods.push_back(method.get<std::string>());
    table.entries.push_back(std::move(support));
  }
  const std::vector<std::string> problems = checkFeatureTable(table, methods);
  if (!problems.empty())
    // checkFeatureTable names entries "features[3]..." and the table "features: ...".
    throw std::invalid_argument(file + ": " + problems.front() +
                                (problems.size() > 1
                                     ? " (and " + std::to_string(problems.size() - 1) + " more)"
                                     : std::string()));
  return table;
}

/// A catalogue command (`command`, `serve.command`): "{python}" replaced, run in the catalogue's
/// folder (relative paths in it are relative to the catalogue file).
ExternalCommand catalogueCommand(const Json& argv, const ProjectPython& python,
                                 const std::string& folder) {
  ExternalCommand command;
  command.workingFolder = folder;
  for (const Json& item : argv) {
    std::string word = item.get<std::string>();
    if (word == "{python}") {
      word = python.interpreter;
      command.pythonPackageFolder = python.packageFolder;
    }
    command.argv.push_back(word);
  }
  return command;
}

EngineEntry catalogueEntry(const std::string& file, const ProjectPython& python,
                           SchemaChecker& schema) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const Json root = Json::parse(text.str(), nullptr, false);
  if (root.is_discarded()) throw std::invalid_argument(file + ": not valid JSON");
  const std::vector<std::string> violations = schema.violations(root);
  if (!violations.empty()) {
    std::string message;
    for (const std::string& v : violations)
      message += (message.empty() ? "" : "; ") + v;
    throw std::invalid_argument(file + ": " + message + " (docs/schemas/" + kSchemaName + ")");
  }
  // The keys, types and values are the schema's; what follows reads them and checks the rules
  // between them that a schema cannot state.
  EngineEntry entry;
  entry.name = root.at("name").get<std::string>();
  const std::string folder = fs::absolute(fs::path(file)).parent_path().lexically_normal().string();
  const ExternalCommand command = catalogueCommand(root.at("command"), python, folder);
  // A persistent process that serves many runs (docs/external-engines.md#persistent-engines).
  std::optional<ExternalCommand> serve;
  if (root.contains("serve")) {
    serve = catalogueCommand(root.at("serve").at("command"), python, folder);
    // One child may serve several runs in turn (the engine rebuilds its world in each run).
    const std::int64_t runsPerChild = root.at("serve").value("runsPerChild", std::int64_t{1});
    if (runsPerChild > 1) {
      serve->argv.push_back("--runs-per-child");
      serve->argv.push_back(std::to_string(runsPerChild));
    }
  }
  entry.defaultMethod = root.at("defaultMethod").get<std::string>();
  const Json& methods = root.at("methods");
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const Json& m = methods.at(i);
    const std::string path = "methods[" + std::to_string(i) + "]";
    MethodInfo info;
    info.name = m.at("name").get<std::string>();
    if (info.name.rfind(entry.name + ".", 0) != 0)
      fail(file, path + ".name", m.at("name"), "a name starting with \"" + entry.name + ".\"");
    info.engine = entry.name;
    info.description = optionalText(m, "description");
    if (m.contains("parameters")) {
      const Json& parameters = m.at("parameters");
      for (std::size_t k = 0; k < parameters.size(); ++k)
        info.parameters.push_back(catalogueParameter(
            parameters.at(k), path + ".parameters[" + std::to_string(k) + "]", info.name, file));
    }
    entry.methods.push_back(std::move(info));
  }
  entry.honouredSettings = {"timeStepSize", "gravitation"};
  // The methods `pbdval run` uses when none is named (default: defaultMethod alone).
  if (root.contains("runMethods")) {
    const Json& list = root.at("runMethods");
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::string method = list.at(k).get<std::string>();
      const bool known = std::any_of(entry.methods.begin(), entry.methods.end(),
                                     [&](const MethodInfo& info) { return info.name == method; });
      if (!known)
        fail(file, "runMethods[" + std::to_string(k) + "]", list.at(k),
             "one of this entry's methods");
      entry.runMethods.push_back(method);
    }
  }
  if (root.contains("features")) {
    std::vector<std::string> methodNames;
    for (const MethodInfo& info : entry.methods)
      methodNames.push_back(info.name);
    entry.features = catalogueFeatures(root.at("features"), methodNames, file);
  }
  // Run by `pbdval run` without --engines unless an example or "runByDefault": false (an engine
  // too slow for the case library's routine run, docs/external-engines.md#the-catalogue); the
  // schema has checked that both are booleans.
  entry.runByDefault =
      root.value("runByDefault", true) && !(root.contains("example") && root.at("example") == true);
  const std::string name = entry.name;
  const FeatureTable features = entry.features;
  entry.make = [name, command, serve, features](const EngineOptions& options) {
    return std::unique_ptr<Engine>(
        new ExternalEngine(name, command, features, serve ? options.serverFolder : std::string()));
  };
  if (serve)
    entry.startServer = [name, serve](const std::string& serverFolder) {
      return launchExternalServer(name, *serve, serverFolder);
    };
  return entry;
}

}  // namespace

std::vector<EngineEntry> readEngineCatalogue(const std::string& folder,
                                             const ProjectPython& python) {
  std::vector<std::string> files;
  std::error_code error;
  for (const auto& item : fs::directory_iterator(folder, error))
    if (item.path().extension() == ".json") files.push_back(item.path().string());
  std::sort(files.begin(), files.end());
  std::vector<EngineEntry> entries;
  if (files.empty()) return entries;
  const Json schema = projectSchema(kSchemaName);
  SchemaChecker checker(schema);  // one for all the files: its patterns compiled once
  for (const std::string& file : files)
    entries.push_back(catalogueEntry(file, python, checker));
  return entries;
}

}  // namespace pbdval
