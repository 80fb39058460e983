#include "adapters/mujoco/mujoco_engine.h"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <sstream>

#include "adapters/mujoco/mujoco_errors.h"
#include "adapters/mujoco/mujoco_model_fields.h"
#include "pbd/io/number_text.h"

namespace pbdval {

namespace mujoco {

std::vector<FeatureUse> featureUses(const pbd::Scene& scene) {
  // Which joints close kinematic loops depends on the spanning forest this adapter builds
  // (kinematic_tree.h): those uses are added to the scene's own.
  std::vector<FeatureUse> uses = sceneFeatureUses(scene);
  const KinematicTree tree = planKinematicTree(scene);
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    const pbd::JointDesc& joint = scene.joints[k];
    if (tree.roles[k] == JointRole::LoopClosure)
      uses.push_back({"joint.closingLoop.ballOrHinge", joint.jsonPath, ""});
    else if (tree.roles[k] == JointRole::Unsupported &&
             joint.type != pbd::JointType::RigidBodyParticleBall &&
             joint.type != pbd::JointType::StiffRod)
      uses.push_back({"joint.closingLoop.other", joint.jsonPath,
                      std::string("a ") + pbd::jointTypeName(joint.type) + " joint"});
  }
  return uses;
}

std::vector<std::string> unsupportedRigidFeatures(const pbd::Scene& scene) {
  // The rigid part only (shapes, joints, bodies, contacts): mujoco-python maps the particle
  // models as flexes and decides those itself (python/pbdval/external/mujoco/flexes.py).
  std::vector<FeatureUse> uses = featureUses(scene);
  const auto particle = [](const FeatureUse& use) {
    for (const char* rigid : {"shape.", "joint.", "body.", "contact."})
      if (use.key.rfind(rigid, 0) == 0) return false;
    return true;
  };
  uses.erase(std::remove_if(uses.begin(), uses.end(), particle), uses.end());
  std::vector<std::string> missing;
  // The built-in engine's table, for the method the adapter runs by default (its entries for
  // rigid features are the same for every method).
  for (UnsupportedUse& use : unsupportedUses(mujocoFeatures(), uses, "mujoco.euler"))
    missing.push_back(std::move(use.message));
  return missing;
}

}  // namespace mujoco

namespace {

using mujoco::guarded;

/// Warnings that mean the run cannot continue: MuJoCo resets mjData after a bad number
/// (the state would jump back to t = 0) and drops contacts or constraints when its buffers
/// are full.
bool isFatal(int warning) {
  return warning == mjWARN_BADQPOS || warning == mjWARN_BADQVEL || warning == mjWARN_BADQACC ||
         warning == mjWARN_BADCTRL || warning == mjWARN_CONTACTFULL || warning == mjWARN_CNSTRFULL;
}

const char* warningName(int warning) {
  switch (warning) {
    case mjWARN_INERTIA:
      return "singular inertia matrix";
    case mjWARN_CONTACTFULL:
      return "contact buffer full (nconmax): contacts were dropped";
    case mjWARN_CNSTRFULL:
      return "constraint buffer full (njmax): constraints were dropped";
    case mjWARN_BADQPOS:
      return "bad qpos: MuJoCo reset the state";
    case mjWARN_BADQVEL:
      return "bad qvel: MuJoCo reset the state";
    case mjWARN_BADQACC:
      return "bad qacc (unstable): MuJoCo reset the state";
    case mjWARN_BADCTRL:
      return "bad ctrl: MuJoCo reset the state";
    default:
      return "warning";
  }
}

Quaternion quaternionAt(const mjtNum* wxyz) {
  return Quaternion(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
}

pbd::Matrix3 worldInertia(const pbd::RigidBodyDesc& body) {
  const pbd::Matrix3 r = body.initialPrincipalRotation().toRotationMatrix();
  return r * body.massProperties.principalInertia.asDiagonal() * r.transpose();
}

}  // namespace

void MujocoEngine::ModelDeleter::operator()(mjModel_* m) const {
  mj_deleteModel(m);
}
void MujocoEngine::DataDeleter::operator()(mjData_* d) const {
  mj_deleteData(d);
}

MujocoEngine::MujocoEngine() = default;
MujocoEngine::~MujocoEngine() = default;

std::vector<std::string> MujocoEngine::unsupported(const pbd::Scene& scene,
                                                   const Method& method) const {
  std::vector<std::string> missing;
  for (UnsupportedUse& use :
       unsupportedUses(mujocoFeatures(), mujoco::featureUses(scene), method.name))
    missing.push_back(std::move(use.message));
  return missing;
}

void MujocoEngine::load(const pbd::Scene& scene, const Method& method) {
  failed_ = true;  // until the model is complete
  settings_ = mujoco::mujocoSettingsFor(scene, method);
  const std::vector<std::string> missing = unsupported(scene, method);
  if (!missing.empty()) throw EngineError("MuJoCo cannot represent " + missing.front());
  warnings_.clear();
  data_.reset();
  model_.reset();
  mjcf_ = mujoco::writeMjcf(scene, settings_, mujoco::planKinematicTree(scene));
  for (const std::string& note : mjcf_.approximations)
    warnings_.push_back(note);
  compile();
  indexBodies(scene);
  forward("mj_forward (initial state)");
  projectInitialVelocities(scene);
  forward("mj_forward (initial velocities)");
  tuneServos(scene);
  warningCounts_.assign(mjNWARNING, 0);
  failed_ = false;
  checkWarnings();
}

void MujocoEngine::indexBodies(const pbd::Scene& scene) {
  bodyIds_.clear();
  sceneIds_.clear();
  principalRotations_.clear();
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    bodyIds_.push_back(mj_name2id(model_.get(), mjOBJ_BODY, mujoco::bodyName(i).c_str()));
    sceneIds_.push_back(scene.rigidBodies[i].id);
    principalRotations_.push_back(scene.rigidBodies[i].massProperties.principalRotation);
  }
}

