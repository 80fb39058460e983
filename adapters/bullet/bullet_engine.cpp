#include "adapters/bullet/bullet_engine.h"

#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <BulletDynamics/ConstraintSolver/btNNCGConstraintSolver.h>
#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <BulletDynamics/MLCPSolvers/btMLCPSolver.h>
#include <LinearMath/btTransformUtil.h>

#include <cmath>
#include <sstream>

#include "adapters/bullet/bullet_convert.h"
#include "adapters/bullet/bullet_joints.h"
#include "adapters/bullet/bullet_materials.h"
#include "adapters/bullet/bullet_shapes.h"
#include "pbd/io/number_text.h"

namespace pbdval {
namespace {

using bullet::toBullet;
using bullet::toEigen;

// --- Methods and their parameters ----------------------------------------------------------

// Defaults are Bullet's, except the four contact settings marked "parity" (docs/methods.md):
// they make restitution and resting contact independent of when Bullet first sees a contact.
std::vector<ParameterSpec> bulletParameters() {
  return {
      integerParameter("iterations", 10, 1, 1e6,
                       "solver iterations per step (btContactSolverInfo::m_numIterations)"),
      realParameter("erp", 0.2, 0, 1, "", "joint error reduction per step (m_erp, Baumgarte)"),
      realParameter("erp2", 0.2, 0, 1, "", "contact error reduction per step (m_erp2)"),
      realParameter("cfm", 0, 0, 1e6, "", "global constraint force mixing (m_globalCfm)"),
      boolParameter("splitImpulse", true,
                    "correct contact penetration deeper than splitImpulsePenetrationThreshold "
                    "with a position-only impulse that adds no velocity"),
      realParameter("splitImpulsePenetrationThreshold", 0, -1e6, 0, "m",
                    "penetration (<= 0) beyond which the split impulse corrects it; shallower "
                    "penetration is corrected through the velocity (erp2). Parity: 0, all of it "
                    "(Bullet: -0.04)"),
      realParameter("warmstartingFactor", 0.85, 0, 1, "",
                    "fraction of the previous step's impulses applied first"),
      realParameter("restitutionVelocityThreshold", 0, 0, 1e6, "m/s",
                    "approach speed below which Bullet drops restitution. Parity: 0 (Bullet: 0.2)"),
      realParameter("linearSlop", 1e-5, 0, 1, "m",
                    "penetration contacts leave uncorrected (m_linearSlop): resting contacts "
                    "settle this deep and stay in contact. Parity: 1e-5 (Bullet: 0)"),
      realParameter("contactProcessingThreshold", 0, 0, 1e30, "m",
                    "contact points farther apart than this are not solved. Parity: 0, touching "
                    "or penetrating points only (Bullet: 1e30, also speculative points, which "
                    "apply restitution only to the speed left after closing the gap)"),
      realParameter("margin", 0.001, 0, 1, "m",
                    "convex collision margin, kept inside the geometry: it rounds edges and "
                    "corners (Bullet: 0.04)"),
  };
}

struct SolverSpec {
  const char* solver;
  const char* description;
};

constexpr SolverSpec kSolvers[] = {
    {"si",
     "btSequentialImpulseConstraintSolver: projected Gauss-Seidel over velocity-level joint, "
     "contact and friction rows, warm started, Baumgarte position correction (ERP), split "
     "impulse for deep contacts; semi-implicit Euler"},
    {"dantzig",
     "btMLCPSolver + btDantzigSolver: each island's rows solved as one mixed LCP by pivoting, "
     "friction bounded by mu times the normal impulse; falls back to sequential impulse when "
     "pivoting fails"},
    {"nncg",
     "btNNCGConstraintSolver: nonsmooth nonlinear conjugate gradient on the sequential-impulse "
     "iteration (Silcowitz, Niebe, Erleben 2010)"},
};

std::vector<MethodInfo> bulletMethods() {
  std::vector<MethodInfo> methods;
  for (const SolverSpec& s : kSolvers) {
    MethodInfo m;
    m.name = std::string("bullet.") + s.solver;
    m.engine = "bullet";
    m.description = s.description;
    m.parameters = bulletParameters();
    methods.push_back(std::move(m));
  }
  return methods;
}

std::string number(double value) {
  return pbd::formatReal(value);
}

std::string vector3(const pbd::Vector3& v) {
  return number(double(v.x())) + " " + number(double(v.y())) + " " + number(double(v.z()));
}

std::string countsText(const std::map<std::string, int>& counts) {
  std::string text;
  for (const auto& [kind, count] : counts)
    text += (text.empty() ? "" : ", ") + kind + " x" + std::to_string(count);
  return text.empty() ? "none" : text;
}

}  // namespace

BulletSettings bulletSettingsFor(const Method& method) {
  BulletSettings s;
  const std::string prefix = "bullet.";
  s.solver = method.name.rfind(prefix, 0) == 0 ? method.name.substr(prefix.size()) : method.name;
  bool known = false;
  for (const SolverSpec& spec : kSolvers)
    known = known || s.solver == spec.solver;
  if (!known) throw std::invalid_argument("unknown Bullet method '" + method.name + "'");
  s.iterations = static_cast<int>(method.integer("iterations"));
  s.erp = method.real("erp");
  s.erp2 = method.real("erp2");
  s.cfm = method.real("cfm");
  s.splitImpulse = method.flag("splitImpulse");
  s.splitImpulsePenetrationThreshold = method.real("splitImpulsePenetrationThreshold");
  s.warmstartingFactor = method.real("warmstartingFactor");
  s.restitutionVelocityThreshold = method.real("restitutionVelocityThreshold");
  s.margin = method.real("margin");
  s.linearSlop = method.real("linearSlop");
  s.contactProcessingThreshold = method.real("contactProcessingThreshold");
  return s;
}

// --- The Bullet world of one run ------------------------------------------------------------

namespace {

std::unique_ptr<btConstraintSolver> makeSolver(const std::string& kind, btDantzigSolver& dantzig) {
  if (kind == "dantzig") return std::make_unique<btMLCPSolver>(&dantzig);
  if (kind == "nncg") return std::make_unique<btNNCGConstraintSolver>();
  return std::make_unique<btSequentialImpulseConstraintSolver>();
}

}  // namespace

struct BulletEngine::Model {
  Model(const pbd::Scene& scene, const BulletSettings& s);
  ~Model();
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  void configureSolver();
  void addBodies(const pbd::Scene& scene);
  std::unique_ptr<btRigidBody> makeBody(const pbd::RigidBodyDesc& desc,
                                        btCollisionShape* shape) const;
  void addJoints(const pbd::Scene& scene);

