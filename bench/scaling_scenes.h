// Generated scenes for the scaling benchmarks (bench/bench_step.cpp, docs/benchmarks.md#scaling):
// families of one shape whose body count grows from 10 to 10,000 while the work per body stays
// the same, so a linear-time engine takes a time per step proportional to the body count.
//
//   chain  N boxes 5 × 2 × 2 cm, 1000 kg/m³, on ball joints, hanging from a static box and
//          released horizontally: chain_100's links and settings (h = 5 ms, 5 substeps × 1
//          iteration), N links instead of 100. No collision objects.
//   spheres N spheres r = 0.1 m in two layers on a static ground box, the upper layer over the
//          hollows of the lower one (every sphere touches the ground or four spheres below it):
//          contact_sphere_pile's spheres and settings on a square floor grown with N.
//   boxes  N cubes of 0.2 m, the same two-layer pattern (the upper cubes bridge four lower ones).
//
// Each scene is written as the seed's scene JSON and read by the loader, as a case file is.
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

namespace pbdval::bench {

inline nlohmann::json scalingSettings(bool contacts) {
  nlohmann::json s = {{"timeStepSize", 0.005}, {"subSteps", 5},         {"maxIterations", 1},
                      {"maxIterationsV", 5},   {"gravitation", {0, -9.81, 0}}};
  if (contacts) s["contactStiffnessRigidBody"] = 10;
  return s;
}

/// chain_100's links, `links` of them.
inline std::string chainScene(int links, const std::string& modelFolder) {
  nlohmann::json scene;
  scene["Name"] = "scaling_chain_" + std::to_string(links);
  scene["Simulation"] = scalingSettings(false);
  nlohmann::json bodies = nlohmann::json::array();
  nlohmann::json joints = nlohmann::json::array();
  bodies.push_back({{"id", 0}, {"geometryFile", modelFolder + "/cube.obj"}, {"isDynamic", false},
                    {"translation", {0, 2, 0}}, {"scale", {0.1, 0.1, 0.1}},
                    {"collisionObjectType", 0}});
  for (int i = 1; i <= links; ++i) {
    bodies.push_back({{"id", i}, {"geometryFile", modelFolder + "/cube.obj"}, {"density", 1000},
                      {"translation", {0.05 * i - 0.025, 2, 0}}, {"scale", {0.05, 0.02, 0.02}},
                      {"collisionObjectType", 0}});
    joints.push_back({{"bodyID1", i - 1}, {"bodyID2", i}, {"position", {0.05 * (i - 1), 2, 0}}});
  }
  scene["RigidBodies"] = bodies;
  scene["BallJoints"] = joints;
  return scene.dump();
}

/// `count` spheres (or cubes) in two layers on a square floor.
inline std::string pileScene(int count, bool boxes, const std::string& modelFolder) {
  const double size = 0.2;       // sphere diameter or cube edge
  const double spacing = 0.21;   // 1 cm between neighbours of a layer
  const int lower = (count + 1) / 2;
  const int side = int(std::ceil(std::sqrt(double(lower))));
  const double floor = side * spacing + 1.0;  // 0.5 m beyond the pile on every side
  nlohmann::json scene;
  scene["Name"] = std::string("scaling_") + (boxes ? "boxes_" : "spheres_") + std::to_string(count);
  scene["Simulation"] = scalingSettings(true);
  nlohmann::json bodies = nlohmann::json::array();
  bodies.push_back({{"id", 0}, {"geometryFile", modelFolder + "/cube.obj"}, {"isDynamic", false},
                    {"translation", {0, -0.5, 0}}, {"scale", {floor, 1, floor}},
                    {"collisionObjectType", 2}, {"collisionObjectScale", {floor, 1, floor}},
                    {"restitution", 0.3}, {"friction", 0.25}});
  const double origin = -0.5 * (side - 1) * spacing;
  for (int i = 0; i < count; ++i) {
    const bool upper = i >= lower;
    const int k = upper ? i - lower : i;
    const double x = origin + (k % side) * spacing + (upper ? 0.5 * spacing : 0);
    const double z = origin + (k / side) * spacing + (upper ? 0.5 * spacing : 0);
    // The upper layer starts 1 cm above where it would rest on the lower one.
    const double y = upper ? (boxes ? 0.31 : 0.255) : 0.105;
    nlohmann::json body = {{"id", i + 1}, {"density", 500}, {"translation", {x, y, z}},
                           {"restitution", 0.3}, {"friction", 0.25}};
    if (boxes) {
      body["geometryFile"] = modelFolder + "/cube.obj";
      body["scale"] = {size, size, size};
      body["collisionObjectType"] = 2;
      body["collisionObjectScale"] = {size, size, size};
    } else {
      body["collisionObjectType"] = 1;
      body["collisionObjectScale"] = {0.5 * size, 0.5 * size, 0.5 * size};
    }
    bodies.push_back(body);
  }
  scene["RigidBodies"] = bodies;
  return scene.dump();
}

}  // namespace pbdval::bench
