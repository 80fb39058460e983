// Joint error measured from the Scene's anchors and axes and the bodies' poses, independently
// of any engine's (and of the PBD library's) joint code. Formulas: docs/metrics.md §Joints.
//
// Every anchor and axis of a joint is given in world coordinates at t = 0 (the seed's
// convention). It is captured once in each body's scene frame, relative to the centre of mass:
//   p_k(t) = x_k(t) + R_k(t) R_k(0)⁻¹ (p − x_k(0)),   a_k(t) = R_k(t) R_k(0)⁻¹ a,
// with R_k(0) the Scene's rotation and x_k(0) its initial centre of mass. The relative rotation
// change of the pair is D = W₀⁻¹ W₁, W_k = R_k(t) R_k(0)⁻¹ (a rotation in the t = 0 world frame;
// D = 𝟙 while the pair keeps its initial relative orientation).
//
// Per type (linear error in m, angular in rad):
//   ball, rigid-body–particle ball: ‖p₁ − p₀‖ (particle: its position in State::particles)
//   stiff rod (CosseratJoints):    ‖p₁ − p₀‖, its zero-stretch constraint (bending and twist
//                                  are elastic, not errors)
//   hinge (+ both hinge motors):   ‖p₁ − p₀‖;  ∠(a₀, a₁) = atan2(‖a₀ × a₁‖, a₀·a₁)
//   universal:                     ‖p₁ − p₀‖;  |π/2 − ∠(a₀, a₁)| (axis1 fixed in body 0, axis2 in
//   body 1) slider, damper, slider motors: ‖(𝟙 − a₀a₀ᵀ) d‖, d = x₁ − p₀ (p₀ fixed in body 0 at body
//   1's
//                                  initial centre of mass, as the seed); geodesic angle of D
//   ball-on-line:                  ‖(𝟙 − a₀a₀ᵀ)(p₁ − p₀)‖ (line through `position` along `axis`
//                                  fixed in body 0; p₁ = `position` fixed in body 1)
//   distance:                      |‖p₁ − p₀‖ − L|, L = ‖position2 − position1‖
//   rigid-body spring:             not a constraint (its extension is a spring, see below)
// The damper's axial offset s = a₀·d and the spring's extension ℓ − ℓ₀ are spring extensions,
// not errors (mechanics.h adds ½ k s² to the energy). A stiff rod's bending and twisting are
// elastic: mechanics.h adds ½ L ΔΩᵀ K ΔΩ, ΔΩ = (2/L)(vec e − vec e⁰), e = S₀⁻¹ S₁ of the two
// segments' scene rotations (w ≥ 0), e⁰ at t = 0, K = (E I, 2 G I, E I), I = π r⁴/4 (Deul et al.
// 2018; the same energy as pbd/joints/stretch_bending_twisting_joint.h, computed here anew).
// Motor tracking (set point f(t) of the sample's time, the value the step ending at t aims at):
//   target-angle hinge:    wrap(θ − clamp(f, −π, π)), θ = twist of D about the initial axis (rad)
//   target-velocity hinge: (ω₁ − ω₀)·a₀ − f (rad/s)
//   target-position slider: a₀·d − f (m)
//   target-velocity slider: d/dt(a₀·d) − f = (ω₀ × a₀)·d + a₀·(v₁ − v₀ − ω₀ × (p₀ − x₀)) − f (m/s)
#pragma once

#include <optional>
#include <string>

#include "adapters/engine.h"

namespace pbdval {

/// A point fixed in a rigid body: its offset from the centre of mass in the body's scene frame.
struct BodyFixedPoint {
  int body = -1;  ///< index into Scene::rigidBodies
  Vector3 offset = Vector3::Zero();
  Vector3 world(const State& state) const;
};

/// A direction fixed in a rigid body, in the body's scene frame.
struct BodyFixedDirection {
  int body = -1;
  Vector3 direction = Vector3::UnitX();
  Vector3 world(const State& state) const;
};

/// The point `worldPoint` (at t = 0) captured in body `body`'s scene frame.
BodyFixedPoint fixPointInBody(const pbd::Scene& scene, int body, const Vector3& worldPoint);
/// The direction `worldDirection` (at t = 0, normalised here) captured in body `body`'s frame.
BodyFixedDirection fixDirectionInBody(const pbd::Scene& scene, int body,
                                      const Vector3& worldDirection);

/// What a motor's tracking error measures (and its unit).
enum class MotorQuantity { None, Angle, AngularVelocity, Position, Velocity };
MotorQuantity motorQuantity(pbd::JointType type);
/// "angle" (rad), "angular_velocity" (rad/s), "position" (m), "velocity" (m/s); "" for None.
const char* motorQuantityName(MotorQuantity quantity);

/// The joint kinds measured alike.
enum class JointShape {
  Ball,
  ParticleBall,
  Hinge,
  Universal,
  Slider,
  BallOnLine,
  Distance,
  Spring
};
JointShape jointShape(pbd::JointType type);
/// False for springs (no constraint, no error).
bool isConstraint(pbd::JointType type);
/// True when the type has an angular error (hinge, universal and slider kinds).
bool hasAngularError(pbd::JointType type);

/// One joint's geometry captured from the Scene at t = 0.
struct JointGeometry {
  pbd::JointType type = pbd::JointType::Ball;
  std::string jsonPath;
  BodyFixedPoint anchor0, anchor1;  ///< p₀ (body 0), p₁ (body 1; unused for the particle joint)
  BodyFixedDirection axis0, axis1;  ///< a₀ (body 0), a₁ (body 1; hinge and universal kinds)
  Vector3 initialAxis = Vector3::UnitX();  ///< a at t = 0 (world), for the hinge angle
  Quaternion initialRotation0 = Quaternion::Identity();  ///< R₀(0), R₁(0): scene rotations
  Quaternion initialRotation1 = Quaternion::Identity();
  int particle = -1;                       ///< global particle index (rigid-body–particle ball)
  double restLength = 0;                   ///< distance joint and spring, m
  double stiffness = 0;                    ///< spring and damper, N/m
  Vector3 rodStiffness = Vector3::Zero();  ///< stiff rod: (E I, 2 G I, E I) ∘ modifier, N m²
  double rodSegmentLength = 0;             ///< stiff rod: L, m
  pbd::MotorTarget target;
};

/// Throws std::invalid_argument naming the joint when its bodies are not in the Scene.
JointGeometry captureJointGeometry(const pbd::Scene& scene, const pbd::JointDesc& joint);

struct JointMeasurement {
  double linear = 0;               ///< m (0 for springs)
  std::optional<double> angular;   ///< rad, for the types with an angular error
  std::optional<double> tracking;  ///< signed motor tracking error, unit by motorQuantity
  double springExtension = 0;      ///< spring ℓ − ℓ₀, damper axial offset a₀·d (m)
};

/// The joint's errors in `state`. Throws std::invalid_argument when the state lacks a body or
/// the particle the joint needs.
JointMeasurement measureJoint(const JointGeometry& joint, const State& state);

/// Relative rotation change D = W₀⁻¹ W₁ of the joint's two bodies (t = 0 world frame).
Quaternion relativeRotationChange(const JointGeometry& joint, const State& state);

/// ½ k (extension)² for springs and dampers, the bending and twisting energy of stiff rods, 0 for
/// the other types (J).
double springPotential(const JointGeometry& joint, const State& state);

}  // namespace pbdval
