// What every joint type shares: the interface, its defaults, and the anchor/frame set-up.
//
// The joint interface (checked at compile time in joint.h):
//   T(const BodyStates&, const JointDesc&)     init: anchors and frames in the bodies' frames
//   void updateTarget(Real time)               motors: set point for the end of the step
//   void beginSubstep(Real substepSize)        XPBD joints: reset their multipliers
//   void solvePosition(BodyStates&, Real h)    update world quantities, project (hard or XPBD)
//   void solveVelocity(BodyStates&)            velocity motors only
//   ConstraintRows<kRows> positionRows(const BodyStates&) const   C and its Jacobians
//   JointError error(const BodyStates&) const  the joint's own constraint error
//   JointEnds ends() const                     the bodies/particle it couples
#pragma once

#include "pbd/joints/joint_parts.h"
#include "pbd/model/scene.h"

namespace pbd {

/// The two ends of a joint: rigid bodies, or a rigid body and a particle.
struct JointEnds {
  int body0 = -1;
  int body1 = -1;     ///< -1 when the second end is a particle
  int particle = -1;  ///< -1 unless the second end is a particle
};

/// No-op defaults for the optional parts of the interface.
struct JointDefaults {
  void updateTarget(Real /*time*/) {}
  void beginSubstep(Real /*substepSize*/) {}
  void solveVelocity(BodyStates& /*bodies*/) {}
};

/// Two anchors at a common world point p and two joint frames whose x axis is a common world
/// axis a, both captured at initialisation (the seed's joints are specified in world
/// coordinates at t = 0).
struct PointAxisFrames {
  int body0 = -1;
  int body1 = -1;
  joint_parts::LocalAnchor anchor0, anchor1;
  joint_parts::LocalFrame frame0, frame1;

  static PointAxisFrames init(const RigidBodyStates& bodies, int body0, int body1,
                              const Vector3& point, const Vector3& axis) {
    PointAxisFrames f;
    f.body0 = body0;
    f.body1 = body1;
    f.anchor0 = joint_parts::LocalAnchor::fromWorld(bodies, body0, point);
    f.anchor1 = joint_parts::LocalAnchor::fromWorld(bodies, body1, point);
    f.frame0 = joint_parts::LocalFrame::fromAxis(bodies, body0, axis);
    f.frame1 = joint_parts::LocalFrame::fromAxis(bodies, body1, axis);
    return f;
  }
  /// Slider-type joints anchor at body 1's centre of mass.
  static PointAxisFrames initAtSecondBody(const RigidBodyStates& bodies, int body0, int body1,
                                          const Vector3& axis) {
    return init(bodies, body0, body1, bodies.position[static_cast<std::size_t>(body1)], axis);
  }

  Vector3 x0(const RigidBodyStates& b) const { return b.position[static_cast<std::size_t>(body0)]; }
  Vector3 x1(const RigidBodyStates& b) const { return b.position[static_cast<std::size_t>(body1)]; }
  Vector3 c0(const RigidBodyStates& b) const { return anchor0.world(b, body0); }
  Vector3 c1(const RigidBodyStates& b) const { return anchor1.world(b, body1); }
  Quaternion worldFrame0(const RigidBodyStates& b) const { return frame0.world(b, body0); }
  Quaternion worldFrame1(const RigidBodyStates& b) const { return frame1.world(b, body1); }
  JointEnds ends() const { return {body0, body1, -1}; }

  /// Point rows (3) at `row`: c₁ − c₀.
  template <int Rows>
  void setPointRows(ConstraintRows<Rows>& rows, int row, const RigidBodyStates& b) const {
    joint_parts::setPointRows(rows, row, x0(b), c0(b), x1(b), c1(b));
  }
  /// Axis rows along columns [firstColumn, firstColumn + count) of body 0's world joint frame
  /// (column 0 is the joint axis); `axialOffset` is subtracted from the column-0 row.
  template <int Rows>
  void setAxisRows(ConstraintRows<Rows>& rows, int row, const RigidBodyStates& b, int firstColumn,
                   int count, Real axialOffset = 0) const {
    const Matrix3 frame = worldFrame0(b).toRotationMatrix();
    for (int i = 0; i < count; ++i) {
      const int column = firstColumn + i;
      joint_parts::setAxisRow(rows, row + i, frame.col(column), x0(b), c0(b), x1(b), c1(b),
                              column == 0 ? axialOffset : Real(0));
    }
  }
  /// Rotation rows from components [first, first + count) of the frame error against `target`.
  template <int Rows>
  void setRotationRows(ConstraintRows<Rows>& rows, int row, const RigidBodyStates& b,
                       int firstComponent, int count,
                       const Quaternion& target = Quaternion::Identity()) const {
    const auto error = joint_parts::relativeRotationError(worldFrame0(b), worldFrame1(b), target);
    joint_parts::setRotationRows(rows, row, error, firstComponent, count);
  }
};

/// Two connectors (`position1` fixed in body 0, `position2` fixed in body 1, world at t = 0) and
/// their initial distance: the geometry of the distance joint and the rigid-body spring.
struct ConnectorPair {
  int body0 = -1;
  int body1 = -1;
  joint_parts::LocalAnchor anchor0, anchor1;
  Real restLength = 0;

  static ConnectorPair init(const RigidBodyStates& bodies, const JointDesc& desc) {
    ConnectorPair c;
    c.body0 = desc.body1;
    c.body1 = desc.body2;
    c.anchor0 = joint_parts::LocalAnchor::fromWorld(bodies, desc.body1, desc.position1);
    c.anchor1 = joint_parts::LocalAnchor::fromWorld(bodies, desc.body2, desc.position2);
    c.restLength = (desc.position2 - desc.position1).norm();
    return c;
  }
  /// C = ‖c₁ − c₀‖ − L and its Jacobians (joint_parts::setDistanceRow).
  ConstraintRows<1> distanceRow(const RigidBodyStates& b) const {
    ConstraintRows<1> rows;
    joint_parts::setDistanceRow(
        rows, 0, b.position[static_cast<std::size_t>(body0)], anchor0.world(b, body0),
        b.position[static_cast<std::size_t>(body1)], anchor1.world(b, body1), restLength);
    return rows;
  }
  JointEnds ends() const { return {body0, body1, -1}; }
};

/// Norm of rows [first, first + count) of C.
template <int Rows>
Real rowNorm(const ConstraintRows<Rows>& rows, int first, int count) {
  return rows.value.segment(first, count).norm();
}

}  // namespace pbd
