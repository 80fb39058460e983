#include "adapters/mujoco/mjcf_writer.h"

#include <algorithm>
#include <sstream>

#include "adapters/mujoco/contact_softness.h"
#include "pbd/io/number_text.h"

namespace pbdval::mujoco {
namespace {

using pbd::CollisionObjectType;
using pbd::JointDesc;
using pbd::JointType;
using pbd::Quaternion;
using pbd::RigidBodyDesc;
using pbd::Vector3;

/// A rigid frame in its parent: x_parent = position + rotation · x_local.
struct Pose {
  Vector3 position = Vector3::Zero();
  Quaternion rotation = Quaternion::Identity();

  Vector3 pointToLocal(const Vector3& world) const {
    return rotation.conjugate() * (world - position);
  }
  Vector3 directionToLocal(const Vector3& world) const { return rotation.conjugate() * world; }
  /// This pose expressed in `parent`'s frame.
  Pose relativeTo(const Pose& parent) const {
    return {parent.pointToLocal(position), (parent.rotation.conjugate() * rotation).normalized()};
  }
};

/// The MuJoCo body frame: the principal frame at t = 0.
Pose bodyFrame(const RigidBodyDesc& body) {
  return {body.initialCenterOfMass(), body.initialPrincipalRotation()};
}

/// The scene frame in the body (principal) frame.
Pose sceneFrameInBody(const RigidBodyDesc& body) {
  const Quaternion toPrincipal = body.massProperties.principalRotation.conjugate();
  return {toPrincipal * -body.massProperties.centerOfMass, toPrincipal.normalized()};
}

std::string num(double value) {
  return pbd::formatReal(value);
}
std::string vec(const Vector3& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}
std::string quat(const Quaternion& q) {  // MuJoCo order: w x y z
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}
std::string poseAttributes(const Pose& p) {
  return "pos=\"" + vec(p.position) + "\" quat=\"" + quat(p.rotation) + "\"";
}

std::string jointName(std::size_t joint, const char* part = "") {
  return "j" + std::to_string(joint) + part;
}
std::string siteName(std::size_t joint, char end) {
  return "s" + std::to_string(joint) + end;
}
std::string tendonName(std::size_t joint) {
  return "t" + std::to_string(joint);
}
std::string geomName(std::size_t body) {
  return "g" + std::to_string(body);
}

bool hasGeom(const RigidBodyDesc& body) {
  return body.collision.type != CollisionObjectType::None;
}

constexpr const char* kNoPassiveForces =
    "damping=\"0\" stiffness=\"0\" armature=\"0\" frictionloss=\"0\"";

bool isMotor(JointType type) {
  return type == JointType::TargetAngleMotorHinge || type == JointType::TargetVelocityMotorHinge ||
         type == JointType::TargetPositionMotorSlider ||
         type == JointType::TargetVelocityMotorSlider;
}

class MjcfWriter {
 public:
  MjcfWriter(const pbd::Scene& scene, const MujocoSettings& settings, const KinematicTree& tree)
      : scene_(scene), settings_(settings), tree_(tree), sites_(scene.rigidBodies.size()) {}

  MjcfModel write() {
    collectSites();
    const std::string contacts = contactPairs();
    const std::string equalities = equalityConstraints();
    out_ << "<mujoco model=\"pbdval\">\n";
    header();
    assets();
    out_ << "<worldbody>\n";
    for (int body : tree_.order)
      if (tree_.parent[std::size_t(body)] < 0) writeBody(body, 1);
    out_ << "</worldbody>\n";
    tendons();
    out_ << equalities << actuators() << contacts << "</mujoco>\n";
    model_.xml = out_.str();
    return model_;
  }

 private:
  const RigidBodyDesc& body(int index) const { return scene_.rigidBodies[std::size_t(index)]; }