void MujocoEngine::compile() {
  model_.reset(mujoco::compileMjcf(mjcf_.xml, warnings_));
  mjData* data = nullptr;
  guarded("mj_makeData", warnings_, [&] { data = mj_makeData(model_.get()); });
  if (data == nullptr) throw EngineError("MuJoCo could not allocate mjData");
  data_.reset(data);
}

void MujocoEngine::forward(const char* what) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  try {
    guarded(what, warnings_, [m, d] { mj_forward(m, d); });
  } catch (const EngineError&) {
    failed_ = true;
    throw;
  }
}

// The Scene gives every body's velocity; MuJoCo's state is the joint velocities. The qvel
// closest to the Scene's velocities in the kinetic-energy norm solves M q̇ = Σ_b J_bᵀ (m v, I ω)
// (the generalized momentum of the Scene's velocities); it reproduces them exactly when they
// agree with the joints, and is recorded as a warning otherwise.
void MujocoEngine::projectInitialVelocities(const pbd::Scene& scene) {
  const mjModel* m = model_.get();
  mjData* d = data_.get();
  const std::size_t nv = std::size_t(m->nv);
  if (nv == 0) return;
  std::vector<mjtNum> momentum(nv, 0), jacp(3 * nv), jacr(3 * nv);
  using RowJacobian = Eigen::Map<Eigen::Matrix<mjtNum, 3, Eigen::Dynamic, Eigen::RowMajor>>;
  using Vector = Eigen::Map<Eigen::Matrix<mjtNum, Eigen::Dynamic, 1>>;
  // The Jacobians of body i's centre-of-mass velocity and angular velocity with respect to qvel.
  const RowJacobian linear(jacp.data(), 3, Eigen::Index(nv)),
      angular(jacr.data(), 3, Eigen::Index(nv));
  auto computeJacobians = [&](std::size_t i) {
    mj_jacBodyCom(m, d, jacp.data(), jacr.data(), bodyIds_[i]);
  };
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const pbd::RigidBodyDesc& b = scene.rigidBodies[i];
    if (!b.isDynamic) continue;
    computeJacobians(i);
    Vector(momentum.data(), Eigen::Index(nv)) +=
        linear.transpose() * (b.massProperties.mass * b.velocity) +
        angular.transpose() * (worldInertia(b) * b.angularVelocity);
  }
  mj_solveM(m, d, d->qvel, momentum.data(), 1);
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const pbd::RigidBodyDesc& b = scene.rigidBodies[i];
    if (!b.isDynamic) continue;
    computeJacobians(i);
    const Vector qvel(d->qvel, Eigen::Index(nv));
    const double mismatch =
        (linear * qvel - b.velocity).norm() + (angular * qvel - b.angularVelocity).norm();
    const double scale = b.velocity.norm() + b.angularVelocity.norm();
    if (mismatch > 1e-9 * (1 + scale)) {
      std::ostringstream note;
      note << b.jsonPath << ": initial velocity disagrees with its joints by " << mismatch
           << "; projected onto them (kinetic-energy norm)";
      warnings_.push_back(note.str());
    }
  }
}

