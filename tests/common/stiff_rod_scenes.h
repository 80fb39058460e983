// Stiff rods of rigid cylinder segments built in code (as the loader would produce them from
// CosseratJoints and TreeModels): a horizontal cantilever and a Y-shaped tree.
#pragma once

#include <cmath>

#include "common/scene_fixtures.h"
#include "pbd/model/world.h"

namespace pbd::test {

struct RodMaterial {
  Real youngsModulus = Real(1e10);  ///< Pa
  Real torsionModulus = Real(4e9);  ///< Pa
  Real density = 1000;              ///< kg/m³
  Real radius = Real(0.01);         ///< m
};

/// I = π r⁴ / 4.
inline Real secondMomentOfArea(Real radius) {
  return Real(EIGEN_PI) / 4 * radius * radius * radius * radius;
}

/// The rotation taking the segment's rod axis (local y) to the unit direction `d`.
inline Quaternion rodAxisTo(const Vector3& d) {
  return Quaternion::FromTwoVectors(Vector3::UnitY(), d).normalized();
}

/// A cylinder segment of length `length` from `start` along the unit direction `d`.
inline RigidBodyDesc rodSegment(int id, const Vector3& start, const Vector3& d, Real length,
                                const RodMaterial& m, bool dynamic) {
  return primitiveBody(id, CollisionObjectType::Cylinder, Vector3(m.radius, length, m.radius),
                       cylinderMoments(m.radius, length, m.density), start + length / 2 * d,
                       m.density, dynamic, rodAxisTo(d));
}

/// A stiff-rod joint between bodies `a` and `b` (indices = ids) at `point`, in tree 0.
inline JointDesc rodJoint(int id, int a, int b, const Vector3& point, Real segmentLength,
                          const RodMaterial& m) {
  JointDesc j = makeJointDesc(JointType::StiffRod, a, b);
  j.jsonPath = "CosseratJoints[" + std::to_string(id) + "]";
  j.position = point;
  j.stiffRod.id = id;
  j.stiffRod.tree = 0;
  j.stiffRod.youngsModulus = m.youngsModulus;
  j.stiffRod.torsionModulus = m.torsionModulus;
  j.stiffRod.averageRadius = m.radius;
  j.stiffRod.averageSegmentLength = segmentLength;
  return j;
}

/// One TreeModel over every body and joint of `s`.
inline void addTree(Scene& s, StiffRodSolver solver) {
  StiffRodTreeDesc tree;
  tree.jsonPath = "TreeModels[0]";
  for (std::size_t i = 0; i < s.rigidBodies.size(); ++i)
    tree.bodies.push_back(int(i));
  for (std::size_t j = 0; j < s.joints.size(); ++j)
    tree.joints.push_back(int(j));
  tree.solver = solver;
  s.stiffRodTrees.push_back(tree);
}

/// A horizontal cantilever along +x: a static clamp segment (body 0) on [−ℓ, 0], then
/// `segments` dynamic segments of length ℓ on [(k−1)ℓ, kℓ], k = 1…N, joined at x = (k−1)ℓ.
/// One substep of size h per step.
inline Scene cantileverScene(int segments, Real totalLength, const RodMaterial& m,
                             StiffRodSolver solver, Real h = Real(0.05), int iterations = 1) {
  Scene s;
  s.simulation.timeStepSize = h;
  s.simulation.subSteps = 1;
  s.simulation.maxIterations = iterations;
  s.simulation.maxIterationsV = 0;
  const Real l = totalLength / Real(segments);
  const Vector3 x = Vector3::UnitX();
  s.rigidBodies.push_back(rodSegment(0, -l * x, x, l, m, false));
  for (int k = 1; k <= segments; ++k) {
    s.rigidBodies.push_back(rodSegment(k, Real(k - 1) * l * x, x, l, m, true));
    s.joints.push_back(rodJoint(k - 1, k - 1, k, Real(k - 1) * l * x, l, m));
  }
  addTree(s, solver);
  return s;
}

/// A Y-shaped tree: a static root segment on [−ℓ, 0] along x, a trunk of two segments to
/// x = 2ℓ, and there two arms of `armSegments` segments each, at ±45° in the x–z plane. Body 2
/// (the trunk's end) carries three joints.
inline Scene yTreeScene(int armSegments, Real l, const RodMaterial& m, StiffRodSolver solver) {
  Scene s;
  s.simulation.timeStepSize = Real(1e-3);
  s.simulation.subSteps = 1;
  s.simulation.maxIterations = 1;
  s.simulation.maxIterationsV = 0;
  const Vector3 x = Vector3::UnitX();
  s.rigidBodies.push_back(rodSegment(0, -l * x, x, l, m, false));
  for (int k = 1; k <= 2; ++k) {
    s.rigidBodies.push_back(rodSegment(k, Real(k - 1) * l * x, x, l, m, true));
    s.joints.push_back(rodJoint(k - 1, k - 1, k, Real(k - 1) * l * x, l, m));
  }
  const Vector3 branch = 2 * l * x;
  for (Real side : {Real(1), Real(-1)}) {
    const Vector3 d = Vector3(1, 0, side).normalized();
    int previous = 2;
    for (int k = 0; k < armSegments; ++k) {
      const int id = int(s.rigidBodies.size());
      const Vector3 start = branch + Real(k) * l * d;
      s.rigidBodies.push_back(rodSegment(id, start, d, l, m, true));
      s.joints.push_back(rodJoint(int(s.joints.size()), previous, id, start, l, m));
      previous = id;
    }
  }
  addTree(s, solver);
  return s;
}

/// World position of the free end (local +y end) of segment `body`.
inline Vector3 segmentTip(const World& world, int body, Real length) {
  const SceneFrameState f = world.sceneFrameState(std::size_t(body));
  return f.centerOfMass + f.rotation * Vector3(0, length / 2, 0);
}

}  // namespace pbd::test
