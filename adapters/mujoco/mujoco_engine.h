// MuJoCo 2.2.2 behind the Engine interface.
//
// Methods: mujoco.euler (default), mujoco.rk4, mujoco.implicit: MuJoCo's three integrators,
// each with the solver and contact parameters of mujoco_settings.h (docs/methods.md).
// The model is MJCF text built from the Scene (mjcf_writer.h) over a spanning forest of its
// joint graph (kinematic_tree.h), compiled through MuJoCo's in-memory VFS. MuJoCo errors and
// warnings are routed per thread (mujoco_errors.h); an error becomes EngineError. The mapping,
// feature by feature, is docs/parity-mujoco.md.
#pragma once

#include <memory>

#include "adapters/engine.h"
#include "adapters/mujoco/mjcf_writer.h"
#include "adapters/mujoco/mujoco_settings.h"

struct mjModel_;
struct mjData_;

namespace pbdval {

class MujocoEngine final : public SteppingEngine {
 public:
  MujocoEngine();
  ~MujocoEngine() override;
  MujocoEngine(const MujocoEngine&) = delete;
  MujocoEngine& operator=(const MujocoEngine&) = delete;

  std::string_view name() const override { return "mujoco"; }
  std::vector<std::string> unsupported(const pbd::Scene& scene,
                                       const Method& method) const override;
  void load(const pbd::Scene& scene, const Method& method) override;
  void step() override;
  void read(State& state) const override;
  RunFacts runFacts() const override;
  std::map<std::string, std::string> effectiveSettings() const override;

  /// For tests: the compiled model, its data, the MJCF text and the messages recorded.
  const mjModel_* model() const { return model_.get(); }
  mjData_* data() { return data_.get(); }
  const std::string& mjcf() const { return mjcf_.xml; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// MuJoCo body id of Scene::rigidBodies[index].
  int bodyId(std::size_t index) const { return bodyIds_[index]; }

 private:
  struct ModelDeleter {
    void operator()(mjModel_* m) const;
  };
  struct DataDeleter {
    void operator()(mjData_* d) const;
  };
  struct Servo {
    int actuator = -1;
    std::string jointPath;  ///< "TargetAngleMotorHingeJoints[0]"
    pbd::MotorTarget target;
    bool velocityServo = false;
    double inertia = 0;  ///< 1/(M⁻¹)ᵢᵢ of the driven joint at t = 0
    double kp = 0, kv = 0;
  };

  void compile();
  void indexBodies(const pbd::Scene& scene);
  void projectInitialVelocities(const pbd::Scene& scene);
  void tuneServos(const pbd::Scene& scene);
  void checkWarnings();
  void forward(const char* what);

  std::unique_ptr<mjModel_, ModelDeleter> model_;
  std::unique_ptr<mjData_, DataDeleter> data_;
  mujoco::MujocoSettings settings_;
  mujoco::MjcfModel mjcf_;
  std::vector<int> bodyIds_;
  std::vector<int> sceneIds_;
  std::vector<Quaternion> principalRotations_;
  std::vector<Servo> servos_;
  std::vector<std::string> warnings_;  ///< MuJoCo's warnings and the adapter's notes
  std::vector<int> warningCounts_;     ///< mjData.warning[i].number already seen
  bool failed_ = false;
  double stepEndTime_ = 0;  ///< time at the end of the step being taken (for messages)
};

/// How the engine maps every scene feature (mujoco_features.cpp; adapters/features.h).
FeatureTable mujocoFeatures();
EngineEntry mujocoEngineEntry();

namespace mujoco {

/// The features `scene` uses (sceneFeatureUses), with the joints that close a loop of the
/// spanning forest this adapter builds (planKinematicTree).
std::vector<FeatureUse> featureUses(const pbd::Scene& scene);

/// The messages of the unsupported uses of the scene's rigid part (shapes, joints, bodies,
/// contacts) by mujocoFeatures(): what mujoco-python, which maps particle models as flexes and
/// decides those itself, cannot take from the built-in adapter's MJCF ("RigidBodies[2]: ...").
std::vector<std::string> unsupportedRigidFeatures(const pbd::Scene& scene);

}  // namespace mujoco

}  // namespace pbdval