// Motors are critically damped servos on the driven joint: with m = 1/(M⁻¹)ᵢᵢ at t = 0 (the
// inertia the actuator sees) and τ = servoTimeconst, a position servo applies
// kp (q* − q) − kv q̇ with kp = m/τ², kv = 2m/τ; a velocity servo kv (q̇* − q̇) with kv = m/τ.
void MujocoEngine::tuneServos(const pbd::Scene& scene) {
  mjModel* m = model_.get();
  mjData* d = data_.get();
  servos_.clear();
  std::vector<mjtNum> unit(std::size_t(m->nv), 0), column(std::size_t(m->nv), 0);
  for (const mujoco::MotorBinding& motor : mjcf_.motors) {
    Servo servo;
    servo.actuator = mj_name2id(m, mjOBJ_ACTUATOR, motor.actuatorName.c_str());
    const int joint = mj_name2id(m, mjOBJ_JOINT, motor.jointName.c_str());
    const std::size_t dof = std::size_t(m->jnt_dofadr[joint]);
    unit.assign(unit.size(), 0);
    unit[dof] = 1;
    mj_solveM(m, d, column.data(), unit.data(), 1);
    servo.inertia = 1 / column[dof];
    const double tau = settings_.servoTimeConstant;
    servo.velocityServo = motor.velocityServo;
    servo.kv = servo.velocityServo ? servo.inertia / tau : 2 * servo.inertia / tau;
    servo.kp = servo.velocityServo ? 0 : servo.inertia / (tau * tau);
    mjtNum* gain = m->actuator_gainprm + mjNGAIN * servo.actuator;
    mjtNum* bias = m->actuator_biasprm + mjNBIAS * servo.actuator;
    gain[0] = servo.velocityServo ? servo.kv : servo.kp;
    bias[0] = 0;
    bias[1] = -servo.kp;
    bias[2] = -servo.kv;
    const pbd::JointDesc& j = scene.joints[std::size_t(motor.joint)];
    servo.jointPath = j.jsonPath;
    servo.target = j.target;
    d->ctrl[servo.actuator] = servo.target.valueAt(Real(d->time));
    servos_.push_back(servo);
  }
}

void MujocoEngine::step() {
  if (failed_) throw EngineError("MuJoCo: this run already failed; load the scene again");
  mjModel* m = model_.get();
  mjData* d = data_.get();
  // Set points for the end of the step being taken, as the PBD motors use them.
  const Real next = Real(d->time + m->opt.timestep);
  for (const Servo& servo : servos_)
    d->ctrl[servo.actuator] = servo.target.valueAt(next);
  stepEndTime_ = double(next);  // a bad-state reset sets d->time back to 0
  try {
    guarded("mj_step", warnings_, [m, d] {
      mj_step(m, d);
      // mj_step leaves positions-derived quantities at the start of the step: refresh the
      // poses and velocities read() uses (the next mj_step recomputes them anyway).
      mj_kinematics(m, d);
      mj_comPos(m, d);
      mj_comVel(m, d);
    });
  } catch (const EngineError&) {
    failed_ = true;
    throw;
  }
  checkWarnings();
}

// MuJoCo counts each kind of warning in mjData; a fatal kind ends the run, the others are
// recorded once (with their count in effectiveSettings).
void MujocoEngine::checkWarnings() {
  const mjData* d = data_.get();
  for (int w = 0; w < mjNWARNING; ++w) {
    const int count = d->warning[w].number;
    const int seen = warningCounts_[std::size_t(w)];
    if (count == seen) continue;
    warningCounts_[std::size_t(w)] = count;
    std::ostringstream message;
    message << "MuJoCo at t = " << stepEndTime_ << " s: " << warningName(w) << " (info "
            << d->warning[w].lastinfo << ")";
    if (isFatal(w)) {
      failed_ = true;
      const bool unstable = w == mjWARN_BADQPOS || w == mjWARN_BADQVEL || w == mjWARN_BADQACC;
      if (unstable) throw EngineDivergence(message.str());
      throw EngineError(message.str());
    }
    if (seen == 0) warnings_.push_back(message.str());
  }
}

