// MuJoCo 2.2.2's compiled model as plain numbers, for comparing it with another MuJoCo
// version's compile of the same MJCF (tests/python/test_mujoco_model_parity.py through
// pbdval._core._mujoco_2_2_2_model; docs/external-engines.md#one-model-description).
#pragma once

#include <string>
#include <vector>

struct mjModel_;

namespace pbdval::mujoco {

/// `xml` compiled by MuJoCo 2.2.2 through its in-memory file system (nothing is written to
/// disk); a compiler warning is appended to `warnings`. The caller owns the model
/// (mj_deleteModel). Throws EngineError with MuJoCo's message when it rejects the model.
mjModel_* compileMjcf(const std::string& xml, std::vector<std::string>& warnings);

/// One field of mjModel (or of its mjOption `opt`) under MuJoCo's own name: `rows` × `cols`
/// numbers, row-major (a size or an option scalar is 1 × 1).
struct ModelField {
  std::string name;  ///< "body_mass", "nbody", "opt.timestep", "opt.gravity"
  int rows = 1;
  int cols = 1;
  bool integer = false;  ///< int or mjtByte in MuJoCo; mjtNum or float otherwise
  std::vector<double> values;
};

/// Every size (MJMODEL_INTS), option (MJOPTION_SCALARS, MJOPTION_VECTORS) and numeric array
/// (MJMODEL_POINTERS, all but the character buffers) of `xml` compiled by MuJoCo 2.2.2, in
/// mjxmacro.h's order. Throws EngineError with MuJoCo's message when it rejects the model.
std::vector<ModelField> compiledModelFields(const std::string& xml);

}  // namespace pbdval::mujoco
