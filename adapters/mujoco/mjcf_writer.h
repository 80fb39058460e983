// The Scene as MJCF text (MuJoCo's XML), loaded through MuJoCo's virtual file system: nothing
// is written to disk.
//
// Frames: every MuJoCo body frame is the scene body's *principal frame* at t = 0 (origin at
// the centre of mass, axes along the principal axes), so `<inertial>` is the identity pose with
// the Scene's mass and principal moments, a free joint's qpos is the centre of mass, and the
// scene frame is recovered as q_scene = q_body ⊗ principalRotation⁻¹. Geoms, sites and joints
// are placed in that frame from the Scene's world data at t = 0.
//
// Shapes: sphere, box (half extents), cylinder (MuJoCo's axis is z, the seed's y: the geom is
// turned by −90° about x); SDF bodies collide as the convex hull of their mesh (MuJoCo always
// collides meshes as hulls). Torus, hollow shapes, inverted SDFs: unsupported.
//
// Contacts: every geom has contype = conaffinity = 0, so MuJoCo generates no contacts of its
// own; each pair of bodies with geoms (not both static) gets an explicit <pair> with the
// Scene's pair friction (condim 3: sliding only; condim 1 when μ = 0), margin = gap = 0 and
// the direct-format solref of contact_softness.h for the pair's restitution.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "adapters/mujoco/kinematic_tree.h"
#include "adapters/mujoco/mujoco_settings.h"

namespace pbdval::mujoco {

/// A motor of the scene driven by a MuJoCo actuator on a tree joint.
struct MotorBinding {
  int joint = -1;              ///< Scene::joints index
  std::string actuatorName;    ///< MuJoCo actuator
  std::string jointName;       ///< the MuJoCo joint it drives
  bool velocityServo = false;  ///< true: velocity servo; false: position servo (PD)
};

struct MjcfModel {
  std::string xml;
  std::vector<MotorBinding> motors;
  int contactPairs = 0;
  /// Of those, the pairs of bodies connected by a joint: they collide too, as in the seed.
  int jointedContactPairs = 0;
  /// Per contact pair: ("RigidBodies[0]-RigidBodies[1]", "mu=… e=… zeta=… stiffness=… damping=…").
  std::vector<std::pair<std::string, std::string>> pairSettings;
  int equalityConstraints = 0;
  /// Approximations made for this scene ("RigidBodies[2]: collides as the convex hull ...").
  std::vector<std::string> approximations;
};

/// MuJoCo body name of Scene::rigidBodies[index].
std::string bodyName(std::size_t index);

/// Requires a scene without unsupported features (MujocoEngine::unsupported, from
/// mujocoFeatures()).
MjcfModel writeMjcf(const pbd::Scene& scene, const MujocoSettings& settings,
                    const KinematicTree& tree);

}  // namespace pbdval::mujoco
