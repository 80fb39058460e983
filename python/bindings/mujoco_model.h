// pbdval._core's MuJoCo functions (python/bindings/mujoco_model.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace pbdval::python {

/// _mujoco_mjcf(resolved_scene, settings) and _mujoco_2_2_2_model(xml).
void bindMujocoModel(pybind11::module_& m);

}  // namespace pbdval::python
