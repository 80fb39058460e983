#include "pbd/joints/xpbd_joint.h"

#include <type_traits>
#include <variant>

#include "pbd/joints/point_constraint.h"

namespace pbd {
namespace {

/// α of every row by family (see the header), before the 1/h² scaling.
template <typename T>
Eigen::Matrix<Real, T::kRows, 1> rowCompliance(const T& /*joint*/,
                                               const ConstraintRows<T::kRows>& rows,
                                               const XpbdSettings& settings) {
  Eigen::Matrix<Real, T::kRows, 1> compliance;
  for (int r = 0; r < T::kRows; ++r) {
    const bool rotational = rows.linear[0].row(r).isZero(0) && rows.linear[1].row(r).isZero(0);
    compliance(r) =
        rotational ? settings.jointAngularCompliance / 4 : settings.jointLinearCompliance;
  }
  return compliance;
}

Eigen::Matrix<Real, 1, 1> rowCompliance(const RigidBodySpring& spring,
                                        const ConstraintRows<1>& /*rows*/,
                                        const XpbdSettings& /*settings*/) {
  return Eigen::Matrix<Real, 1, 1>::Constant(Real(1) / spring.stiffness());
}

Eigen::Matrix<Real, 6, 1> rowCompliance(const DamperJoint& damper, const ConstraintRows<6>& rows,
                                        const XpbdSettings& settings) {
  Eigen::Matrix<Real, 6, 1> compliance = rowCompliance<DamperJoint>(damper, rows, settings);
  compliance(0) = Real(1) / damper.stiffness();
  return compliance;
}

template <typename T>
bool exertsNothing(const T& /*joint*/) {
  return false;
}
bool exertsNothing(const RigidBodySpring& spring) {
  return !(spring.stiffness() > 0);
}
bool exertsNothing(const DamperJoint& damper) {
  return !(damper.stiffness() > 0);
}

/// A joint's two ends moved to their poses of the substep's start (oldPosition, oldRotation; a
/// particle end's oldPosition) for as long as this lives; the current poses are put back when
/// it goes. The rows of JointDirections::Start are evaluated through it: every joint type's
/// positionRows() then gives its Jacobians at the start poses, with no second implementation
/// of any joint's geometry (and no allocation: the two ends' poses are kept here).
class StartPosesOfEnds {
 public:
  StartPosesOfEnds(BodyStates& bodies, const JointEnds& ends) : bodies_(bodies), ends_(ends) {
    RigidBodyStates& b = bodies_.rigid;
    for (int k = 0; k < 2; ++k) {
      const int body = k == 0 ? ends_.body0 : ends_.body1;
      if (body < 0) continue;
      const auto i = static_cast<std::size_t>(body);
      position_[k] = b.position[i];
      rotation_[k] = b.rotation[i];
      b.position[i] = b.oldPosition[i];
      b.rotation[i] = b.oldRotation[i];
    }
    if (ends_.particle >= 0) {
      ParticleStates& p = bodies_.particles;
      const auto i = static_cast<std::size_t>(ends_.particle);
      particlePosition_ = p.position[i];
      p.position[i] = p.oldPosition[i];
    }
  }
  ~StartPosesOfEnds() {
    RigidBodyStates& b = bodies_.rigid;
    for (int k = 0; k < 2; ++k) {
      const int body = k == 0 ? ends_.body0 : ends_.body1;
      if (body < 0) continue;
      const auto i = static_cast<std::size_t>(body);
      b.position[i] = position_[k];
      b.rotation[i] = rotation_[k];
    }
    if (ends_.particle >= 0)
      bodies_.particles.position[std::size_t(ends_.particle)] = particlePosition_;
  }
  StartPosesOfEnds(const StartPosesOfEnds&) = delete;
  StartPosesOfEnds& operator=(const StartPosesOfEnds&) = delete;

