#include "pbd/io/scene_writer.h"

#include <nlohmann/json.hpp>

#include "scene_reading.h"

namespace pbd {
namespace {

using scene_io::Json;
using scene_io::writeBoolean;
using scene_io::writeInteger;
using scene_io::writeNumber;
using scene_io::writeString;
using scene_io::writeVector;

void writePose(Json& o, const Vector3& translation, const std::optional<GivenRotation>& rotation,
               const Vector3& scale) {
  writeVector(o, "translation", translation);
  if (rotation) {
    writeVector(o, "rotationAxis", rotation->axis);
    writeNumber(o, "rotationAngle", rotation->angle);
  }
  writeVector(o, "scale", scale);
}

Json integers(const std::vector<int>& values) {
  Json array = Json::array();
  for (int v : values)
    array.push_back(v);
  return array;
}

Json rigidBodyJson(const RigidBodyDesc& b, const scene_io::LoadContext& context) {
  Json o = Json::object();
  writeInteger(o, "id", b.id);
  writeBoolean(o, "isDynamic", b.isDynamic);
  writeNumber(o, "density", b.density);
  if (!b.geometryFile.empty()) writeString(o, "geometryFile", b.geometryFile);
  writePose(o, b.translation, b.givenRotation, b.scale);
  writeVector(o, "velocity", b.velocity);
  writeVector(o, "angularVelocity", b.angularVelocity);
  writeNumber(o, "restitution", b.restitution);
  writeNumber(o, "friction", b.friction);
  writeBoolean(o, "flatShading", b.flatShading);
  scene_io::writeKeys(scene_io::collisionKeys(context), b.collision, o);
  if (b.givenMass) writeNumber(o, "mass", *b.givenMass);
  if (b.givenInertia) writeVector(o, "inertia", *b.givenInertia);
  return o;
}

template <class Model>
void writeModelKeys(Json& o, const Model& m) {
  writeInteger(o, "id", m.id);
  o["staticParticles"] = integers(m.staticParticles);
  writeNumber(o, "restitution", m.restitution);
  writeNumber(o, "friction", m.friction);
  if (m.density) writeNumber(o, "density", *m.density);
  writePose(o, m.translation, m.givenRotation, m.scale);
}

Json jointJson(const JointDesc& j) {
  using namespace scene_io;
  const unsigned keys = jointKeys(j.type);
  Json o = Json::object();
  if (keys & kTwoBodies) {
    writeInteger(o, "bodyID1", j.bodyId1);
    writeInteger(o, "bodyID2", j.bodyId2);
  }
  if (keys & kBodyAndParticle) {
    writeInteger(o, "rbID", j.bodyId1);
    writeInteger(o, "particleID", j.particle);
  }
  if (keys & kPosition) writeVector(o, "position", j.position);
  if (keys & kTwoPositions) {
    writeVector(o, "position1", j.position1);
    writeVector(o, "position2", j.position2);
  }
  if (keys & kAxis) writeVector(o, "axis", j.axis);
  if (keys & kTwoAxes) {
    writeVector(o, "axis1", j.axis1);
    writeVector(o, "axis2", j.axis2);
  }
  if (keys & kStiffness) writeNumber(o, "stiffness", j.stiffness);
  if (j.type == JointType::StiffRod) {
    writeInteger(o, "id", j.stiffRod.id);
    writeVector(o, "stiffnessModifier", j.stiffRod.stiffnessModifier);
  }
  if (keys & kMotor) {
    if (j.target.hasSequence()) {
      Json flat = Json::array();
      for (std::size_t i = 0; i < j.target.times.size(); ++i) {
        flat.push_back(double(j.target.times[i]));
        flat.push_back(double(j.target.values[i]));
      }
      o["targetSequence"] = flat;
    } else {
      writeNumber(o, "target", j.target.constant);
    }
    writeBoolean(o, "repeatSequence", j.target.repeat);
  }
  return o;
}

}  // namespace

std::string writeSceneJson(const Scene& scene) {
  using namespace scene_io;
  const LoadContext context{std::filesystem::path(".")};  // the collision table's file key
  Json root = Json::object();
  if (!scene.name.empty()) writeString(root, "Name", scene.name);
  writeVector(root, "cameraPosition", scene.viewer.cameraPosition);
  writeVector(root, "cameraLookat", scene.viewer.cameraLookat);

  Json simulation = Json::object();
  writeKeys(simulationKeys(), scene.simulation, simulation);
  // A cloth or solid setting nothing in this scene reads is left out when it has its default
  // value (reading it back gives the same), so a clean scene writes no key the loader would
  // warn about; a non-default one is kept (the round trip is exact) and warned about on reading.
  Json defaults = Json::object();
  writeKeys(simulationKeys(), SimulationSettings{}, defaults);
  for (auto it = simulation.begin(); it != simulation.end();) {
    const bool unused = !unusedModelSettingReason(it.key(), scene).empty();
    const auto standard = defaults.find(it.key());
    if (unused && standard != defaults.end() && *standard == it.value())
      it = simulation.erase(it);
    else
      ++it;
  }
  writeKeys(viewerKeys(), scene.viewer, simulation);
  if (scene.lineModels.empty())  // they would only draw the "ignored" warning when read back
    for (const char* key :
         {"rod_stretchingStiffness", "rod_shearingStiffnessX", "rod_shearingStiffnessY",
          "rod_bendingStiffnessX", "rod_bendingStiffnessY", "rod_twistingStiffness"})
      simulation.erase(key);
  root["Simulation"] = simulation;

  Json bodies = Json::array();
  for (const RigidBodyDesc& b : scene.rigidBodies)
    bodies.push_back(rigidBodyJson(b, context));
  if (!scene.rigidBodies.empty()) root["RigidBodies"] = bodies;

  if (!scene.triangleModels.empty()) {
    Json models = Json::array();
    for (const TriangleModelDesc& m : scene.triangleModels) {
      Json o = Json::object();
      writeString(o, "geometryFile", m.geometryFile);
      writeModelKeys(o, m);
      models.push_back(o);
    }
    root["TriangleModels"] = models;
  }
  if (!scene.tetModels.empty()) {
    Json models = Json::array();
    for (const TetModelDesc& m : scene.tetModels) {
      Json o = Json::object();
      writeString(o, "nodeFile", m.nodeFile);
      writeString(o, "eleFile", m.eleFile);
      if (!m.visFile.empty()) writeString(o, "visFile", m.visFile);
      writeModelKeys(o, m);
      // Only the collision keys a tet model uses (the others warn when read).
      Json collision = Json::object();
      writeKeys(collisionKeys(context), m.collision, collision);
      for (const char* key : {"collisionObjectType", "testMesh"})
        if (collision.contains(key)) o[key] = collision[key];
      models.push_back(o);
    }
    root["TetModels"] = models;
  }
  if (!scene.lineModels.empty()) {
    Json models = Json::array();
    for (const LineModelDesc& m : scene.lineModels) {
      Json o = Json::object();
      writeInteger(o, "id", m.id);
      Json points = Json::array();
      for (const Vector3& p : m.points)
        points.push_back({double(p.x()), double(p.y()), double(p.z())});
      o["points"] = points;
      o["staticParticles"] = integers(m.staticParticles);
      o["staticSegments"] = integers(m.staticSegments);
      if (m.radius) writeNumber(o, "radius", *m.radius);
      if (m.density) writeNumber(o, "density", *m.density);
      if (m.youngsModulus) writeNumber(o, "youngsModulus", *m.youngsModulus);
      if (m.shearModulus) writeNumber(o, "shearModulus", *m.shearModulus);
      if (m.usesModuli()) writeNumber(o, "shearFactor", m.shearFactor);
      models.push_back(o);
    }
    root["LineModels"] = models;
  }
  if (!scene.fluidModels.empty()) {
    Json models = Json::array();
    const auto boxJson = [](const AxisAlignedBox& box) {
      Json o = Json::object();
      writeVector(o, "min", box.min);
      writeVector(o, "max", box.max);
      return o;
    };
    for (const FluidModelDesc& m : scene.fluidModels) {
      Json o = Json::object();
      writeKeys(fluidModelKeys(), m, o);
      Json blocks = Json::array();
      for (const AxisAlignedBox& block : m.blocks)
        blocks.push_back(boxJson(block));
      o["blocks"] = blocks;
      if (m.container) o["container"] = boxJson(*m.container);
      if (!m.particles.empty()) {
        Json listed = Json::array();
        for (const Vector3& x : m.particles)
          listed.push_back(Json{double(x.x()), double(x.y()), double(x.z())});
        o["particles"] = listed;
      }
      if (!m.boundaryWalls.empty()) {
        Json walls = Json::array();
        for (const AxisAlignedBox& wall : m.boundaryWalls)
          walls.push_back(boxJson(wall));
        o["boundaryWalls"] = walls;
      }
      models.push_back(o);
    }
    root["FluidModels"] = models;
  }
  if (!scene.contactPairs.empty()) {
    Json pairs = Json::array();
    for (const ContactPairDesc& p : scene.contactPairs) {
      Json o = Json::object();
      writeInteger(o, "bodyID1", p.bodyId1);
      writeInteger(o, "bodyID2", p.bodyId2);
      if (p.hasFriction) writeNumber(o, "friction", p.friction);
      if (p.hasRestitution) writeNumber(o, "restitution", p.restitution);
      pairs.push_back(o);
    }
    root["ContactPairs"] = pairs;
  }
  for (int t = 0; t < kJointTypeCount; ++t) {
    const auto type = static_cast<JointType>(t);
    Json block = Json::array();
    for (const JointDesc& j : scene.joints)
      if (j.type == type) block.push_back(jointJson(j));
    if (!block.empty()) root[jointBlockName(type)] = block;
  }
  if (!scene.stiffRodTrees.empty()) {
    const auto bodyIds = [&](const std::vector<int>& indices) {
      Json ids = Json::array();
      for (int b : indices)
        ids.push_back(scene.rigidBodies[static_cast<std::size_t>(b)].id);
      return ids;
    };
    Json trees = Json::array();
    for (const StiffRodTreeDesc& tree : scene.stiffRodTrees) {
      Json o = Json::object();
      writeInteger(o, "id", tree.id);
      writeNumber(o, "youngsModulus", tree.youngsModulus);
      writeNumber(o, "torsionModulus", tree.torsionModulus);
      writeInteger(o, "solverType", static_cast<int>(tree.solver));
      o["rbIds"] = bodyIds(tree.bodies);
      o["staticSegments"] = bodyIds(tree.staticSegments);
      Json jointIds = Json::array();
      for (int j : tree.joints)
        jointIds.push_back(scene.joints[static_cast<std::size_t>(j)].stiffRod.id);
      o["jIds"] = jointIds;
      trees.push_back(o);
    }
    root["TreeModels"] = trees;
  }
  if (!scene.validationJson.empty()) root["Validation"] = Json::parse(scene.validationJson);
  return root.dump(2) + "\n";
}

}  // namespace pbd
