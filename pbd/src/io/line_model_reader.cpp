// LineModels[] (pbdval's extension; the seed builds its Cosserat rods in code): a polyline of
// `points` or a `helix`, static particles and segments, and either the seed's PBD rod (rod_*
// fractions of the Simulation block) or the XPBD rod with physical moduli. Rod particles are
// appended after every triangle- and tet-model particle (model/scene.h, appendLineModel).
#include <stdexcept>

#include "scene_reading.h"

namespace pbd::scene_io {
namespace {

struct HelixInput {
  Real radius = 0, pitch = 0, turns = 0;
  int points = 0;
  Vector3 center = Vector3::Zero();
};

KeyTable<HelixInput> helixKeys() {
  using H = HelixInput;
  return {
      required(numberKey("radius", &H::radius, positive())),
      required(numberKey("pitch", &H::pitch)),
      required(numberKey("turns", &H::turns, positive())),
      required(integerKey("points", &H::points, between(2, 1000000))),
      vectorKey("center", &H::center),
  };
}

KeyTable<LineModelDesc> lineModelKeys() {
  using L = LineModelDesc;
  return {
      integerKey("id", &L::id),
      {"staticParticles",
       [](const JsonValue& v, L& m) { m.staticParticles = v.integers(nonNegative()); }},
      {"staticSegments",
       [](const JsonValue& v, L& m) { m.staticSegments = v.integers(nonNegative()); }},
      numberKey("radius", &L::radius, positive()),
      numberKey("density", &L::density, positive()),
      numberKey("youngsModulus", &L::youngsModulus, positive()),
      numberKey("shearModulus", &L::shearModulus, positive()),
      numberKey("shearFactor", &L::shearFactor, between(1e-6, 10)),
  };
}

std::vector<Vector3> readPoints(JsonObject& object) {
  const auto points = object.find("points");
  const auto helix = object.find("helix");
  if (points && helix) helix->error("give either \"points\" or \"helix\", not both");
  if (!points && !helix)
    object.error("missing key \"points\" (an array of at least 2 [x, y, z]) or \"helix\"");
  if (points) {
    const std::vector<JsonValue> elements = points->elements("[x, y, z] points");
    if (elements.size() < 2) points->fail("at least 2 points");
    std::vector<Vector3> result;
    for (const JsonValue& e : elements)
      result.push_back(e.vector3());
    return result;
  }
  JsonObject helixObject = helix->object();
  HelixInput in;
  readKeys(helixObject, helixKeys(), in);
  helixObject.warnUnknownKeys();
  return helixPoints(in.radius, in.pitch, in.turns, in.points - 1, in.center);
}

void checkIndices(JsonObject& object, const char* key, const std::vector<int>& indices,
                  std::size_t count, const char* what) {
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (static_cast<std::size_t>(indices[i]) >= count)
      object.find(key)->elements(std::string(what) + " indices")[i].fail(
          std::string("a ") + what + " index in [0, " + std::to_string(count - 1) +
          "] (the model has " + std::to_string(count) + " " + what + "s)");
}

void checkMaterial(JsonObject& object, const LineModelDesc& model) {
  if (model.youngsModulus.has_value() != model.shearModulus.has_value()) {
    const char* given = model.youngsModulus ? "youngsModulus" : "shearModulus";
    object.find(given)->error(
        "\"youngsModulus\" and \"shearModulus\" go together (both: the XPBD rod with physical "
        "moduli; neither: the seed's PBD rod with the Simulation block's rod_* fractions)");
  }
  if (!model.radius) {
    for (const char* key : {"density", "youngsModulus"})
      if (auto value = object.find(key))
        value->error(std::string("\"") + key + "\" needs the rod's \"radius\" (m)");
  }
  if (object.has("shearFactor") && !model.usesModuli())
    object.find("shearFactor")
        ->warn("ignored: only the XPBD rod (youngsModulus and shearModulus) has shear rows in N");
}

LineModelDesc readLineModel(const JsonValue& element) {
  JsonObject object = element.object();
  LineModelDesc model;
  model.jsonPath = element.path();
  readKeys(object, lineModelKeys(), model);
  model.points = readPoints(object);
  checkMaterial(object, model);
  checkIndices(object, "staticParticles", model.staticParticles, model.points.size(), "point");
  checkIndices(object, "staticSegments", model.staticSegments, model.points.size() - 1, "segment");
  try {
    model.frames = lineModelFrames(model.points);
  } catch (const std::invalid_argument& e) {
    (object.has("points") ? *object.find("points") : *object.find("helix")).error(e.what());
  }
  object.warnUnknownKeys();
  return model;
}

}  // namespace

void readLineModels(const JsonValue& block, Scene& scene) {
  for (const JsonValue& element : block.elements("line-model objects"))
    appendLineModel(scene, readLineModel(element));
}

void warnUnusedRodSettings(JsonObject& root, const Scene& scene) {
  if (!scene.lineModels.empty()) return;
  const auto simulation = root.find("Simulation");
  if (!simulation || !simulation->isObject()) return;
  JsonObject object = simulation->object();
  for (const char* key :
       {"rod_stretchingStiffness", "rod_shearingStiffnessX", "rod_shearingStiffnessY",
        "rod_bendingStiffnessX", "rod_bendingStiffnessY", "rod_twistingStiffness"})
    if (auto value = object.find(key))
      value->warn(
          "ignored: the scene has no LineModels (the rod_* fractions apply to the PBD "
          "variant of Cosserat rods only)");
}

}  // namespace pbd::scene_io
