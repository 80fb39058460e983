// Generated scenes for the scaling benchmarks (bench/bench_step.cpp, docs/benchmarks.md#scaling):
// families of one shape whose body count grows from 10 to 10,000 while the work per body stays
// the same, so a linear-time engine takes a time per step proportional to the body count.
//
//   chain  N boxes 5 × 2 × 2 cm, 1000 kg/m³, on ball joints, hanging from a static box and
//          released horizontally: chain_100's links and settings (h = 5 ms, 5 substeps × 1
//          iteration), N links instead of 100. No collision objects.
//   spheres N/5 equal piles on one static ground box, on a square grid 0.8 m apart: four spheres
//          r = 0.1 m in a square (1 cm apart) and a fifth in their hollow, contact_sphere_pile's
//          spheres and settings. Every body has the same neighbours whatever N is, so the work
//          per body is the same (one contiguous pile would have a share of edge bodies with
//          fewer contacts that shrinks as N grows: its cost per body grows with N for every
//          engine, 1.2 as an exponent for Bullet too). The broad phase still sees all piles at
//          once: a sweep along x meets every pile of a column.
//   boxes  the same with cubes of 0.2 m, the fifth bridging the four below it.
//   cloth  a square sheet of n × n particles (N = n²), 1 m wide, 0.3 kg/m², pinned at two
//          corners: cloth_hanging's methods and settings (XPBD distances of 1000 N/m and XPBD
//          isometric bending; 5 substeps × 2 iterations), released flat. Every particle has the
//          same stencil, so the work per particle is the same for every N.
//   solid  a cube of n × n × n particles (N = n³), 0.1 m cells, Kuhn tets (pbd::tetLattice),
//          1000 kg/m³, XPBD FEM (solid method 3, E = 10⁶ Pa, ν = 0.3), hanging from its static
//          top face (5 substeps × 1 iteration).
//   rod    a straight Cosserat rod (LineModels) of N particles 1 cm apart, clamped at one end
//          (first particle and segment static), the seed's PBD variant with the default rod_*
//          stiffnesses, released horizontally (5 substeps x 1 iteration).
//   fluid  a cube of n x n x n fluid particles (N = n^3, r = 0.025 m, the seed's FluidDemo
//          parameters) in one corner of a container twice as long, collapsing as a dam break
//          (5 ms frames, 5 substeps, 5 Jacobi iterations).
//
// The rigid scenes are written as the seed's scene JSON and read by the loader, as a case file
// is; the particle scenes are built as pbd::Scene directly (their meshes would need files).
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "pbd/model/mass_properties.h"
#include "pbd/model/mesh.h"
#include "pbd/model/scene.h"

