// The 13 joint blocks: which keys each takes, body and particle resolution, and the checks a
// joint's geometry needs (non-zero axes, perpendicular universal axes, distinct connector
// points, increasing motor sequences).
#include <cmath>
#include <map>

#include "scene_reading.h"

namespace pbd::scene_io {
namespace {

struct JointInput {
  JointDesc desc;
  std::optional<Real> target;
  std::optional<MotorTarget> sequence;
  bool repeat = false;
  bool repeatGiven = false;
  std::optional<Vector3> particleJointPosition;  ///< documented, but ignored by the seed
};

Vector3 readAxis(const JsonValue& value) {
  const Vector3 axis = value.vector3();
  const Real norm = axis.stableNorm();
  if (!(norm > 0)) value.fail("a non-zero axis");
  return axis / norm;
}

/// A flat [t0, v0, t1, v1, ...] array: even length >= 2, strictly increasing times.
MotorTarget readTargetSequence(const JsonValue& value) {
  const std::vector<Real> flat = value.numbers();
  if (flat.size() < 2 || flat.size() % 2 != 0) {
    value.fail(
        "a flat array [t0, v0, t1, v1, ...] of even length >= 2 (the seed silently "
        "drops an odd last entry)");
  }
  MotorTarget target;
  for (std::size_t i = 0; i < flat.size(); i += 2) {
    if (!target.times.empty() && !(flat[i] > target.times.back())) {
      value.elements("numbers")[i].fail("a time > " + formatNumber(target.times.back()) +
                                        " (sequence times must increase strictly)");
    }
    target.times.push_back(flat[i]);
    target.values.push_back(flat[i + 1]);
  }
  return target;
}

KeyReader<JointInput> bodyIdKey(const char* key, int JointDesc::*member) {
  return required(KeyReader<JointInput>{
      key, [member](const JsonValue& v, JointInput& j) { j.desc.*member = v.integer(); }});
}

KeyReader<JointInput> positionKey(const char* key, Vector3 JointDesc::*member) {
  return required(KeyReader<JointInput>{
      key, [member](const JsonValue& v, JointInput& j) { j.desc.*member = v.vector3(); }});
}

KeyReader<JointInput> axisKey(const char* key, Vector3 JointDesc::*member) {
  return required(KeyReader<JointInput>{
      key, [member](const JsonValue& v, JointInput& j) { j.desc.*member = readAxis(v); }});
}

KeyTable<JointInput> jointKeyTable(JointType type) {
  using J = JointInput;
  const unsigned keys = jointKeys(type);
  KeyTable<J> table;
  if (keys & kTwoBodies) {
    table.push_back(bodyIdKey("bodyID1", &JointDesc::bodyId1));
    table.push_back(bodyIdKey("bodyID2", &JointDesc::bodyId2));
  }
  if (keys & kBodyAndParticle) {
    table.push_back(bodyIdKey("rbID", &JointDesc::bodyId1));
    table.push_back(required(KeyReader<J>{"particleID", [](const JsonValue& v, J& j) {
                                            j.desc.particle = v.integer(nonNegative());
                                          }}));
    table.push_back(
        {"position", [](const JsonValue& v, J& j) { j.particleJointPosition = v.vector3(); }});
  }
  if (keys & kPosition) table.push_back(positionKey("position", &JointDesc::position));
  if (keys & kTwoPositions) {
    table.push_back(positionKey("position1", &JointDesc::position1));
    table.push_back(positionKey("position2", &JointDesc::position2));
  }
  if (keys & kAxis) table.push_back(axisKey("axis", &JointDesc::axis));
  if (keys & kTwoAxes) {
    table.push_back(axisKey("axis1", &JointDesc::axis1));
    table.push_back(axisKey("axis2", &JointDesc::axis2));
  }
  if (keys & kStiffness) {
    table.push_back(required(KeyReader<J>{
        "stiffness", [](const JsonValue& v, J& j) { j.desc.stiffness = v.number(positive()); }}));
  }
  if (keys & kMotor) {
    table.push_back({"target", [](const JsonValue& v, J& j) { j.target = v.number(); }});
    table.push_back(
        {"targetSequence", [](const JsonValue& v, J& j) { j.sequence = readTargetSequence(v); }});
    table.push_back({"repeatSequence", [](const JsonValue& v, J& j) {
                       j.repeat = v.boolean();
                       j.repeatGiven = true;
                     }});
  }
  return table;
}

/// Rigid-body ids → indices, to resolve the joints' body ids.
class BodyLookup {
 public:
  explicit BodyLookup(const Scene& scene) : scene_(scene) {
    for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i)
      indicesById_[scene.rigidBodies[i].id].push_back(static_cast<int>(i));
  }

  int indexOf(const JsonValue& idKey, int id) const {
    const auto it = indicesById_.find(id);
    if (it == indicesById_.end()) idKey.fail("the id of a rigid body (no rigid body has this id)");
    if (it->second.size() > 1) {
      std::string bodies;
      for (int i : it->second)
        bodies += (bodies.empty() ? "" : ", ") + path(i);
      idKey.error("id " + std::to_string(id) + " is ambiguous: " + bodies +
                  " share it; give the rigid bodies distinct ids");
    }
    return it->second.front();
  }

  const std::string& path(int index) const {
    return scene_.rigidBodies[static_cast<std::size_t>(index)].jsonPath;
  }

