// Writes a Scene back in the seed's JSON format (docs/scene-format.md#writing-a-scene): every
// key the loader reads, from the same key tables where there is one (a row reads its key and
// writes it back), so that loading the text gives the same Scene.
#pragma once

#include <string>

#include "pbd/model/scene.h"

namespace pbd {

/// The scene as JSON text. Loading it (parseScene with any source path: file paths are written
/// absolute, as the loader resolved them) gives back `scene`: every value bit for bit, except
/// the unit axes of joints, which the loader normalises again (a few ulp). Numbers are written
/// in the shortest form that reads back exactly. Rotations are written as the file gave them
/// (RigidBodyDesc::givenRotation), `mass` and `inertia` only where the file gave them.
std::string writeSceneJson(const Scene& scene);

}  // namespace pbd