  void header() {
    // Contact rows: ≤ 4 per contact (pyramidal condim 3); MuJoCo 2.2.2 allocates njmax² for
    // its constraint matrices, hence the cap. A full buffer stops the run (mujoco_engine.cpp).
    const int contacts = std::max(100, std::min(8 * model_.contactPairs, 16 * dynamicBodies()));
    const int rows = std::min(3000, std::max(500, 4 * contacts + 6 * model_.equalityConstraints));
    const Vector3 g = scene_.simulation.gravitation.cast<double>();
    out_ << "<compiler angle=\"radian\" inertiafromgeom=\"false\" coordinate=\"local\" "
            "fusestatic=\"false\" balanceinertia=\"false\" boundmass=\"0\" boundinertia=\"0\" "
            "settotalmass=\"-1\"/>\n"
         << "<size nconmax=\"" << contacts << "\" njmax=\"" << rows << "\"/>\n"
         << "<option timestep=\"" << num(settings_.stepSize) << "\" gravity=\"" << vec(g)
         << "\" integrator=\"" << settings_.integrator << "\" solver=\"" << settings_.solver
         << "\" iterations=\"" << settings_.iterations << "\" tolerance=\""
         << num(settings_.tolerance) << "\" cone=\"" << settings_.cone
         << "\" impratio=\"1\" noslip_iterations=\"0\" density=\"0\" viscosity=\"0\" "
            "wind=\"0 0 0\" collision=\"all\" jacobian=\"auto\">\n"
         // filterparent off: jointed bodies collide (the seed's rule). The explicit <pair>s are
         // never filtered anyway; the flag keeps it so should automatic contacts ever be used.
         << "  <flag constraint=\"enable\" equality=\"enable\" contact=\"enable\" "
            "passive=\"enable\" gravity=\"enable\" warmstart=\"enable\" actuation=\"enable\" "
            "refsafe=\"enable\" filterparent=\"disable\" override=\"disable\" "
            "energy=\"disable\" multiccd=\"disable\"/>\n"
         << "</option>\n";
  }

  int dynamicBodies() const {
    return int(std::count_if(scene_.rigidBodies.begin(), scene_.rigidBodies.end(),
                             [](const RigidBodyDesc& b) { return b.isDynamic; }));
  }

  void assets() {
    std::ostringstream meshes;
    for (std::size_t i = 0; i < scene_.rigidBodies.size(); ++i) {
      const RigidBodyDesc& b = scene_.rigidBodies[i];
      if (b.collision.type != CollisionObjectType::SignedDistanceField) continue;
      meshes << "  <mesh name=\"m" << i << "\" vertex=\"";
      for (const Vector3& v : b.mesh->vertices)
        meshes << vec(v.cwiseProduct(b.collision.scale)) << "  ";
      meshes << "\" face=\"";
      for (const auto& t : b.mesh->triangles)
        meshes << t[0] << " " << t[1] << " " << t[2] << "  ";
      meshes << "\"/>\n";
      model_.approximations.push_back(
          b.jsonPath + ": signed-distance-field body collides as the convex hull of its mesh");
    }
    if (meshes.tellp() > 0) out_ << "<asset>\n" << meshes.str() << "</asset>\n";
  }

  void writeBody(int index, int depth) {
    const std::string indent(std::size_t(2 * depth), ' ');
    const RigidBodyDesc& b = body(index);
    const int parent = tree_.parent[std::size_t(index)];
    const Pose frame = parent < 0 ? bodyFrame(b) : bodyFrame(b).relativeTo(bodyFrame(body(parent)));
    out_ << indent << "<body name=\"" << bodyName(std::size_t(index)) << "\" "
         << poseAttributes(frame) << ">\n";
    if (b.isDynamic)
      out_ << indent << "  <inertial pos=\"0 0 0\" quat=\"1 0 0 0\" mass=\""
           << num(b.massProperties.mass) << "\" diaginertia=\""
           << vec(b.massProperties.principalInertia) << "\"/>\n";
    if (tree_.freeRoot[std::size_t(index)])
      out_ << indent << "  <freejoint name=\"free" << index << "\"/>\n";
    if (tree_.parentJoint[std::size_t(index)] >= 0) joints(index, indent + "  ");
    if (hasGeom(b)) geom(index, indent + "  ");
    for (const std::string& site : sites_[std::size_t(index)])
      out_ << indent << "  " << site;
    for (int child : tree_.children(index))
      writeBody(child, depth + 1);
    out_ << indent << "</body>\n";
  }

