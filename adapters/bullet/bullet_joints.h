// The Scene's joints as Bullet constraints (maximal coordinates, btTypedConstraint).
//
// Anchors and axes are world quantities at t = 0; every constraint frame is built in the world
// at t = 0 and expressed in each body's frame (its principal frame at the centre of mass), so
// both frames coincide initially, as in the PBD joints. Body A is the joint's body1, body B
// its body2.
//
// Scene joint                  Bullet
//   Ball                       btPoint2PointConstraint
//   BallOnLine                 btGeneric6DofSpring2Constraint: linear x (the axis) free, y, z
//                              locked; rotations free
//   Hinge                      btHingeConstraint (frame z = axis, useReferenceFrameA false)
//   Universal                  btGeneric6DofSpring2Constraint, Euler order XYZ: frame z = axis1
//                              (in A), x = axis2 (in B); the middle Euler angle, asin(z_A·x_B),
//                              locked at 0; both outer angles free, unlimited
//   Slider                     btGeneric6DofSpring2Constraint at body B's centre of mass,
//                              x = axis: linear x free, the other five locked
//   Damper                     the slider with a linear-x spring (stiffness k, no damping, rest
//                              offset 0)
//   TargetAngleMotorHinge      btHingeConstraint motor: setMotorTarget(θ*(t + h), h) each step
//                              (velocity (θ* − θ)/h, shortest way), unlimited impulse
//   TargetVelocityMotorHinge   btHingeConstraint motor at ω*(t + h), unlimited impulse
//   TargetPositionMotorSlider  the slider with linear x locked at s*(t + h), stop ERP 1 (the set
//                              point is reached at the end of the step)
//   TargetVelocityMotorSlider  the slider with a linear-x motor at v*(t + h), unlimited force
//   RigidBodySpring            a force element: F = −k (‖c_B − c_A‖ − L) n applied at the
//                              connectors before each step (Bullet has no distance spring)
//   Distance                   unsupported (no distance constraint in Bullet)
//   RigidBodyParticleBall      unsupported (no particles)
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "adapters/bullet/bullet_convert.h"
#include "pbd/model/scene.h"

namespace pbdval::bullet {

/// The constraints of one world and what must happen to them before each step.
struct JointModel {
  std::vector<std::unique_ptr<btTypedConstraint>> constraints;
  /// Called before each step with the time at its end and the step size: motor set points,
  /// spring forces.
  std::vector<std::function<void(double endTime, double stepSize)>> beforeStep;
  /// How many joints became each kind of Bullet constraint.
  std::map<std::string, int> kindCounts;
};

/// Builds the Bullet counterpart of `joint` between bodies `a` and `b` (at their t = 0 poses).
/// Constraints go into model.constraints; the caller adds them to the world.
void addJoint(const pbd::JointDesc& joint, btRigidBody& a, btRigidBody& b, JointModel& model);

/// Sign that turns the Scene's slider velocity (body B along +axis relative to A) into
/// btGeneric6DofSpring2Constraint's linear motor target velocity.
extern const double kLinearMotorVelocitySign;

}  // namespace pbdval::bullet