void MujocoEngine::read(State& state) const {
  const mjModel* m = model_.get();
  const mjData* d = data_.get();
  state.time = d->time;
  state.bodies.resize(bodyIds_.size());
  state.particles.clear();
  for (std::size_t i = 0; i < bodyIds_.size(); ++i) {
    const int id = bodyIds_[i];
    BodyState& s = state.bodies[i];
    s.id = sceneIds_[i];
    // The body frame is the principal frame: its origin is the centre of mass.
    s.position = Vector3(d->xpos[3 * id], d->xpos[3 * id + 1], d->xpos[3 * id + 2]);
    s.rotation = quaternionAt(d->xquat + 4 * id) * principalRotations_[i].conjugate();
    mjtNum velocity[6];  // [ω; v] at the body frame's origin, world axes
    mj_objectVelocity(m, d, mjOBJ_XBODY, id, velocity, 0);
    s.angularVelocity = Vector3(velocity[0], velocity[1], velocity[2]);
    s.velocity = Vector3(velocity[3], velocity[4], velocity[5]);
  }
}

std::map<std::string, std::string> MujocoEngine::effectiveSettings() const {
  std::map<std::string, std::string> s = mujoco::describeSettings(settings_);
  const mjModel* m = model_.get();
  s["engine"] = std::string("MuJoCo ") + mj_versionString();
  s["precision"] = "double";
  s["coordinates"] = "reduced (kinematic tree; loops closed by equality constraints)";
  s["contact.pairs"] = std::to_string(mjcf_.contactPairs);
  s["jointedBodiesCollide"] =
      "yes (as in the seed): " + std::to_string(mjcf_.jointedContactPairs) +
      " of the pairs join bodies connected by a joint; explicit <pair>s, which MuJoCo never "
      "filters, and filterparent disabled";
  s["contact.condim"] = "3 (sliding friction only; 1 when the pair friction is 0)";
  s["contact.margin"] = "0";
  s["contact.gap"] = "0";
  s["impratio"] = "1";
  s["noslip_iterations"] = "0";
  s["damping"] = "0 (joints, tendons, medium)";
  s["armature"] = "0";
  s["frictionloss"] = "0";
  s["sleeping"] = "none (MuJoCo 2.2.2 has no sleeping)";
  s["substeps"] = "none (one mj_step per step; RK4 evaluates 4 stages)";
  s["equality.constraints"] = std::to_string(mjcf_.equalityConstraints);
  if (m != nullptr) {
    s["nconmax"] = std::to_string(m->nconmax);
    s["njmax"] = std::to_string(m->njmax);
    s["gravity"] = pbd::formatReal(m->opt.gravity[0]) + " " + pbd::formatReal(m->opt.gravity[1]) +
                   " " + pbd::formatReal(m->opt.gravity[2]);
  }
  for (const auto& [pair, law] : mjcf_.pairSettings)
    s["contact." + pair] = law;
  for (const Servo& servo : servos_)
    s["servo." + servo.jointPath] =
        std::string(servo.velocityServo ? "velocity" : "position (PD)") +
        " kp=" + pbd::formatReal(servo.kp) + " kv=" + pbd::formatReal(servo.kv) +
        " joint inertia=" + pbd::formatReal(servo.inertia);
  for (std::size_t w = 0; w < warningCounts_.size(); ++w)
    if (warningCounts_[w] > 0)
      s[std::string("warning.count.") + warningName(int(w))] = std::to_string(warningCounts_[w]);
  for (std::size_t i = 0; i < warnings_.size(); ++i)
    s["warning." + std::to_string(i)] = warnings_[i];
  return s;
}

RunFacts MujocoEngine::runFacts() const {
  RunFacts facts;
  facts.engineVersion = std::string("MuJoCo ") + mj_versionString();
  facts.integratorStepsPerSceneStep = 1;  // one mj_step per step (RK4: 4 stages of one step)
  facts.contactMargin = 0;                // contact.margin 0; soft contacts are no margin
  // Generalised coordinates: the scene's initial velocities enter projected onto the joints.
  facts.initialVelocitiesProjected = true;
  return facts;
}

EngineEntry mujocoEngineEntry() {
  EngineEntry entry;
  entry.name = "mujoco";
  entry.defaultMethod = "mujoco.euler";
  entry.methods = mujoco::mujocoMethods();
  entry.honouredSettings = {"timeStepSize", "gravitation"};
  entry.features = mujocoFeatures();
  entry.make = [](const EngineOptions&) { return std::unique_ptr<Engine>(new MujocoEngine()); };
  return entry;
}

}  // namespace pbdval