  BulletSettings settings;
  double stepSize;
  pbd::Vector3 gravity;
  long steps = 0;
  bullet::PairMaterials materials;

  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btDantzigSolver dantzig;
  std::unique_ptr<btConstraintSolver> solver;
  bullet::ShapeStore shapes;
  std::vector<bullet::BodyTag> tags;  ///< user pointers; sized once, never reallocated
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<pbd::Quaternion> principalRotations;  ///< principal → scene frame, per body
  std::vector<int> ids;
  bullet::JointModel joints;
  std::unique_ptr<btDiscreteDynamicsWorld> world;  ///< last: refers to everything above
};

BulletEngine::Model::Model(const pbd::Scene& scene, const BulletSettings& s)
    : settings(s),
      stepSize(double(scene.simulation.timeStepSize)),
      gravity(scene.simulation.gravitation),
      materials(scene),
      solver(makeSolver(s.solver, dantzig)),
      shapes(s.margin) {
  bullet::installPairMaterialHooks();
  btGImpactCollisionAlgorithm::registerAlgorithm(&dispatcher);
  world = std::make_unique<btDiscreteDynamicsWorld>(&dispatcher, &broadphase, solver.get(),
                                                    &configuration);
  world->setGravity(toBullet(gravity));  // Bullet's default is (0, −10, 0)
  configureSolver();
  addBodies(scene);
  addJoints(scene);
}

BulletEngine::Model::~Model() {
  for (const auto& c : joints.constraints)
    world->removeConstraint(c.get());
  for (const auto& b : bodies)
    world->removeRigidBody(b.get());
  world.reset();
}

void BulletEngine::Model::configureSolver() {
  btContactSolverInfo& info = world->getSolverInfo();
  info.m_numIterations = settings.iterations;
  info.m_erp = settings.erp;
  info.m_erp2 = settings.erp2;
  info.m_globalCfm = settings.cfm;
  info.m_splitImpulse = settings.splitImpulse ? 1 : 0;
  info.m_splitImpulsePenetrationThreshold = settings.splitImpulsePenetrationThreshold;
  info.m_warmstartingFactor = settings.warmstartingFactor;
  info.m_restitutionVelocityThreshold = settings.restitutionVelocityThreshold;
  info.m_linearSlop = settings.linearSlop;
  // A direct solver is cheaper on small islands than on islands batched together.
  if (settings.solver == "dantzig") info.m_minimumSolverBatchSize = 1;
  world->getDispatchInfo().m_deterministicOverlappingPairs = true;
}

void BulletEngine::Model::addBodies(const pbd::Scene& scene) {
  tags.resize(scene.rigidBodies.size());
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i) {
    const pbd::RigidBodyDesc& desc = scene.rigidBodies[i];
    btCollisionShape* shape = shapes.shapeFor(desc);
    const bool collides = shape != nullptr;
    auto body = makeBody(desc, collides ? shape : shapes.emptyShape());
    tags[i] = {static_cast<int>(i), &materials};
    body->setUserPointer(&tags[i]);
    if (collides)
      world->addRigidBody(body.get());
    else
      world->addRigidBody(body.get(), 0, 0);  // no collision object: never in a pair
    principalRotations.push_back(desc.massProperties.principalRotation);
    ids.push_back(desc.id);
    bodies.push_back(std::move(body));
  }
}