  // --- joints ---------------------------------------------------------------------------------

  /// One MuJoCo joint of a tree joint: name suffix, type, axis in the child's frame.
  struct JointElement {
    const char* suffix;
    const char* type;
    Vector3 axis;
  };

  /// The MuJoCo joints expressing scene joint `j` in `child` (in order: the first one turns
  /// about an axis fixed in the parent, a later one about an axis turned by the earlier ones).
  std::vector<JointElement> jointElements(const JointDesc& j, int child) const {
    const bool reversed = tree_.reversed[std::size_t(child)];
    const Pose frame = bodyFrame(body(child));
    // Seen from body 2, body 1 moves the opposite way: negate the axis so that joint values
    // and motor set points keep the Scene's sign (body 2 relative to body 1).
    const Vector3 axis = frame.directionToLocal((reversed ? -1 : 1) * j.axis);
    const Vector3 unused = Vector3::UnitZ();
    switch (j.type) {
      case JointType::Ball:
        return {{"", "ball", unused}};
      case JointType::Hinge:
      case JointType::TargetAngleMotorHinge:
      case JointType::TargetVelocityMotorHinge:
        return {{"", "hinge", axis}};
      case JointType::Slider:
      case JointType::Damper:
      case JointType::TargetPositionMotorSlider:
      case JointType::TargetVelocityMotorSlider:
        return {{"", "slide", axis}};
      case JointType::Universal: {
        // axis1 is fixed in body 1, axis2 in body 2: the parent's axis goes first.
        const Vector3 a1 = frame.directionToLocal(j.axis1), a2 = frame.directionToLocal(j.axis2);
        return {{"a", "hinge", reversed ? a2 : a1}, {"b", "hinge", reversed ? a1 : a2}};
      }
      case JointType::BallOnLine:
        // The line is fixed in body 1. As the parent: slide first (its axis stays fixed in the
        // parent). As the child: ball first, so the slide axis turns with the child.
        if (reversed) return {{"b", "ball", unused}, {"s", "slide", axis}};
        return {{"s", "slide", axis}, {"b", "ball", unused}};
      default:
        return {};  // never tree joints (kinematic_tree.cpp)
    }
  }

  void joints(int child, const std::string& indent) {
    const std::size_t k = std::size_t(tree_.parentJoint[std::size_t(child)]);
    const JointDesc& j = scene_.joints[k];
    const Vector3 anchor = bodyFrame(body(child)).pointToLocal(j.position);
    // The damper joint's spring: joint stiffness about the initial offset (springref 0).
    const std::string passive = j.type == JointType::Damper
                                    ? "damping=\"0\" stiffness=\"" + num(j.stiffness) +
                                          "\" springref=\"0\" armature=\"0\" frictionloss=\"0\""
                                    : kNoPassiveForces;
    for (const JointElement& e : jointElements(j, child))
      out_ << indent << "<joint name=\"" << jointName(k, e.suffix) << "\" type=\"" << e.type
           << "\" pos=\"" << vec(anchor) << "\" axis=\"" << vec(e.axis)
           << "\" limited=\"false\" ref=\"0\" " << passive << "/>\n";
  }

  // --- geoms and sites ------------------------------------------------------------------------

  void geom(int index, const std::string& indent) {
    const RigidBodyDesc& b = body(index);
    Pose pose = sceneFrameInBody(b);
    const Vector3& s = b.collision.scale;
    std::string shape;
    switch (b.collision.type) {
      case CollisionObjectType::Sphere:
        shape = "type=\"sphere\" size=\"" + num(s.x()) + "\"";
        break;
      case CollisionObjectType::Box:
        shape = "type=\"box\" size=\"" + vec(s / 2) + "\"";
        break;
      case CollisionObjectType::Cylinder:
        // MuJoCo's cylinder axis is z; the seed's is y: turn z onto y (−90° about x).
        pose.rotation =
            (pose.rotation * Quaternion(pbd::AngleAxis(-EIGEN_PI / 2, Vector3::UnitX())))
                .normalized();
        shape = "type=\"cylinder\" size=\"" + num(s.x()) + " " + num(s.y() / 2) + "\"";
        break;
      case CollisionObjectType::SignedDistanceField:
        shape = "type=\"mesh\" mesh=\"m" + std::to_string(index) + "\"";
        break;
      default:
        return;  // unsupported shapes are rejected before (mujocoFeatures())
    }
    out_ << indent << "<geom name=\"" << geomName(std::size_t(index)) << "\" " << shape << " "
         << poseAttributes(pose) << " contype=\"0\" conaffinity=\"0\" margin=\"0\" gap=\"0\"/>\n";
  }

