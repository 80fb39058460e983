// All rigid-body joints of the seed behind one interface (see joint_common.h), stored as a
// tagged union so the solver loops dispatch without virtual calls or heap allocation.
// The alternatives are in JointType order: Joint::index() == static_cast<int>(type).
#pragma once

#include <type_traits>
#include <variant>

#include "pbd/joints/ball_joint.h"
#include "pbd/joints/ball_on_line_joint.h"
#include "pbd/joints/damper_joint.h"
#include "pbd/joints/distance_joint.h"
#include "pbd/joints/hinge_joint.h"
#include "pbd/joints/rigid_body_particle_ball_joint.h"
#include "pbd/joints/rigid_body_spring.h"
#include "pbd/joints/slider_joint.h"
#include "pbd/joints/stretch_bending_twisting_joint.h"
#include "pbd/joints/target_angle_motor_hinge_joint.h"
#include "pbd/joints/target_position_motor_slider_joint.h"
#include "pbd/joints/target_velocity_motor_hinge_joint.h"
#include "pbd/joints/target_velocity_motor_slider_joint.h"
#include "pbd/joints/universal_joint.h"

namespace pbd {

using Joint = std::variant<BallJoint, BallOnLineJoint, HingeJoint, UniversalJoint, SliderJoint,
                           RigidBodyParticleBallJoint, RigidBodySpring, DistanceJoint, DamperJoint,
                           TargetAngleMotorHingeJoint, TargetVelocityMotorHingeJoint,
                           TargetPositionMotorSliderJoint, TargetVelocityMotorSliderJoint,
                           StretchBendingTwistingJoint>;
static_assert(std::variant_size_v<Joint> == kJointTypeCount);

namespace detail {
// Compile-time check that every alternative implements the interface and sits at the index
// of its JointType.
template <typename T, std::size_t Index>
constexpr bool implementsJointInterface() {
  using Rows = decltype(std::declval<const T&>().positionRows(std::declval<const BodyStates&>()));
  return static_cast<std::size_t>(T::kType) == Index &&
         std::is_same_v<Rows, ConstraintRows<T::kRows>> &&
         std::is_same_v<decltype(std::declval<T&>().solvePosition(std::declval<BodyStates&>(),
                                                                  Real(0))),
                        void> &&
         std::is_same_v<decltype(std::declval<T&>().solveVelocity(std::declval<BodyStates&>())),
                        void> &&
         std::is_same_v<decltype(std::declval<T&>().beginSubstep(Real(0))), void> &&
         std::is_same_v<decltype(std::declval<T&>().updateTarget(Real(0))), void> &&
         std::is_same_v<decltype(std::declval<const T&>().error(std::declval<const BodyStates&>())),
                        JointError> &&
         std::is_same_v<decltype(std::declval<const T&>().ends()), JointEnds> &&
         std::is_constructible_v<T, const BodyStates&, const JointDesc&>;
}
template <std::size_t... I>
constexpr bool allImplementJointInterface(std::index_sequence<I...>) {
  return (implementsJointInterface<std::variant_alternative_t<I, Joint>, I>() && ...);
}
}  // namespace detail
static_assert(detail::allImplementJointInterface(std::make_index_sequence<kJointTypeCount>{}),
              "every joint type implements the joint interface, in JointType order");

/// Creates the joint described by `desc` from the bodies' initial poses.
Joint makeJoint(const BodyStates& bodies, const JointDesc& desc);

inline JointType jointType(const Joint& joint) {
  return static_cast<JointType>(joint.index());
}
inline JointEnds jointEnds(const Joint& joint) {
  return std::visit([](const auto& j) { return j.ends(); }, joint);
}
inline JointError jointError(const Joint& joint, const BodyStates& bodies) {
  return std::visit([&](const auto& j) { return j.error(bodies); }, joint);
}

}  // namespace pbd
