// The Scene's joints as ODE joints (docs/parity-ode.md has the table).
//
// Orientation. The seed's joints act on body 1 relative to body 0 (`bodyID2` relative to
// `bodyID1`); ODE's hinge angle and slider position measure its first body relative to its
// second. So ODE's first body is scene body 1 and its second scene body 0 (or the static world).
// When scene body 1 is static, ODE's first body is scene body 0 and the axis of hinges, sliders
// and motors is negated, which keeps every angle, position and set point in the scene's sense.
// A joint between two static bodies does nothing and is not created.
//
//   ball                      dJointCreateBall at `position`
//   hinge                     dJointCreateHinge at `position`, `axis`
//   universal                 dJointCreateUniversal: axis1 fixed in body 0, axis2 in body 1
//   slider                    dJointCreateSlider along `axis`
//   distance                  dJointCreateDBall between `position1` (body 0), `position2`
//   ball-on-line              ode.step only: an auxiliary carriage body (mass carriageMassRatio
//                             × the lighter dynamic end, isotropic inertia scaled alike) on a
//                             slider along `axis` in body 0, and a ball joint from it to body 1
//                             at `position`. QuickStep's iterations cannot resolve so light a
//                             body: unsupported there.
//   rigid-body spring         DBall whose row is a spring: ERP = h k/(h k + c), CFM = 1/(h k + c)
//                             with damping c = 0 (ODE manual §3.8), i.e. ERP 1, CFM 1/(h k)
//   damper (axial spring)     slider with both stops at 0 and the same stop ERP/CFM spring
//   target-velocity motors    hinge/slider motor: dParamVel = set point at the end of the step,
//                             dParamFMax = ∞ (a hard velocity row, as the seed's)
//   target-angle/position     hinge/slider motor as a servo: dParamVel = (set point at the end
//                             of the step − current angle or position)/h, dParamFMax = ∞, so the
//                             set point is reached at the end of every step, as the seed's
//                             hard position row does
//   rigid-body–particle ball  unsupported: ODE has no particles
#pragma once

#include <string>
#include <vector>

#include "adapters/ode/ode_world.h"

namespace pbdval::ode {

class OdeJoints {
 public:
  /// Creates every joint of `scene` in `world` (owned by the world). Call inside an OdeCall.
  OdeJoints(OdeWorld& world, const pbd::Scene& scene, const OdeSettings& settings);

  /// Sets the motors for the step that ends at `endTime` (the seed evaluates set points there).
  void prepareStep(double endTime, double stepSize);

 private:
  struct MotorDrive {
    dJointID joint = nullptr;
    pbd::JointType type = pbd::JointType::TargetVelocityMotorHinge;
    pbd::MotorTarget target;
  };
  /// The joint's two ODE bodies in ODE's order, and whether the scene's roles are swapped.
  struct Ends {
    dBodyID first = nullptr;
    dBodyID second = nullptr;
    bool swapped = false;
  };

  Ends endsOf(const pbd::JointDesc& desc) const;
  void add(const pbd::JointDesc& desc);
  void addBallOnLine(const pbd::JointDesc& desc);
  void addSpring(const pbd::JointDesc& desc, const Ends& ends);
  dJointID addHinge(const pbd::JointDesc& desc, const Ends& ends);
  dJointID addSlider(const pbd::JointDesc& desc, const Ends& ends);
  void addMotor(const pbd::JointDesc& desc, dJointID joint);
  Vector3 pointVelocity(int index, const Vector3& point) const;

  OdeWorld& world_;
  const pbd::Scene& scene_;
  OdeSettings settings_;
  std::vector<MotorDrive> motors_;
};

}  // namespace pbdval::ode
