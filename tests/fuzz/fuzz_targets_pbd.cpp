#include <nlohmann/json.hpp>

#include "fuzz_support.h"
#include "fuzz_targets.h"
#include "pbd/io/mesh_loader.h"
#include "pbd/io/scene_loader.h"

namespace pbdval::fuzz {

std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

void expectPrintable(const char* message) {
  try {
    (void)nlohmann::json(std::string(message)).dump();
  } catch (const nlohmann::json::type_error&) {
    std::fprintf(stderr, "error message is not valid UTF-8: %s\n", message);
    std::abort();
  }
}

void sceneTarget(const std::uint8_t* data, std::size_t size) {
  try {
    const pbd::LoadedScene loaded = pbd::parseScene(text(data, size), kSceneName);
    for (const pbd::SceneDiagnostic& warning : loaded.warnings)
      expectPrintable(warning.text().c_str());
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
  }
}

void objTarget(const std::uint8_t* data, std::size_t size) {
  try {
    (void)pbd::parseObj(text(data, size), "fuzz.obj");
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
  }
}

void tetGenTarget(const std::uint8_t* data, std::size_t size) {
  const std::string all = text(data, size);
  const std::string separator = "\n===\n";
  const std::size_t split = all.find(separator);
  const std::string node = split == std::string::npos ? all : all.substr(0, split);
  const std::string ele = split == std::string::npos ? "" : all.substr(split + separator.size());
  try {
    (void)pbd::parseTetGen(node, ele, "fuzz.node", "fuzz.ele");
  } catch (const pbd::SceneError& e) {
    expectPrintable(e.what());
  }
}

}  // namespace pbdval::fuzz
