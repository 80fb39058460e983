#include "adapters/mujoco/mujoco_model_fields.h"

#include <mujoco/mjxmacro.h>
#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>
#include <type_traits>

#include "adapters/engine.h"
#include "adapters/mujoco/mujoco_errors.h"

namespace pbdval::mujoco {
namespace {

constexpr const char* kModelFile = "pbdval.xml";

/// MuJoCo's in-memory file system (about 2 MB in 2.2.2: kept off the stack).
struct VirtualFiles {
  std::unique_ptr<mjVFS> vfs = std::make_unique<mjVFS>();
  VirtualFiles() { mj_defaultVFS(vfs.get()); }
  ~VirtualFiles() { mj_deleteVFS(vfs.get()); }  // never mj_deleteFileVFS: it hangs in 2.2.2
  VirtualFiles(const VirtualFiles&) = delete;
  VirtualFiles& operator=(const VirtualFiles&) = delete;
};

template <class T>
ModelField field(const std::string& name, const T* values, int rows, int cols) {
  ModelField f;
  f.name = name;
  f.rows = rows;
  f.cols = cols;
  f.integer = std::is_integral_v<T>;
  f.values.reserve(std::size_t(rows) * std::size_t(cols));
  for (int i = 0; i < rows * cols; ++i)
    f.values.push_back(double(values[i]));
  return f;
}

}  // namespace

mjModel* compileMjcf(const std::string& xml, std::vector<std::string>& warnings) {
  VirtualFiles files;
  char error[1024] = "";
  mjModel* model = nullptr;
  guarded("mj_loadXML", warnings, [&] {
    if (mj_makeEmptyFileVFS(files.vfs.get(), kModelFile, int(xml.size())) != 0) return;
    std::memcpy(files.vfs->filedata[mj_findFileVFS(files.vfs.get(), kModelFile)], xml.data(),
                xml.size());
    model = mj_loadXML(kModelFile, files.vfs.get(), error, sizeof error);
    mj_freeLastXML();  // MuJoCo keeps the parsed XML in a global; nothing here needs it
  });
  if (model == nullptr)
    throw EngineError(std::string("MuJoCo rejected the model: ") +
                      (error[0] != 0 ? error : "the VFS could not hold it"));
  if (error[0] != 0) warnings.push_back(std::string("MuJoCo compiler: ") + error);
  return model;
}

std::vector<ModelField> compiledModelFields(const std::string& xml) {
  std::vector<std::string> warnings;
  const std::unique_ptr<mjModel, void (*)(mjModel*)> owned(compileMjcf(xml, warnings),
                                                           mj_deleteModel);
  const mjModel* m = owned.get();
  std::vector<ModelField> fields;
#define X(name) fields.push_back(field(#name, &m->name, 1, 1));
  MJMODEL_INTS
#undef X
#define X(type, name) fields.push_back(field("opt." #name, &m->opt.name, 1, 1));
  MJOPTION_SCALARS
#undef X
#define X(name, size) fields.push_back(field("opt." #name, m->opt.name, 1, size));
  MJOPTION_VECTORS
#undef X
  MJMODEL_POINTERS_PREAMBLE(m)
  (void)nq, (void)nv, (void)na, (void)nu, (void)nmocap;  // the rows are read from m below
  // Character buffers (names, paths, text) are not numbers: left out.
#define X(type, name, rows, cols)            \
  if constexpr (!std::is_same_v<type, char>) \
    fields.push_back(field(#name, m->name, int(m->rows), int(cols)));
  MJMODEL_POINTERS
#undef X
  return fields;
}

}  // namespace pbdval::mujoco
