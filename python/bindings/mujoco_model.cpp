// pbdval._core's MuJoCo functions: the built-in adapter's MJCF (adapters/mujoco/mjcf_writer.h)
// of a resolved scene's rigid part (validation/external/resolved_scene_reader.h) for the
// mujoco-python engine, which compiles it with MuJoCo 4, and MuJoCo 2.2.2's compile of any MJCF as
// numbers, for the test that compares the two versions' models field by field
// (docs/external-engines.md#one-model-description).
#include "python/bindings/mujoco_model.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "adapters/mujoco/kinematic_tree.h"
#include "adapters/mujoco/mjcf_writer.h"
#include "adapters/mujoco/mujoco_engine.h"
#include "adapters/mujoco/mujoco_model_fields.h"
#include "adapters/mujoco/mujoco_settings.h"
#include "validation/external/resolved_scene_reader.h"

namespace py = pybind11;

namespace pbdval::python {
namespace {

using nlohmann::json;

template <class T>
T setting(const py::dict& settings, const char* key) {
  if (!settings.contains(key))
    throw std::invalid_argument(std::string("MuJoCo settings: missing '") + key + "'");
  return settings[key].cast<T>();
}

mujoco::MujocoSettings settingsOf(const py::dict& d, double stepSize) {
  mujoco::MujocoSettings s;
  s.integrator = setting<std::string>(d, "integrator");
  s.solver = setting<std::string>(d, "solver");
  s.iterations = setting<int>(d, "iterations");
  s.tolerance = setting<double>(d, "tolerance");
  s.cone = setting<std::string>(d, "cone");
  s.stepSize = stepSize;
  s.contactTimeConstant = setting<double>(d, "contact_time_constant");
  const auto equality = setting<std::vector<double>>(d, "equality_solref");
  const auto solimp = setting<std::vector<double>>(d, "solimp");
  if (equality.size() != 2 || solimp.size() != 5)
    throw std::invalid_argument("MuJoCo settings: equality_solref needs 2 numbers, solimp 5");
  s.equalitySolref = {equality[0], equality[1]};
  for (std::size_t i = 0; i < 5; ++i)
    s.solimp[i] = solimp[i];
  s.servoTimeConstant = setting<double>(d, "servo_time_constant");
  return s;
}

py::dict mjcfOfResolvedScene(const std::string& resolvedText, const py::dict& settings) {
  const pbd::Scene scene = rigidSceneFromResolvedJson(json::parse(resolvedText));
  py::dict out;
  const std::vector<std::string> unsupported = mujoco::unsupportedRigidFeatures(scene);
  out["unsupported"] = unsupported;
  if (!unsupported.empty()) return out;
  const mujoco::KinematicTree tree = mujoco::planKinematicTree(scene);
  const mujoco::MjcfModel model =
      mujoco::writeMjcf(scene, settingsOf(settings, double(scene.simulation.timeStepSize)), tree);
  out["xml"] = model.xml;
  py::list motors;
  for (const mujoco::MotorBinding& motor : model.motors) {
    py::dict m;
    m["joint"] = motor.joint;
    m["actuator"] = motor.actuatorName;
    m["joint_name"] = motor.jointName;
    m["velocity_servo"] = motor.velocityServo;
    motors.append(m);
  }
  out["motors"] = motors;
  out["contact_pairs"] = model.contactPairs;
  out["jointed_contact_pairs"] = model.jointedContactPairs;
  py::dict pairs;
  for (const auto& [pair, law] : model.pairSettings)
    pairs[py::str(pair)] = law;
  out["pair_settings"] = pairs;
  out["equality_constraints"] = model.equalityConstraints;
  out["approximations"] = model.approximations;
  std::vector<std::string> bodies;
  for (std::size_t i = 0; i < scene.rigidBodies.size(); ++i)
    bodies.push_back(mujoco::bodyName(i));
  out["body_names"] = bodies;
  return out;
}

py::dict modelFields(const std::string& xml) {
  py::dict out;
  for (const mujoco::ModelField& f : mujoco::compiledModelFields(xml)) {
    const std::vector<py::ssize_t> shape = {py::ssize_t(f.rows), py::ssize_t(f.cols)};
    if (f.integer) {  // int and mjtByte fields as integers, so a comparison knows to be exact
      py::array_t<std::int64_t> values(shape);
      std::transform(f.values.begin(), f.values.end(), values.mutable_data(),
                     [](double v) { return std::int64_t(v); });
      out[py::str(f.name)] = values;
    } else {
      py::array_t<double> values(shape);
      std::copy(f.values.begin(), f.values.end(), values.mutable_data());
      out[py::str(f.name)] = values;
    }
  }
  return out;
}

}  // namespace

void bindMujocoModel(py::module_& m) {
  m.def("_mujoco_mjcf", &mjcfOfResolvedScene, py::arg("resolved_scene"), py::arg("settings"));
  m.def("_mujoco_2_2_2_model", &modelFields, py::arg("xml"));
}

}  // namespace pbdval::python
