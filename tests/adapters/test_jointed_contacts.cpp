// Jointed bodies collide with each other in every engine and method, as in the seed (its
// collision detection tests every pair of collision objects; nothing filters jointed ones).
// The scene, cases/contact_jointed_bodies.json, hinges a 0.5 x 0.05 x 0.05 m link 5 cm above
// the top face of the 1.2 x 0.1 x 0.1 m beam it is jointed to and lets it fall from horizontal:
// once onto a static beam (MuJoCo: a child of the world), once onto a dynamic beam hinged at
// its centre (MuJoCo: a parent-child pair, which MuJoCo's automatic contacts filter out by
// default). Measured: how deep the link's corners go below the beam's top face, in the beam's
// frame (so a joint that gives way does not count as penetration). A box-box contact pushes a
// corner out through the nearer face, so a working contact keeps every corner above the beam's
// mid-plane (depth < half the beam's thickness); without the contact the link swings through
// the beam (the control below, with the shapes removed).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "adapters/engine.h"
#include "engines/selftest_engine.h"
#include "pbd/io/scene_loader.h"
#include "validation/run/case_spec.h"
#include "validation/run/simulation.h"

namespace pbdval::test {
namespace {

using pbd::JointDesc;
using pbd::RigidBodyDesc;
using pbd::Scene;

const std::string kCase =
    (std::filesystem::path(PBDVAL_SOURCE_DIR) / "cases" / "contact_jointed_bodies.json").string();

/// Every method of every engine a run uses by default (the self-test engine has no contacts).
std::vector<std::string> allMethods() {
  std::vector<std::string> methods;
  for (const EngineEntry& entry : testRegistry().entries())
    if (entry.runByDefault)
      for (const MethodInfo& method : entry.methods)
        methods.push_back(method.name);
  return methods;
}

/// Methods that diverge on this scene for a reason other than the collision rule, and why. The
/// test asserts the divergence, so that a fix shows here.
const std::map<std::string, std::string> kDiverging = {
    {"bullet.nncg",
     "btNNCGConstraintSolver with warm starting diverges on a contact between two hinged "
     "dynamic bodies (the dynamic beam and its link), jointed to each other or not: hinged to "
     "the anchor instead, the link diverges too; with warmstartingFactor=0 or 200 iterations "
     "it runs (measured)"}};

/// A link hinged above the beam it is jointed to (Scene::rigidBodies indices): each hinge of
/// the case between two bodies with collision shapes.
struct LinkOnBeam {
  int beam = -1, link = -1;
};

std::vector<LinkOnBeam> linksOnBeams(const Scene& s) {
  std::vector<LinkOnBeam> links;
  for (const JointDesc& joint : s.joints)
    if (s.rigidBodies[std::size_t(joint.body1)].collision.type != pbd::CollisionObjectType::None)
      links.push_back({joint.body1, joint.body2});
  return links;
}

/// The box's corners in world coordinates (its collision box: full extents collision.scale,
/// centred on the scene frame's origin).
std::vector<Vector3> corners(const RigidBodyDesc& body, const BodyState& state) {
  const Vector3 origin = state.position - state.rotation * body.massProperties.centerOfMass;
  std::vector<Vector3> out;
  for (int i = 0; i < 8; ++i) {
    const Vector3 sign((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    out.push_back(origin + state.rotation * sign.cwiseProduct(body.collision.scale / 2));
  }
  return out;
}

/// How far the link's deepest corner is below the beam's top face (negative: above it),
/// counting the corners above the beam's footprint.
double depthBelowTopFace(const Scene& s, const State& state, const LinkOnBeam& l) {
  const RigidBodyDesc& beam = s.rigidBodies[std::size_t(l.beam)];
  const BodyState& beamState = state.bodies[std::size_t(l.beam)];
  const Vector3 beamOrigin =
      beamState.position - beamState.rotation * beam.massProperties.centerOfMass;
  const Vector3 half = beam.collision.scale / 2;
  double deepest = -std::numeric_limits<double>::infinity();
  for (const Vector3& corner :
       corners(s.rigidBodies[std::size_t(l.link)], state.bodies[std::size_t(l.link)])) {
    const Vector3 local = beamState.rotation.conjugate() * (corner - beamOrigin);
    if (std::abs(local.x()) > half.x() || std::abs(local.z()) > half.z()) continue;
    deepest = std::max(deepest, half.y() - local.y());
  }
  return deepest;
}

/// The deepest each link's corners went below its beam's top face over the case's duration.
std::vector<double> deepestCorners(const Scene& s, const std::vector<LinkOnBeam>& links,
                                   const std::string& methodName, RunOutcome& outcome) {
  const double duration = defaultDuration(s, parseCaseSpec(s, testRegistry()));
  const Method method = testRegistry().resolve(methodName);
  const std::unique_ptr<Engine> engine =
      testRegistry().make(testRegistry().method(methodName).engine);
  std::vector<double> deepest(links.size(), -std::numeric_limits<double>::infinity());
  RunCallbacks callbacks;
  callbacks.onSample = [&](const State& state) {
    for (std::size_t i = 0; i < links.size(); ++i)
      deepest[i] = std::max(deepest[i], depthBelowTopFace(s, state, links[i]));
  };
  outcome = runSimulation(*engine, s, method, {duration, 0}, callbacks);
  return deepest;
}

/// The gap between the link's bottom face and the beam's top face at t = 0.
double initialGap(const Scene& s, const LinkOnBeam& l) {
  const RigidBodyDesc &beam = s.rigidBodies[std::size_t(l.beam)],
                      &link = s.rigidBodies[std::size_t(l.link)];
  return (link.translation.y() - link.collision.scale.y() / 2) -
         (beam.translation.y() + beam.collision.scale.y() / 2);
}

class JointedBodies : public ::testing::TestWithParam<std::string> {};

TEST_P(JointedBodies, ALinkFallingOntoTheBeamItIsJointedToIsStoppedByTheirContact) {
  const Scene s = pbd::loadScene(kCase).scene;
  const std::vector<LinkOnBeam> links = linksOnBeams(s);
  ASSERT_EQ(links.size(), 2u) << kCase << ": a static and a dynamic beam";
  RunOutcome outcome;
  const std::vector<double> deepest = deepestCorners(s, links, GetParam(), outcome);
  if (const auto diverging = kDiverging.find(GetParam()); diverging != kDiverging.end()) {
    EXPECT_EQ(outcome.status, RunStatus::Diverged) << diverging->second;
    return;
  }
  ASSERT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  for (std::size_t i = 0; i < links.size(); ++i) {
    const LinkOnBeam& l = links[i];
    SCOPED_TRACE("link " + s.rigidBodies[std::size_t(l.link)].jsonPath + " on " +
                 s.rigidBodies[std::size_t(l.beam)].jsonPath);
    // The contact keeps every corner above the beam's mid-plane (the geometric bound, above).
    EXPECT_LT(deepest[i], s.rigidBodies[std::size_t(l.beam)].collision.scale.y() / 2);
    // ...and the link did reach the beam: closer than half the initial 2.5 cm gap (PBD's
    // contacts begin contactTolerance = 1 cm early).
    EXPECT_GT(deepest[i], -initialGap(s, l) / 2);
  }
}

// The control: with the collision shapes removed the same links swing through their beams, so
// the bound above fails for an engine that drops the jointed pairs' contacts.
TEST_P(JointedBodies, WithoutCollisionShapesTheLinkSwingsThroughTheBeam) {
  const Scene withShapes = pbd::loadScene(kCase).scene;
  const std::vector<LinkOnBeam> links = linksOnBeams(withShapes);
  Scene s = withShapes;
  for (RigidBodyDesc& body : s.rigidBodies)
    body.collision.type = pbd::CollisionObjectType::None;
  RunOutcome outcome;
  const std::vector<double> deepest = deepestCorners(s, links, GetParam(), outcome);
  ASSERT_EQ(outcome.status, RunStatus::Ok) << outcome.reason;
  for (std::size_t i = 0; i < links.size(); ++i)
    EXPECT_GT(deepest[i], withShapes.rigidBodies[std::size_t(links[i].beam)].collision.scale.y());
}

TEST_P(JointedBodies, TheRunRecordsThatJointedBodiesCollide) {
  const Method method = testRegistry().resolve(GetParam());
  const std::unique_ptr<SteppingEngine> engine =
      testRegistry().makeStepping(testRegistry().method(GetParam()).engine);
  engine->load(pbd::loadScene(kCase).scene, method);
  const auto settings = engine->effectiveSettings();
  const auto found = settings.find("jointedBodiesCollide");
  ASSERT_NE(found, settings.end());
  EXPECT_EQ(found->second.rfind("yes", 0), 0u) << found->second;
}

INSTANTIATE_TEST_SUITE_P(Engines, JointedBodies, ::testing::ValuesIn(allMethods()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           std::replace(name.begin(), name.end(), '.', '_');
                           return name;
                         });

}  // namespace
}  // namespace pbdval::test
