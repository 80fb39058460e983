// The rigid part of a resolved scene (validation/external/resolved_scene.h) read back into a
// pbd::Scene: bodies (pose, principal frame, mass properties, velocities, collision shape, mesh),
// joints (type, bodies, anchors and axes in world coordinates at t = 0, stiffness, motor target),
// every contact pair's friction and restitution (as explicit pairs, so Scene::pairMaterial
// returns the resolved values whatever the combination rule), gravity and the step. It is the
// inverse of resolvedSceneJson for what an engine adapter reads of the rigid part: a scene
// written and read back gives the adapters the same numbers, bit for bit (the resolved scene's
// quaternions may have the opposite sign, which rotates the same way, bit for bit).
// Used to build the MuJoCo model of an external engine from the document it was given
// (pbdval._core._mujoco_mjcf; docs/external-engines.md#one-model-description).
// Particles, deformable models, rods and fluids are not read.
#pragma once

#include <nlohmann/json.hpp>

#include "pbd/model/scene.h"

namespace pbdval {

/// Throws std::invalid_argument "resolved scene: /bodies/2/pose/rotation: expected ..." for a
/// value that is missing or of the wrong kind, and for a joint or pair naming an unknown body.
/// A body's mesh (`geometry.file`) is read with the scene loader's OBJ reader.
pbd::Scene rigidSceneFromResolvedJson(const nlohmann::json& resolved);

}  // namespace pbdval