namespace pbdval::bench {

inline nlohmann::json scalingSettings(bool contacts) {
  nlohmann::json s = {{"timeStepSize", 0.005},
                      {"subSteps", 5},
                      {"maxIterations", 1},
                      {"maxIterationsV", 5},
                      {"gravitation", {0, -9.81, 0}}};
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
  bodies.push_back({{"id", 0},
                    {"geometryFile", modelFolder + "/cube.obj"},
                    {"isDynamic", false},
                    {"translation", {0, 2, 0}},
                    {"scale", {0.1, 0.1, 0.1}},
                    {"collisionObjectType", 0}});
  for (int i = 1; i <= links; ++i) {
    bodies.push_back({{"id", i},
                      {"geometryFile", modelFolder + "/cube.obj"},
                      {"density", 1000},
                      {"translation", {0.05 * i - 0.025, 2, 0}},
                      {"scale", {0.05, 0.02, 0.02}},
                      {"collisionObjectType", 0}});
    joints.push_back({{"bodyID1", i - 1}, {"bodyID2", i}, {"position", {0.05 * (i - 1), 2, 0}}});
  }
  scene["RigidBodies"] = bodies;
  scene["BallJoints"] = joints;
  return scene.dump();
}

/// `count` spheres (or cubes; a multiple of 5) in piles of five on a square floor.
inline std::string pileScene(int count, bool boxes, const std::string& modelFolder) {
  const double size = 0.2;      // sphere diameter or cube edge
  const double spacing = 0.21;  // 1 cm between the four lower bodies of a pile
  const double pitch = 0.8;     // between piles
  const int piles = count / 5;
  const int side = int(std::ceil(std::sqrt(double(piles))));
  const double floor = side * pitch + 1.0;
  nlohmann::json scene;
  scene["Name"] = std::string("scaling_") + (boxes ? "boxes_" : "spheres_") + std::to_string(count);
  scene["Simulation"] = scalingSettings(true);
  nlohmann::json bodies = nlohmann::json::array();
  bodies.push_back({{"id", 0},
                    {"geometryFile", modelFolder + "/cube.obj"},
                    {"isDynamic", false},
                    {"translation", {0, -0.5, 0}},
                    {"scale", {floor, 1, floor}},
                    {"collisionObjectType", 2},
                    {"collisionObjectScale", {floor, 1, floor}},
                    {"restitution", 0.3},
                    {"friction", 0.25}});
  const double origin = -0.5 * (side - 1) * pitch;
  int id = 1;
  auto add = [&](double x, double y, double z) {
    nlohmann::json body = {{"id", id++},
                           {"density", 500},
                           {"translation", {x, y, z}},
                           {"restitution", 0.3},
                           {"friction", 0.25}};
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
  };
  for (int p = 0; p < piles; ++p) {
    const double cx = origin + (p % side) * pitch, cz = origin + (p / side) * pitch;
    for (int k = 0; k < 4; ++k)  // 5 mm above the ground
      add(cx + ((k & 1) - 0.5) * spacing, 0.105, cz + ((k >> 1) - 0.5) * spacing);
    // 1 cm above where it rests on the four (spheres: in their hollow; a cube: on their tops).
    add(cx, boxes ? 0.31 : 0.255, cz);
  }
  scene["RigidBodies"] = bodies;
  return scene.dump();
}

/// The rod family: `particles` particles (as scene JSON: LineModels need no file).
inline std::string rodScene(int particles) {
  nlohmann::json scene;
  scene["Name"] = "scaling_rod_" + std::to_string(particles);
  scene["Simulation"] = scalingSettings(false);
  nlohmann::json points = nlohmann::json::array();
  for (int i = 0; i < particles; ++i)
    points.push_back({0.01 * i, 1.0, 0.0});
  nlohmann::json rod = nlohmann::json::object();
  rod["points"] = points;
  rod["staticParticles"] = nlohmann::json::array({0});
  rod["staticSegments"] = nlohmann::json::array({0});
  scene["LineModels"] = nlohmann::json::array({rod});
  return scene.dump();
}

/// The fluid family: a cube of `side`³ particles in a container twice as long.
inline std::string fluidScene(int side) {
  const double spacing = 0.05;  // 2r
  const double edge = side * spacing;
  nlohmann::json scene;
  scene["Name"] = "scaling_fluid_" + std::to_string(side * side * side);
  scene["Simulation"] = scalingSettings(false);
  nlohmann::json block = {{"min", {0, 0, 0}}, {"max", {edge, edge, edge}}};
  nlohmann::json container = {{"min", {0, 0, 0}}, {"max", {2 * edge, 1.5 * edge, edge}}};
  nlohmann::json fluid = nlohmann::json::object();
  fluid["blocks"] = nlohmann::json::array({block});
  fluid["container"] = container;
  scene["FluidModels"] = nlohmann::json::array({fluid});
  return scene.dump();
}

/// The cloth family: `side` × `side` particles.
inline pbd::Scene clothScene(int side) {
  pbd::Scene scene;
  scene.name = "scaling_cloth_" + std::to_string(side * side);
  scene.simulation.timeStepSize = 0.005;
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = 2;
  scene.simulation.clothSimulationMethod = 4;
  scene.simulation.cloth_stiffness = 1000;
  scene.simulation.clothBendingMethod = 3;
  scene.simulation.cloth_bendingStiffness = 1;
  pbd::TriangleModelDesc cloth;
  const double spacing = 1.0 / (side - 1);
  cloth.mesh = pbd::triangleGrid(side, side, spacing, pbd::Vector3(0, 1, 0));
  cloth.density = 0.3;
  cloth.staticParticles = {0, side - 1};
  const std::vector<pbd::Real> masses = pbd::lumpedMasses(cloth.mesh, 0.3);
  for (std::size_t p = 0; p < cloth.mesh.vertices.size(); ++p) {
    const bool pinned = p == 0 || p == std::size_t(side - 1);
    scene.particles.push_back(
        {cloth.mesh.vertices[p], pbd::Vector3::Zero(), pinned ? 0 : masses[p]});
  }
  scene.triangleModels.push_back(std::move(cloth));
  return scene;
}

/// The solid family: `side`³ particles.
inline pbd::Scene solidScene(int side) {
  pbd::Scene scene;
  scene.name = "scaling_solid_" + std::to_string(side * side * side);
  scene.simulation.timeStepSize = 0.005;
  scene.simulation.subSteps = 5;
  scene.simulation.maxIterations = 1;
  scene.simulation.solidSimulationMethod = 3;
  scene.simulation.solid_stiffness = 1e6;
  pbd::TetModelDesc solid;
  solid.mesh = pbd::tetLattice(side, side, side, pbd::Vector3(0.1, -0.1, 0.1));
  solid.density = 1000;
  const std::vector<pbd::Real> masses = pbd::lumpedMasses(solid.mesh, 1000);
  for (std::size_t p = 0; p < solid.mesh.vertices.size(); ++p) {
    const bool top = solid.mesh.vertices[p].y() == 0;
    if (top) solid.staticParticles.push_back(int(p));
    scene.particles.push_back({solid.mesh.vertices[p], pbd::Vector3::Zero(), top ? 0 : masses[p]});
  }
  scene.tetModels.push_back(std::move(solid));
  return scene;
}

}  // namespace pbdval::bench