std::unique_ptr<btRigidBody> BulletEngine::Model::makeBody(const pbd::RigidBodyDesc& desc,
                                                           btCollisionShape* shape) const {
  const pbd::MassProperties& mass = desc.massProperties;
  if (desc.isDynamic && !(mass.mass > 0 && (mass.principalInertia.array() > 0).all()))
    throw EngineError(desc.jsonPath + ": a dynamic body needs a positive mass and inertia");
  // Mass and principal inertia from the Scene, never calculateLocalInertia; static bodies
  // (isDynamic false) are mass-0 objects at their principal frame all the same.
  const double bodyMass = desc.isDynamic ? double(mass.mass) : 0;
  const btVector3 inertia = desc.isDynamic ? toBullet(mass.principalInertia) : btVector3(0, 0, 0);
  btRigidBody::btRigidBodyConstructionInfo info(bodyMass, nullptr, shape, inertia);
  info.m_startWorldTransform =
      toBullet(desc.initialPrincipalRotation(), desc.initialCenterOfMass());
  info.m_linearDamping = 0;
  info.m_angularDamping = 0;
  info.m_additionalDamping = false;
  info.m_friction = double(desc.friction);  // replaced per pair by the material hooks
  info.m_restitution = double(desc.restitution);
  auto body = std::make_unique<btRigidBody>(info);
  body->setActivationState(DISABLE_DEACTIVATION);
  body->setContactProcessingThreshold(settings.contactProcessingThreshold);
  body->setFlags(BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
  if (desc.isDynamic) {
    body->setLinearVelocity(toBullet(desc.velocity));
    body->setAngularVelocity(toBullet(desc.angularVelocity));
  }
  return body;
}

void BulletEngine::Model::addJoints(const pbd::Scene& scene) {
  for (const pbd::JointDesc& joint : scene.joints)
    bullet::addJoint(joint, *bodies[static_cast<std::size_t>(joint.body1)],
                     *bodies[static_cast<std::size_t>(joint.body2)], joints);
  // Jointed bodies keep colliding with each other, as in the seed.
  for (const auto& c : joints.constraints)
    world->addConstraint(c.get(), false);
}

// --- Engine interface -----------------------------------------------------------------------

BulletEngine::BulletEngine() = default;
BulletEngine::~BulletEngine() = default;

std::vector<std::string> BulletEngine::unsupported(const pbd::Scene& scene,
                                                   const Method& method) const {
  return unsupportedFeatures(bulletFeatures(), scene, method.name);
}

void BulletEngine::load(const pbd::Scene& scene, const Method& method) {
  const BulletSettings settings = bulletSettingsFor(method);
  model_.reset();
  model_ = std::make_unique<Model>(scene, settings);
}

BulletEngine::Model& BulletEngine::model() const {
  if (!model_) throw EngineError("Bullet engine: load() a scene first");
  return *model_;
}

void BulletEngine::step() {
  Model& m = model();
  const double endTime = double(m.steps + 1) * m.stepSize;
  for (const auto& prepare : m.joints.beforeStep)
    prepare(endTime, m.stepSize);
  // Exactly one internal step of h: no substepping, no interpolation.
  const int taken = m.world->stepSimulation(m.stepSize, 1, m.stepSize);
  if (taken != 1)
    throw EngineError("Bullet took " + std::to_string(taken) + " internal steps instead of 1");
  ++m.steps;
}

void BulletEngine::read(State& state) const {
  const Model& m = model();
  state.time = double(m.steps) * m.stepSize;
  state.bodies.resize(m.bodies.size());
  for (std::size_t i = 0; i < m.bodies.size(); ++i) {
    const btRigidBody& body = *m.bodies[i];
    const btTransform& pose = body.getCenterOfMassTransform();
    BodyState& s = state.bodies[i];
    s.id = m.ids[i];
    s.position = toEigen(pose.getOrigin());
    // The body frame is the principal frame: q_scene = q_principal ⊗ principalRotation⁻¹.
    s.rotation = toEigen(pose.getRotation()) * m.principalRotations[i].conjugate();
    s.velocity = toEigen(body.getLinearVelocity());
    s.angularVelocity = toEigen(body.getAngularVelocity());
  }
  state.particles.clear();
}

RunFacts BulletEngine::runFacts() const {
  RunFacts facts;
  facts.engineVersion = "Bullet " + std::to_string(btGetVersion() / 100) + "." +
                        std::to_string(btGetVersion() % 100) + " (double precision)";
  facts.integratorStepsPerSceneStep = 1;  // stepSimulation(h, 1, h)
  facts.contactMargin = model().settings.linearSlop;
  return facts;
}

std::map<std::string, std::string> BulletEngine::effectiveSettings() const {
  if (!model_) return {};
  const Model& m = *model_;
  const BulletSettings& s = m.settings;
  const btContactSolverInfo& info = m.world->getSolverInfo();
  return {
      {"engine", "Bullet " + std::to_string(btGetVersion()) + " btDiscreteDynamicsWorld"},
      {"precision", sizeof(btScalar) == 8 ? "double" : "float"},
      {"solver", s.solver},
      {"iterations", std::to_string(info.m_numIterations)},
      {"erp", number(info.m_erp)},
      {"erp2", number(info.m_erp2)},
      {"cfm", number(info.m_globalCfm)},
      {"splitImpulse", std::to_string(info.m_splitImpulse)},
      {"splitImpulsePenetrationThreshold", number(info.m_splitImpulsePenetrationThreshold)},
      {"warmstartingFactor", number(info.m_warmstartingFactor)},
      {"restitutionVelocityThreshold", number(info.m_restitutionVelocityThreshold)},
      {"linearSlop", number(info.m_linearSlop)},
      {"solverMode", std::to_string(info.m_solverMode)},
      {"margin", number(m.shapes.margin())},
      {"contactProcessingThreshold", number(s.contactProcessingThreshold)},
      {"contactBreakingThreshold", number(gContactBreakingThreshold) + " x shape bounding radius"},
      {"frictionModel",
       "one friction row per contact point along the relative sliding velocity (isotropic cone)"},
      {"contactMaterials",
       "Scene::pairMaterial per pair (gCalculateCombinedFriction/RestitutionCallback)"},
      {"jointedBodiesCollide", "yes (as the seed)"},
      {"timeStepSize", number(m.stepSize)},
      {"stepping", "stepSimulation(h, 1, h): one internal step per step"},
      {"gravity", vector3(m.gravity)},
      {"gyroscopic", "implicit, body frame (BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY)"},
      {"damping", "0"},
      {"sleeping", "off (DISABLE_DEACTIVATION)"},
      {"maxRotationPerStep", number(ANGULAR_MOTION_THRESHOLD) + " rad (Bullet compile-time cap)"},
      {"shapes", countsText(m.shapes.kindCounts())},
      {"joints", countsText(m.joints.kindCounts)},
  };
}

const btDiscreteDynamicsWorld& BulletEngine::world() const {
  return *model().world;
}

const btRigidBody& BulletEngine::body(std::size_t index) const {
  return *model().bodies.at(index);
}

EngineEntry bulletEngineEntry() {
  EngineEntry entry;
  entry.name = "bullet";
  entry.defaultMethod = "bullet.si";
  entry.methods = bulletMethods();
  entry.honouredSettings = {"timeStepSize", "gravitation"};
  entry.features = bulletFeatures();
  entry.make = [](const EngineOptions&) { return std::unique_ptr<Engine>(new BulletEngine()); };
  return entry;
}

}  // namespace pbdval
