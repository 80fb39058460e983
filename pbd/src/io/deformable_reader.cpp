// TriangleModels[] and TetModels[]: meshes transformed to the world, and one particle per
// vertex (triangle models first, then tet models, in file order), of mass 1 as in the seed or,
// with the model's `density`, lumped from the element areas or volumes; 0 when listed in
// `staticParticles`.
#include <cmath>

#include "pbd/model/mass_properties.h"
#include "scene_reading.h"

namespace pbd::scene_io {
namespace {

/// The keys triangle and tet models share besides the pose.
template <class Model>
KeyTable<Model> commonModelKeys() {
  return {
      integerKey("id", &Model::id),
      {"staticParticles",
       [](const JsonValue& v, Model& m) { m.staticParticles = v.integers(nonNegative()); }},
      numberKey("restitution", &Model::restitution, between(0, 1)),
      numberKey("friction", &Model::friction, nonNegative()),
      numberKey("density", &Model::density, positive()),
  };
}

void checkStaticParticles(const std::vector<int>& indices, std::size_t vertexCount,
                          JsonObject& object) {
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (static_cast<std::size_t>(indices[i]) >= vertexCount) {
      object.find("staticParticles")
          ->elements("vertex indices")[i]
          .fail("a vertex index in [0, " + std::to_string(vertexCount - 1) + "] (the model has " +
                std::to_string(vertexCount) + " vertices)");
    }
  }
}

/// Appends one particle per vertex: mass 1 (the seed's rule) or, with a density, the lumped
/// masses of the elements; returns the index of the first. With a density, a vertex in no
/// element is an error (its mass would be 0: static without being listed as such).
template <class Mesh>
int appendParticles(const Mesh& mesh, const std::optional<Real>& density,
                    const std::vector<int>& staticParticles, JsonObject& object, Scene& scene) {
  std::vector<Real> masses(mesh.vertices.size(), Real(1));
  if (density) {
    masses = lumpedMasses(mesh, *density);
    for (std::size_t i = 0; i < masses.size(); ++i)
      if (!(masses[i] > 0))
        object.find("density")->error(
            "vertex " + std::to_string(i) +
            " is in no element of positive size, so a density gives it no mass; remove the "
            "vertex from the mesh or leave \"density\" out (every vertex then has mass 1, as in "
            "the seed)");
  }
  const std::size_t first = scene.particles.size();
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    ParticleDesc particle;  // at rest
    particle.position = mesh.vertices[i];
    particle.mass = masses[i];
    scene.particles.push_back(particle);
  }
  for (int index : staticParticles)
    scene.particles[first + static_cast<std::size_t>(index)].mass = 0;
  return static_cast<int>(first);
}

/// The diagonal of the vertices' bounding box (the model's size L).
Real boundingDiagonal(const std::vector<Vector3>& vertices) {
  if (vertices.empty()) return 0;
  Vector3 low = vertices.front(), high = vertices.front();
  for (const Vector3& v : vertices) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  return (high - low).norm();
}

/// Fails at `fileKey` for the first triangle whose area is below kDegenerateElementFraction L².
void checkTriangleAreas(const TriangleMesh& mesh, const JsonValue& fileKey) {
  const Real size = boundingDiagonal(mesh.vertices);
  const Real minimum = Real(kDegenerateElementFraction) * size * size;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& e = mesh.triangles[t];
    const Vector3& a = mesh.vertices[static_cast<std::size_t>(e[0])];
    const Real area = Real(0.5) * (mesh.vertices[static_cast<std::size_t>(e[1])] - a)
                                      .cross(mesh.vertices[static_cast<std::size_t>(e[2])] - a)
                                      .norm();
    if (!(area >= minimum)) {
      fileKey.error("triangle " + std::to_string(t) + " (vertices " + std::to_string(e[0]) + ", " +
                    std::to_string(e[1]) + ", " + std::to_string(e[2]) + ") has area " +
                    formatNumber(area) + " m^2; expected at least 1e-12 L^2 = " +
                    formatNumber(minimum) + " m^2 (L = " + formatNumber(size) +
                    " m, the model's bounding-box diagonal): a degenerate triangle has no "
                    "normal and no strain; remove it from the mesh");
    }
  }
}

/// Fails at `fileKey` for the first tet whose |volume| is below kDegenerateElementFraction L³.
void checkTetVolumes(const TetMesh& mesh, const JsonValue& fileKey) {
  const Real size = boundingDiagonal(mesh.vertices);
  const Real minimum = Real(kDegenerateElementFraction) * size * size * size;
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t) {
    const auto& e = mesh.tetrahedra[t];
    const auto vertex = [&](int k) -> const Vector3& {
      return mesh.vertices[static_cast<std::size_t>(e[static_cast<std::size_t>(k)])];
    };
    const Real volume =
        (vertex(1) - vertex(0)).cross(vertex(2) - vertex(0)).dot(vertex(3) - vertex(0)) / 6;
    if (!(std::abs(volume) >= minimum)) {
      fileKey.error("tet " + std::to_string(t) + " (vertices " + std::to_string(e[0]) + ", " +
                    std::to_string(e[1]) + ", " + std::to_string(e[2]) + ", " +
                    std::to_string(e[3]) + ") has volume " + formatNumber(volume) +
                    " m^3; expected |volume| at least 1e-12 L^3 = " + formatNumber(minimum) +
                    " m^3 (L = " + formatNumber(size) +
                    " m, the model's bounding-box diagonal): a flat tet has no volume gradient "
                    "for its constraints; remove it from the mesh");
    }
  }
}

