// Simulation state of rigid bodies and particles as structure-of-arrays.
//
// Rigid bodies are simulated in their principal frame: `position` is the centre of mass and
// `rotation` maps principal axes to world. The scene frame (the frame of the body's geometry
// file) is recovered with `principalInScene` (see World::sceneFrameState).
#pragma once

#include <cstddef>
#include <vector>

#include "pbd/math/types.h"

namespace pbd {

struct RigidBodyStates {
  // Hot data, read and written every substep.
  std::vector<Vector3> position;         ///< centre of mass, world
  std::vector<Quaternion> rotation;      ///< principal frame → world
  std::vector<Vector3> velocity;         ///< of the centre of mass, world
  std::vector<Vector3> angularVelocity;  ///< world
  std::vector<Vector3> oldPosition;      ///< at the start of the current substep
  std::vector<Vector3> lastPosition;     ///< at the start of the previous substep
  std::vector<Quaternion> oldRotation;
  std::vector<Quaternion> lastRotation;
  std::vector<Vector3> acceleration;  ///< set to gravity at the start of every step
  std::vector<Vector3> torque;        ///< constant external torque (never cleared, as in the seed)
  std::vector<Real> inverseMass;      ///< 0 for static bodies
  std::vector<Vector3> inertia;       ///< principal moments
  std::vector<Vector3> inverseInertia;  ///< 0 for static bodies

  // Cold data.
  std::vector<Real> mass;
  std::vector<Quaternion> principalInScene;  ///< principal frame → scene frame (constant)
  std::vector<Vector3> centerOfMassInScene;  ///< centre of mass in the scene frame (constant)

  std::size_t size() const { return position.size(); }
  bool isDynamic(std::size_t i) const { return inverseMass[i] > 0; }

  /// R diag(I⁻¹) Rᵀ at the current rotation (zero for static bodies).
  Matrix3 inverseInertiaWorld(std::size_t i) const {
    const Matrix3 r = rotation[i].toRotationMatrix();
    return r * inverseInertia[i].asDiagonal() * r.transpose();
  }
  /// R diag(I) Rᵀ at the current rotation.
  Matrix3 inertiaWorld(std::size_t i) const {
    const Matrix3 r = rotation[i].toRotationMatrix();
    return r * inertia[i].asDiagonal() * r.transpose();
  }

  void resize(std::size_t n);
};

struct ParticleStates {
  std::vector<Vector3> position;
  std::vector<Vector3> velocity;
  std::vector<Vector3> oldPosition;
  std::vector<Vector3> lastPosition;
  std::vector<Vector3> acceleration;
  std::vector<Real> inverseMass;  ///< 0 for static particles
  std::vector<Real> mass;

  std::size_t size() const { return position.size(); }
  void resize(std::size_t n);
};

/// The orientations of Cosserat-rod segments (constraints/cosserat_rod.h): one quaternion per
/// segment, integrated like a rigid body's with the isotropic inertia 1/(4 w_q) (w_q the
/// quaternion's 4-vector inverse mass, the seed's "orientation mass" inverse) and no gravity.
struct SegmentStates {
  std::vector<Quaternion> rotation;      ///< director frame → world (d₃ along the segment)
  std::vector<Quaternion> oldRotation;   ///< at the start of the current substep
  std::vector<Vector3> angularVelocity;  ///< world
  std::vector<Vector3> torque;           ///< constant external torque, world (0 unless set in code)
  std::vector<Real> inverseMass;         ///< w_q; 0 for static segments

  std::size_t size() const { return rotation.size(); }
  void resize(std::size_t n);
};

/// Everything a constraint may read or move.
struct BodyStates {
  RigidBodyStates rigid;
  ParticleStates particles;
  SegmentStates segments;  ///< rod segment orientations (after the particles of their rods)
};

}  // namespace pbd
