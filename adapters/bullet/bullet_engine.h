// Bullet 3.24 (double precision) behind the Engine interface: btRigidBody + btTypedConstraint
// in a btDiscreteDynamicsWorld, maximal coordinates.
//
// Methods (parameters and defaults in bulletMethods(), docs/methods.md):
//   bullet.si       btSequentialImpulseConstraintSolver (projected Gauss–Seidel, the default)
//   bullet.dantzig  btMLCPSolver with btDantzigSolver (direct pivoting MLCP solve)
//   bullet.nncg     btNNCGConstraintSolver (nonsmooth nonlinear conjugate gradient)
//
// Parity with the other engines (docs/parity-bullet.md): gravity from the Scene, no sleeping,
// no damping, one internal step per step (stepSimulation(h, 1, h)), the implicit gyroscopic
// term, mass and principal inertia from the Scene, per-pair friction and restitution from
// Scene::pairMaterial, restitution velocity threshold 0.
#pragma once

#include <memory>

#include "adapters/engine.h"

class btDiscreteDynamicsWorld;
class btRigidBody;

namespace pbdval {

/// The values of a Bullet method's parameters.
struct BulletSettings {
  std::string solver = "si";  ///< "si", "dantzig" or "nncg"
  int iterations = 10;
  double erp = 0.2;   ///< joints (btContactSolverInfo::m_erp)
  double erp2 = 0.2;  ///< contacts (m_erp2)
  double cfm = 0;     ///< global constraint force mixing (m_globalCfm)
  bool splitImpulse = true;
  double splitImpulsePenetrationThreshold = 0;  ///< m; Bullet's default −0.04
  double warmstartingFactor = 0.85;
  double restitutionVelocityThreshold = 0;  ///< m/s; Bullet's default 0.2
  double margin = 0.001;                    ///< convex collision margin, m; Bullet's 0.04
  double linearSlop = 1e-5;                 ///< resting penetration left, m; Bullet's 0
  double contactProcessingThreshold = 0;    ///< m; Bullet's 1e30 (speculative contacts)
};

/// The method's parameters, validated; throws std::invalid_argument naming a bad one.
BulletSettings bulletSettingsFor(const Method& method);

class BulletEngine final : public SteppingEngine {
 public:
  BulletEngine();
  ~BulletEngine() override;

  std::string_view name() const override { return "bullet"; }
  std::vector<std::string> unsupported(const pbd::Scene& scene,
                                       const Method& method) const override;
  void load(const pbd::Scene& scene, const Method& method) override;
  void step() override;
  void read(State& state) const override;
  RunFacts runFacts() const override;
  std::map<std::string, std::string> effectiveSettings() const override;

  /// The Bullet world and bodies (Scene order), for tests; valid after load().
  const btDiscreteDynamicsWorld& world() const;
  const btRigidBody& body(std::size_t index) const;

 private:
  struct Model;
  /// The loaded model; throws EngineError before load().
  Model& model() const;
  std::unique_ptr<Model> model_;
};

/// How the engine maps every scene feature (bullet_features.cpp; adapters/features.h).
FeatureTable bulletFeatures();
EngineEntry bulletEngineEntry();

}  // namespace pbdval