struct TriangleModelInput {
  TriangleModelDesc desc;
  PoseInput pose;
};

TriangleModelDesc readTriangleModel(const JsonValue& element, LoadContext& context, Scene& scene) {
  JsonObject object = element.object();
  TriangleModelInput in;
  TriangleModelDesc& model = in.desc;
  model.jsonPath = element.path();
  KeyTable<TriangleModelDesc> keys = commonModelKeys<TriangleModelDesc>();
  keys.push_back(required(KeyReader<TriangleModelDesc>{
      "geometryFile", [&context](const JsonValue& v, TriangleModelDesc& m) {
        m.geometryFile = context.existingFile(v);
      }}));
  readKeys(object, keys, model);
  readKeys(object, poseKeys(), in.pose);

  model.translation = in.pose.translation;
  model.scale = in.pose.scale;
  model.rotation = resolveRotation(in.pose, object);
  model.givenRotation = givenRotation(in.pose);
  model.mesh =
      *context.scaledObj(model.geometryFile, Vector3::Ones(), *object.find("geometryFile"));
  for (auto& v : model.mesh.vertices)
    v = toWorld(v, model.scale, model.rotation, model.translation);
  checkTriangleAreas(model.mesh, *object.find("geometryFile"));
  checkStaticParticles(model.staticParticles, model.mesh.vertices.size(), object);
  model.firstParticle =
      appendParticles(model.mesh, model.density, model.staticParticles, object, scene);
  object.warnUnknownKeys();
  return model;
}

struct TetModelInput {
  TetModelDesc desc;
  PoseInput pose;
};

KeyTable<TetModelDesc> tetFileKeys(const LoadContext& context) {
  using T = TetModelDesc;
  return {
      required(KeyReader<T>{
          "nodeFile",
          [&context](const JsonValue& v, T& m) { m.nodeFile = context.existingFile(v); }}),
      required(KeyReader<T>{"eleFile", [&context](const JsonValue& v,
                                                  T& m) { m.eleFile = context.existingFile(v); }}),
      {"visFile",
       [&context](const JsonValue& v, T& m) {
         // Empty: no visual mesh (the seed's default). A missing file is a warning: the visual
         // mesh only follows the tets, and PositionBasedDynamics runs without it (its OBJ
         // loader logs the failure and leaves the mesh empty).
         m.visFile.clear();
         if (v.string().empty()) return;
         try {
           m.visFile = context.existingFile(v);
         } catch (const SceneError& e) {
           v.warn(std::string("ignored: ") + e.diagnostic().message +
                  "; the tet model is simulated without a visual mesh");
         }
       }},
  };
}

TetModelDesc readTetModel(const JsonValue& element, LoadContext& context, Scene& scene) {
  JsonObject object = element.object();
  TetModelInput in;
  TetModelDesc& model = in.desc;
  model.jsonPath = element.path();
  readKeys(object, tetFileKeys(context), model);
  readKeys(object, commonModelKeys<TetModelDesc>(), model);
  readKeys(object, poseKeys(), in.pose);
  readKeys(object, collisionKeys(context), model.collision);
  checkCollisionScale(model.collision, object);
  // A tet model's collision shape is never used (docs/contacts.md): tet–tet contacts use the
  // model's own boundary and no body is tested against a tet model's SDF. Only
  // collisionObjectType (0: always tested) and testMesh take effect.
  for (const char* key : {"collisionObjectFileName", "collisionObjectScale", "invertSDF",
                          "thicknessSDF", "resolutionSDF"})
    if (const auto value = object.find(key))
      value->warn(
          std::string("ignored for a tet model: its particle-tet contacts use the tet "
                      "mesh's own boundary, not a collision shape (only "
                      "collisionObjectType and testMesh take effect)"));

  model.translation = in.pose.translation;
  model.scale = in.pose.scale;
  model.rotation = resolveRotation(in.pose, object);
  model.givenRotation = givenRotation(in.pose);
  const auto place = [&model](Vector3& v) {
    v = toWorld(v, model.scale, model.rotation, model.translation);
  };
  model.mesh = context.tetGen(model.nodeFile, model.eleFile, *object.find("nodeFile"));
  for (auto& v : model.mesh.vertices)
    place(v);
  checkTetVolumes(model.mesh, *object.find("eleFile"));
  if (!model.visFile.empty()) {
    TriangleMesh visual =
        *context.scaledObj(model.visFile, Vector3::Ones(), *object.find("visFile"));
    for (auto& v : visual.vertices)
      place(v);
    model.visMesh = std::make_shared<const TriangleMesh>(std::move(visual));
  }
  checkStaticParticles(model.staticParticles, model.mesh.vertices.size(), object);
  model.firstParticle =
      appendParticles(model.mesh, model.density, model.staticParticles, object, scene);
  object.warnUnknownKeys();
  return model;
}

}  // namespace

void readTriangleModels(const JsonValue& block, LoadContext& context, Scene& scene) {
  for (const JsonValue& element : block.elements("triangle-model objects"))
    scene.triangleModels.push_back(readTriangleModel(element, context, scene));
}

void readTetModels(const JsonValue& block, LoadContext& context, Scene& scene) {
  for (const JsonValue& element : block.elements("tet-model objects"))
    scene.tetModels.push_back(readTetModel(element, context, scene));
}

}  // namespace pbd::scene_io