  /// Sites of distance joints and springs, in the bodies' frames.
  void collectSites() {
    for (std::size_t k = 0; k < scene_.joints.size(); ++k) {
      const JointRole role = tree_.roles[k];
      if (role != JointRole::DistanceTendon && role != JointRole::SpringTendon) continue;
      const JointDesc& j = scene_.joints[k];
      addSite(j.body1, siteName(k, 'a'), j.position1);
      addSite(j.body2, siteName(k, 'b'), j.position2);
    }
  }
  void addSite(int index, const std::string& name, const Vector3& world) {
    const Vector3 local = bodyFrame(body(index)).pointToLocal(world);
    sites_[std::size_t(index)].push_back("<site name=\"" + name + "\" pos=\"" + vec(local) +
                                         "\"/>\n");
  }

  void tendons() {
    std::ostringstream t;
    for (std::size_t k = 0; k < scene_.joints.size(); ++k) {
      const JointRole role = tree_.roles[k];
      if (role != JointRole::DistanceTendon && role != JointRole::SpringTendon) continue;
      const JointDesc& j = scene_.joints[k];
      const double stiffness = role == JointRole::SpringTendon ? double(j.stiffness) : 0;
      t << "  <spatial name=\"" << tendonName(k) << "\" limited=\"false\" stiffness=\""
        << num(stiffness) << "\" damping=\"0\" frictionloss=\"0\" springlength=\""
        << num((j.position2 - j.position1).norm()) << "\">\n"
        << "    <site site=\"" << siteName(k, 'a') << "\"/><site site=\"" << siteName(k, 'b')
        << "\"/>\n  </spatial>\n";
    }
    if (t.tellp() > 0) out_ << "<tendon>\n" << t.str() << "</tendon>\n";
  }

  // --- constraints, actuators, contacts -------------------------------------------------------

  std::string solimp() const {
    std::string text;
    for (double v : settings_.solimp)
      text += (text.empty() ? "" : " ") + num(v);
    return text;
  }

  std::string softness() const {
    return "solref=\"" + num(settings_.equalitySolref[0]) + " " + num(settings_.equalitySolref[1]) +
           "\" solimp=\"" + solimp() + "\"";
  }

  std::string connect(const JointDesc& j, const Vector3& world) {
    ++model_.equalityConstraints;
    return "  <connect body1=\"" + bodyName(std::size_t(j.body1)) + "\" body2=\"" +
           bodyName(std::size_t(j.body2)) + "\" anchor=\"" +
           vec(bodyFrame(body(j.body1)).pointToLocal(world)) + "\" " + softness() + "/>\n";
  }

  /// Lever arm of a hinge closure's second connect: the farther centre of mass from the
  /// anchor, at least 0.1 m (the axis' misalignment angle is the second point's error / arm).
  double hingeArm(const JointDesc& j) const {
    return std::max({0.1, (body(j.body1).initialCenterOfMass() - j.position).norm(),
                     (body(j.body2).initialCenterOfMass() - j.position).norm()});
  }

  std::string equalityConstraints() {
    std::ostringstream e;
    for (std::size_t k = 0; k < scene_.joints.size(); ++k) {
      const JointDesc& j = scene_.joints[k];
      if (tree_.roles[k] == JointRole::LoopClosure) {
        e << connect(j, j.position);
        if (j.type == JointType::Hinge) e << connect(j, j.position + hingeArm(j) * j.axis);
      } else if (tree_.roles[k] == JointRole::DistanceTendon) {
        ++model_.equalityConstraints;
        e << "  <tendon tendon1=\"" << tendonName(k) << "\" polycoef=\"0 0 0 0 0\" " << softness()
          << "/>\n";
      }
    }
    return e.tellp() > 0 ? "<equality>\n" + e.str() + "</equality>\n" : "";
  }