 private:
  BodyStates& bodies_;
  JointEnds ends_;
  std::array<Vector3, 2> position_{Vector3::Zero(), Vector3::Zero()};
  std::array<Quaternion, 2> rotation_{Quaternion::Identity(), Quaternion::Identity()};
  Vector3 particlePosition_ = Vector3::Zero();
};

/// Inverse mass and world inverse inertia of a joint's two ends at the bodies' current poses.
std::array<EndInverseMass, 2> endInverseMasses(const BodyStates& bodies, const JointEnds& ends) {
  return {joint_parts::rigidEnd(bodies.rigid, ends.body0),
          ends.particle >= 0
              ? EndInverseMass{bodies.particles.inverseMass[std::size_t(ends.particle)],
                               Matrix3::Zero()}
              : joint_parts::rigidEnd(bodies.rigid, ends.body1)};
}

template <typename T>
void solve(const T& joint, BodyStates& bodies, Real substepSize, const XpbdSettings& settings,
           XpbdJointMultipliers& multipliers) {
  constexpr int kRows = T::kRows;
  using Vector = Eigen::Matrix<Real, kRows, 1>;
  if (exertsNothing(joint)) return;
  const JointEnds ends = joint.ends();
  const bool particleEnd = ends.particle >= 0;
  const ConstraintRows<kRows> rows = joint.positionRows(bodies);  // C and ∇C now
  const Vector compliance =
      rowCompliance(joint, rows, settings) / (substepSize * substepSize);  // α̃ = α/h²
  const Vector lambda = multipliers.template head<kRows>();
  const Vector rhs = -rows.value - compliance.cwiseProduct(lambda);
  RowCorrection<kRows> c;
  bool solved = false;
  if (settings.jointDirections == JointDirections::Start &&
      startDirectionsApply(bodies.rigid, ends.body0) &&
      startDirectionsApply(bodies.rigid, ends.body1)) {
    ConstraintRows<kRows> start;
    std::array<EndInverseMass, 2> startInverseMasses;
    {
      const StartPosesOfEnds startPoses(bodies, ends);
      start = joint.positionRows(bodies);  // ∇C at the substep's start
      startInverseMasses = endInverseMasses(bodies, ends);
    }
    solved = solveRowsAlongStart(start, rows, startInverseMasses, compliance, rhs, c);
  }
  if (!solved && !solveRows(rows, endInverseMasses(bodies, ends), compliance, rhs, c)) return;
  multipliers.template head<kRows>() += c.multiplier;
  joint_parts::applyPositionCorrection(bodies.rigid, ends.body0, c.linear[0], c.angular[0]);
  if (particleEnd)
    bodies.particles.position[std::size_t(ends.particle)] += c.linear[1];
  else
    joint_parts::applyPositionCorrection(bodies.rigid, ends.body1, c.linear[1], c.angular[1]);
}

/// The ball joint: three linear rows of one compliance, through its direct solve.
void solve(BallJoint& joint, BodyStates& bodies, Real substepSize, const XpbdSettings& settings,
           XpbdJointMultipliers& multipliers) {
  const Real complianceTilde = settings.jointLinearCompliance / (substepSize * substepSize);
  multipliers.head<3>() += joint.solvePositionCompliant(
      bodies, complianceTilde, multipliers.head<3>(), settings.jointDirections);
}

/// The stiff-rod joint: its own compliances (stretch regularisation, 1/(K L h²)), not the
/// settings' joint compliances.
void solve(StretchBendingTwistingJoint& joint, BodyStates& bodies, Real substepSize,
           const XpbdSettings& /*settings*/, XpbdJointMultipliers& multipliers) {
  const stiff_rod::Vector6 compliance =
      stiff_rod::rowCompliance(joint.stiffness(), joint.segmentLength(), substepSize);
  multipliers += joint.project(bodies, compliance, multipliers);
}

/// Whether T's per-substep hooks do anything: a type that does not declare its own inherits
/// JointDefaults' empty one.
template <typename T>
constexpr bool hasTarget =
    !std::is_same_v<decltype(&T::updateTarget), void (JointDefaults::*)(Real)>;
template <typename T>
constexpr bool hasVelocityPass =
    !std::is_same_v<decltype(&T::solveVelocity), void (JointDefaults::*)(BodyStates&)>;
static_assert(!hasTarget<BallJoint> && !hasVelocityPass<BallJoint> &&
                  hasTarget<TargetVelocityMotorSliderJoint> &&
                  hasVelocityPass<TargetVelocityMotorSliderJoint>,
              "the hooks are told apart from JointDefaults' empty ones");

}  // namespace

XpbdJointSchedule scheduleJointsXpbd(const std::vector<Joint>& joints) {
  XpbdJointSchedule schedule;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const BallJoint* ball = std::get_if<BallJoint>(&joints[j]);
    if (schedule.runs.empty() || schedule.runs.back().ball != (ball != nullptr))
      schedule.runs.push_back({j, j, ball != nullptr, schedule.balls.size()});
    schedule.runs.back().end = j + 1;
    if (ball) {
      const PointAxisFrames& frames = ball->frames();
      schedule.balls.push_back(
          {frames.body0, frames.body1, frames.anchor0.inBody, frames.anchor1.inBody});
    }
    std::visit(
        [&](const auto& joint) {
          using T = std::decay_t<decltype(joint)>;
          if (hasTarget<T>) schedule.withTarget.push_back(j);
          if (hasVelocityPass<T>) schedule.withVelocityPass.push_back(j);
        },
        joints[j]);
  }
  return schedule;
}

void updateJointTargetsXpbd(std::vector<Joint>& joints, const XpbdJointSchedule& schedule,
                            Real time) {
  for (std::size_t j : schedule.withTarget)
    std::visit([&](auto& joint) { joint.updateTarget(time); }, joints[j]);
}

void solveJointPositionsXpbd(std::vector<Joint>& joints, const XpbdJointSchedule& schedule,
                             BodyStates& bodies, Real substepSize, const XpbdSettings& settings,
                             std::vector<XpbdJointMultipliers>& multipliers, bool firstSweep) {
  // Ball joints: α̃ = α/h² once per substep; λ from zero in the substep's first sweep (as
  // BallJoint's own solve), continued in the next.
  const Real ballCompliance = settings.jointLinearCompliance / (substepSize * substepSize);
  for (const XpbdJointSchedule::Run& run : schedule.runs) {
    if (run.ball) {
      const XpbdJointSchedule::Ball* ball = schedule.balls.data() + run.firstBall;
      for (std::size_t j = run.begin; j < run.end; ++j, ++ball) {
        XpbdJointMultipliers& lambda = multipliers[j];
        if (firstSweep) lambda.setZero();
        const Vector3 accumulated = lambda.head<3>();
        lambda.head<3>() += projectPointConstraint(bodies.rigid, ball->body0, ball->body1,
                                                   ball->anchor0, ball->anchor1, ballCompliance,
                                                   accumulated, settings.jointDirections);
      }
      continue;
    }
    for (std::size_t j = run.begin; j < run.end; ++j) {
      XpbdJointMultipliers& lambda = multipliers[j];
      if (firstSweep) lambda.setZero();
      std::visit([&](auto& joint) { solve(joint, bodies, substepSize, settings, lambda); },
                 joints[j]);
    }
  }
}

void solveJointVelocitiesXpbd(std::vector<Joint>& joints, const XpbdJointSchedule& schedule,
                              BodyStates& bodies) {
  for (std::size_t j : schedule.withVelocityPass)
    std::visit([&](auto& joint) { joint.solveVelocity(bodies); }, joints[j]);
}

}  // namespace pbd
