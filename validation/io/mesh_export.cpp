#include "validation/io/mesh_export.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "pbd/io/mesh_writer.h"
#include "validation/io/atomic_file.h"

namespace pbdval {

MeshExporter::MeshExporter(const pbd::Scene& scene, MeshExportOptions options)
    : options_(std::move(options)) {
  if (!(options_.framesPerSecond > 0) || !std::isfinite(options_.framesPerSecond))
    throw std::invalid_argument("mesh export: the frame rate must be positive, got " +
                                std::to_string(options_.framesPerSecond));
  if (!options_.obj && !options_.ply)
    throw std::invalid_argument("mesh export: no format (OBJ or PLY) chosen");
  createFolders(options_.directory);

  for (std::size_t b = 0; b < scene.rigidBodies.size(); ++b) {
    const pbd::RigidBodyDesc& body = scene.rigidBodies[b];
    if (!body.mesh) {
      notes_.push_back(body.jsonPath + " (id " + std::to_string(body.id) +
                       "): no mesh file, not exported");
      continue;
    }
    Surface s;
    s.name = "body" + std::to_string(body.id);
    s.kind = Kind::Body;
    s.body = b;
    s.mesh = body.mesh;
    s.centerOfMass = body.massProperties.centerOfMass;
    s.triangles = body.mesh->triangles;
    surfaces_.push_back(std::move(s));
  }
  for (std::size_t m = 0; m < scene.triangleModels.size(); ++m) {
    const pbd::TriangleModelDesc& model = scene.triangleModels[m];
    Surface s;
    s.name = "cloth" + std::to_string(m);
    for (std::size_t v = 0; v < model.mesh.vertices.size(); ++v)
      s.particles.push_back(model.firstParticle + int(v));
    s.triangles = model.mesh.triangles;
    surfaces_.push_back(std::move(s));
  }
  for (std::size_t m = 0; m < scene.tetModels.size(); ++m) {
    const pbd::TetModelDesc& model = scene.tetModels[m];
    Surface s;
    s.name = "solid" + std::to_string(m);
    if (model.visMesh) {
      const std::vector<pbd::BarycentricAttachment> attached =
          pbd::attachToTets(model.mesh, model.visMesh->vertices);
      if (attached.empty() && !model.visMesh->vertices.empty()) {
        notes_.push_back(model.jsonPath +
                         ": the visual mesh cannot attach (no tet of positive "
                         "volume); its boundary faces are exported instead");
      } else {
        s.kind = Kind::Attached;
        for (const pbd::BarycentricAttachment& a : attached) {
          const auto& tet = model.mesh.tetrahedra[std::size_t(a.tet)];
          s.carriers.push_back({model.firstParticle + tet[0], model.firstParticle + tet[1],
                                model.firstParticle + tet[2], model.firstParticle + tet[3]});
          s.weights.push_back({double(a.weights[0]), double(a.weights[1]), double(a.weights[2]),
                               double(a.weights[3])});
        }
        s.triangles = model.visMesh->triangles;
        surfaces_.push_back(std::move(s));
        continue;
      }
    }
    for (std::size_t v = 0; v < model.mesh.vertices.size(); ++v)
      s.particles.push_back(model.firstParticle + int(v));
    s.triangles = pbd::boundaryFaces(model.mesh);
    surfaces_.push_back(std::move(s));
  }
}

std::vector<Vector3> MeshExporter::vertices(const Surface& surface, const State& state) const {
  std::vector<Vector3> out;
  switch (surface.kind) {
    case Kind::Body: {
      const BodyState& body = state.bodies.at(surface.body);
      const Vector3 origin = body.position - body.rotation * surface.centerOfMass;
      for (const Vector3& v : surface.mesh->vertices)
        out.push_back(origin + body.rotation * v);
      break;
    }
    case Kind::Particles:
      for (int p : surface.particles)
        out.push_back(state.particles.at(std::size_t(p)).position);
      break;
    case Kind::Attached:
      for (std::size_t v = 0; v < surface.carriers.size(); ++v) {
        Vector3 x = Vector3::Zero();
        for (std::size_t i = 0; i < 4; ++i)
          x += surface.weights[v][i] *
               state.particles.at(std::size_t(surface.carriers[v][i])).position;
        out.push_back(x);
      }
      break;
  }
  return out;
}

void MeshExporter::writeFrame(const State& state) {
  char frame[16];
  std::snprintf(frame, sizeof frame, "%05zu", nextFrame_);
  for (const Surface& surface : surfaces_) {
    if (surface.kind != Kind::Body && state.particles.empty()) continue;  // not read back
    const std::vector<Vector3> positions = vertices(surface, state);
    const std::string stem = options_.directory + "/" + surface.name + "_" + frame;
    if (options_.obj) {
      OutputFile file(stem + ".obj");
      pbd::writeObj(file.stream(), positions, surface.triangles);
      file.commit();
      ++files_;
    }
    if (options_.ply) {
      OutputFile file(stem + ".ply");
      pbd::writePly(file.stream(), positions, surface.triangles);
      file.commit();
      ++files_;
    }
  }
  ++frames_;
}

void MeshExporter::onState(const State& state) {
  const double frameTime = double(nextFrame_) / options_.framesPerSecond;
  if (state.time < frameTime - 1e-9 * std::max(1.0, std::abs(frameTime))) return;
  writeFrame(state);
  // The next frame is the first one after this state's time.
  nextFrame_ = std::size_t(std::floor(state.time * options_.framesPerSecond + 1e-9)) + 1;
}

}  // namespace pbdval