 private:
  const Scene& scene_;
  std::map<int, std::vector<int>> indicesById_;
};

void connectTwoBodies(JsonObject& object, const BodyLookup& bodies, JointDesc& joint) {
  joint.body1 = bodies.indexOf(*object.find("bodyID1"), joint.bodyId1);
  joint.body2 = bodies.indexOf(*object.find("bodyID2"), joint.bodyId2);
  if (joint.body1 == joint.body2) {
    object.error("bodyID1 and bodyID2 both refer to " + bodies.path(joint.body1) + " (id " +
                 std::to_string(joint.bodyId1) + "); a joint connects two different bodies");
  }
}

void connectBodyAndParticle(JsonObject& object, const BodyLookup& bodies, const Scene& scene,
                            JointInput& in) {
  JointDesc& joint = in.desc;
  joint.body1 = bodies.indexOf(*object.find("rbID"), joint.bodyId1);
  joint.body2 = -1;
  const std::size_t count = scene.particles.size();
  if (static_cast<std::size_t>(joint.particle) >= count) {
    object.find("particleID")
        ->fail(count == 0 ? std::string("a particle index (the scene has no particles)")
                          : "a particle index in [0, " + std::to_string(count - 1) +
                                "] (triangle-model vertices first, then tet-model vertices)");
  }
  joint.position = scene.particles[static_cast<std::size_t>(joint.particle)].position;
  // Relative round-off slack: the same point written twice must not warn.
  const Real slack = std::sqrt(kEpsilon) * (1 + joint.position.norm());
  if (in.particleJointPosition && (*in.particleJointPosition - joint.position).norm() > slack) {
    object.find("position")
        ->warn("ignored: the joint sits at particle " + std::to_string(joint.particle) + ", " +
               formatVector(joint.position) + " (the seed ignores this key too)");
  }
}

void checkJointGeometry(JsonObject& object, JointDesc& joint) {
  const unsigned keys = jointKeys(joint.type);
  if (keys & kTwoAxes) {
    const Real cosine = joint.axis1.dot(joint.axis2);
    // 1e-6: the joint holds axis1 · axis2 = 0 exactly; this admits axes written with about
    // six significant digits, and nothing a user would call "not perpendicular".
    if (std::abs(cosine) > Real(1e-6)) {
      object.find("axis2")->fail(
          "an axis perpendicular to axis1 (the universal joint holds "
          "axis1 · axis2 = 0; here cos = " +
          formatNumber(cosine) + ")");
    }
  }
  if (keys & kTwoPositions) {
    const Real length = (joint.position1 - joint.position2).norm();
    // Round-off slack relative to the coordinates: the points must really differ.
    const Real slack = std::sqrt(kEpsilon) * (1 + joint.position1.norm() + joint.position2.norm());
    if (!(length > slack)) {
      object.find("position2")
          ->fail(
              "a point different from position1 (the joint holds the distance between "
              "them, which must not be zero)");
    }
  }
}

/// The seed clamps target angles to [−π, π].
Real clampAngle(Real angle, const JsonValue& where) {
  const Real pi = Real(EIGEN_PI);
  if (std::abs(angle) <= pi) return angle;
  const Real clamped = angle > 0 ? pi : -pi;
  where.warn("target angle " + formatNumber(angle) + " clamped to " + formatNumber(clamped) +
             " (as in the seed, which limits motor angles to [-pi, pi])");
  return clamped;
}

MotorTarget resolveMotorTarget(JsonObject& object, JointInput& in) {
  MotorTarget motor;
  motor.repeat = in.repeat;
  motor.repeatGiven = in.repeatGiven;
  if (in.target) {
    motor.constant = *in.target;
    if (in.sequence) {
      object.find("targetSequence")
          ->warn("ignored: \"target\" is also given and wins (seed semantics)");
    }
  } else if (in.sequence) {
    motor.times = in.sequence->times;
    motor.values = in.sequence->values;
  }
  if (in.desc.type == JointType::TargetAngleMotorHinge) {
    if (in.target) motor.constant = clampAngle(motor.constant, *object.find("target"));
    if (motor.hasSequence()) {
      const auto entries = object.find("targetSequence")->elements("numbers");
      for (std::size_t i = 0; i < motor.values.size(); ++i)
        motor.values[i] = clampAngle(motor.values[i], entries[2 * i + 1]);
    }
  }
  return motor;
}

JointDesc readJoint(JointType type, const JsonValue& element, const BodyLookup& bodies,
                    const Scene& scene) {
  JsonObject object = element.object();
  JointInput in;
  in.desc.type = type;
  in.desc.jsonPath = element.path();
  readKeys(object, jointKeyTable(type), in);
  if (jointKeys(type) & kBodyAndParticle) {
    connectBodyAndParticle(object, bodies, scene, in);
  } else {
    connectTwoBodies(object, bodies, in.desc);
  }
  checkJointGeometry(object, in.desc);
  if (jointKeys(type) & kMotor) in.desc.target = resolveMotorTarget(object, in);
  object.warnUnknownKeys();
  return in.desc;
}

}  // namespace

int resolveBodyId(const JsonValue& idValue, const Scene& scene) {
  return BodyLookup(scene).indexOf(idValue, idValue.integer());
}

void readJoints(JsonObject& root, Scene& scene) {
  const BodyLookup bodies(scene);
  for (int t = 0; t < kJointTypeCount; ++t) {
    const auto type = static_cast<JointType>(t);
    if (type == JointType::StiffRod) continue;  // readStiffRods
    const auto block = root.find(jointBlockName(type));
    if (!block) continue;
    for (const JsonValue& element : block->elements("joint objects"))
      scene.joints.push_back(readJoint(type, element, bodies, scene));
  }
}

}  // namespace pbd::scene_io
