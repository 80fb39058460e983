// Surface meshes of a run written at a frame rate (the seed's exportOBJ, exportPLY, exportFPS;
// `pbdval simulate --export-dir`, docs/cli.md#mesh-export). From the states read back and the
// Scene, for every engine alike:
//   rigid bodies  the scene-frame mesh placed by the body's pose: x = p + R (v − c), p the centre
//                 of mass read back, R the scene frame's rotation, c the centre of mass in the
//                 scene frame (bodies without a mesh, primitives, are skipped with a note);
//   cloth         the triangle model's triangles over its particles;
//   solids        the visual mesh (visFile) carried by the tets through barycentric coordinates
//                 taken at t = 0, else the tet mesh's boundary faces.
// Frame k is the first state at or after t = k / fps; files are <dir>/<name>_<k:05>.<obj|ply>
// with name body<id>, cloth<i> or solid<i> (i: the model's place in the scene).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "pbd/model/mesh.h"

namespace pbdval {

struct MeshExportOptions {
  std::string directory;
  bool obj = false;
  bool ply = false;
  double framesPerSecond = 25;
};

class MeshExporter {
 public:
  /// Creates the directory (and its parents). Throws std::invalid_argument for a frame rate that
  /// is not positive and finite or no format, std::runtime_error naming the directory when it
  /// cannot be created.
  MeshExporter(const pbd::Scene& scene, MeshExportOptions options);

  /// Writes the frames whose time has come with `state`.
  void onState(const State& state);

  std::size_t frames() const { return frames_; }
  std::size_t files() const { return files_; }
  /// What was left out and why (bodies without a mesh, solids that could not attach).
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  enum class Kind { Body, Particles, Attached };
  struct Surface {
    std::string name;
    Kind kind = Kind::Particles;
    std::size_t body = 0;                           ///< Body: index in State::bodies
    std::shared_ptr<const pbd::TriangleMesh> mesh;  ///< Body: the scene-frame mesh
    Vector3 centerOfMass = Vector3::Zero();         ///< Body: in the scene frame
    std::vector<int> particles;                     ///< Particles: vertex → particle
    std::vector<std::array<int, 4>> carriers;       ///< Attached: vertex → the tet's particles
    std::vector<std::array<double, 4>> weights;     ///< Attached: vertex → barycentric weights
    std::vector<std::array<int, 3>> triangles;
  };

  std::vector<Vector3> vertices(const Surface& surface, const State& state) const;
  void writeFrame(const State& state);

  MeshExportOptions options_;
  std::vector<Surface> surfaces_;
  std::vector<std::string> notes_;
  std::size_t nextFrame_ = 0;
  std::size_t frames_ = 0;
  std::size_t files_ = 0;
};

}  // namespace pbdval
