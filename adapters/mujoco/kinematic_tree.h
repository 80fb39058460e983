// MuJoCo is a reduced-coordinate engine: bodies form a tree and every joint lives in a child
// body. The Scene's joints form a graph over its bodies, with all static bodies fused into one
// node (the world). This file chooses a spanning forest of that graph and classifies every
// joint.
//
// - Tree joints become MuJoCo joints in the child body. Joints that only MuJoCo joints can
//   express (slider, universal, ball-on-line, damper, the four motors) are taken first, then
//   ball and hinge joints, in scene order (Kruskal with a priority, so a loop is closed by a
//   ball or hinge joint whenever one lies on it).
// - Loop joints (edges left out of the forest) become equality constraints: a ball joint one
//   `connect`, a hinge two `connect`s on its axis. Other types cannot close a loop: reported.
// - Distance joints are always equality constraints (a spatial tendon of constant length), and
//   springs always tendon forces: they take no part in the forest.
// - Joints between two static bodies constrain nothing that moves and are left out.
// - Trees deeper than 64 bodies are cut at a ball or hinge joint, which then closes the cut as
//   an equality constraint (MJCF nests bodies, and MuJoCo's XML parser limits nesting depth).
// Each tree is rooted at the world (through the static body its joint names) or, for a group
// of dynamic bodies attached to nothing static, at its first body, which gets a free joint.
#pragma once

#include <string>
#include <vector>

#include "pbd/model/scene.h"

namespace pbdval::mujoco {

enum class JointRole {
  Tree,            ///< MuJoCo joint(s) in the child body
  LoopClosure,     ///< equality constraint(s)
  DistanceTendon,  ///< tendon of constant length (equality constraint)
  SpringTendon,    ///< tendon with stiffness
  StaticOnly,      ///< between two static bodies: nothing to do
  Unsupported,
};

struct KinematicTree {
  /// Per body (Scene::rigidBodies index): the parent body, or -1 for a child of the world.
  std::vector<int> parent;
  /// Per body: the scene joint that connects it to its parent, or -1 (static or free root).
  std::vector<int> parentJoint;
  /// Per body: true when the body is the joint's first body (body1), i.e. the joint is seen
  /// from the other side and its axes and set points change sign.
  std::vector<bool> reversed;
  /// Per body: a dynamic body at the root of a tree: it gets a free joint.
  std::vector<bool> freeRoot;
  /// Bodies with their parents first.
  std::vector<int> order;
  /// Per scene joint.
  std::vector<JointRole> roles;
  /// "SliderJoints[1]: ..." for every joint or feature MuJoCo cannot represent here.
  std::vector<std::string> unsupported;

  std::vector<int> children(int body) const;
};

KinematicTree planKinematicTree(const pbd::Scene& scene);

}  // namespace pbdval::mujoco