  /// Gains are set after compilation, from the joint-space inertia (mujoco_engine.cpp).
  std::string actuators() {
    std::ostringstream a;
    for (std::size_t k = 0; k < scene_.joints.size(); ++k) {
      const JointDesc& j = scene_.joints[k];
      if (tree_.roles[k] != JointRole::Tree || !isMotor(j.type)) continue;
      MotorBinding motor;
      motor.joint = int(k);
      motor.actuatorName = "motor" + std::to_string(k);
      motor.jointName = jointName(k);
      motor.velocityServo = j.type == JointType::TargetVelocityMotorHinge ||
                            j.type == JointType::TargetVelocityMotorSlider;
      a << "  <general name=\"" << motor.actuatorName << "\" joint=\"" << motor.jointName
        << "\" dyntype=\"none\" gaintype=\"fixed\" gainprm=\"0\" biastype=\"affine\" "
           "biasprm=\"0 0 0\" ctrllimited=\"false\" forcelimited=\"false\"/>\n";
      model_.motors.push_back(motor);
    }
    return a.tellp() > 0 ? "<actuator>\n" + a.str() + "</actuator>\n" : "";
  }

  std::string contactPairs() {
    std::ostringstream c;
    const std::size_t n = scene_.rigidBodies.size();
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n; ++b) {
        const RigidBodyDesc &ba = scene_.rigidBodies[a], &bb = scene_.rigidBodies[b];
        if (!hasGeom(ba) || !hasGeom(bb) || (!ba.isDynamic && !bb.isDynamic)) continue;
        const pbd::ContactMaterial material = scene_.pairMaterial(int(a), int(b));
        const DirectSolref law = contactSolref(settings_.contactTimeConstant, settings_.stepSize,
                                               double(material.restitution));
        const double mu = double(material.friction);
        c << "  <pair geom1=\"" << geomName(a) << "\" geom2=\"" << geomName(b) << "\" condim=\""
          << (mu > 0 ? 3 : 1) << "\" friction=\"" << num(mu) << " " << num(mu)
          << " 0 0 0\" solref=\"" << num(-law.stiffness) << " " << num(-law.damping)
          << "\" solimp=\"" << solimp() << "\" margin=\"0\" gap=\"0\"/>\n";
        ++model_.contactPairs;
        if (jointed(int(a), int(b))) ++model_.jointedContactPairs;
        model_.pairSettings.emplace_back(
            ba.jsonPath + "-" + bb.jsonPath,
            "mu=" + num(mu) + " e=" + num(double(material.restitution)) +
                " zeta=" + num(law.dampingRatio) + " stiffness=" + num(law.stiffness) +
                " damping=" + num(law.damping));
      }
    return c.tellp() > 0 ? "<contact>\n" + c.str() + "</contact>\n" : "";
  }

  /// Whether a joint connects Scene::rigidBodies[a] and [b] (either way round).
  bool jointed(int a, int b) const {
    return std::any_of(scene_.joints.begin(), scene_.joints.end(), [&](const JointDesc& j) {
      return (j.body1 == a && j.body2 == b) || (j.body1 == b && j.body2 == a);
    });
  }

  const pbd::Scene& scene_;
  const MujocoSettings& settings_;
  const KinematicTree& tree_;
  std::vector<std::vector<std::string>> sites_;
  std::ostringstream out_;
  MjcfModel model_;
};

}  // namespace

std::string bodyName(std::size_t index) {
  return "b" + std::to_string(index);
}

MjcfModel writeMjcf(const pbd::Scene& scene, const MujocoSettings& settings,
                    const KinematicTree& tree) {
  return MjcfWriter(scene, settings, tree).write();
}

}  // namespace pbdval::mujoco
