// On-disk cache of distance grids built from meshes (collisionObjectType 5).
//
// Folder: given by the caller (the library reads no environment; the pbdval command takes it
// from $PBDVAL_SDF_CACHE, $XDG_CACHE_HOME or $HOME); an empty folder disables the cache.
//
// One file per grid, named sdf-<key>.grid, where the key is a 64-bit FNV-1a hash of the format
// version, the precision, the mesh (vertices and triangles, bit for bit), the domain, the
// resolution and the interpolation. File layout (native byte order; the cache is local to one
// machine):
//   magic "PBDVGRID" (8 bytes) | version u32 | key u64 | cells 3 × i32 | domain 6 × f64 |
//   interpolation u32 | node count u64 | nodes f64[count] |
//   checksum u64 (FNV-1a of every preceding byte)
// A file is used only if every field matches and the checksum is right; anything else (a
// truncated, corrupt, foreign or stale file) is rebuilt and replaced. Writes go to a
// temporary file in the same folder, renamed over the target, so readers never see a partial
// file. A folder that cannot be written only costs the cache, never the run.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "pbd/collision/distance_grid.h"
#include "pbd/model/mesh.h"

namespace pbd {

enum class GridCacheOutcome {
  Disabled,  ///< no cache folder: built in memory
  Loaded,    ///< a valid cache file was used
  Built,     ///< no cache file: built and written
  Rebuilt,   ///< a cache file existed but was invalid (corrupt, truncated, stale): rebuilt
};
const char* gridCacheOutcomeName(GridCacheOutcome outcome);

struct CachedGrid {
  std::shared_ptr<const DistanceGrid> grid;
  GridCacheOutcome outcome = GridCacheOutcome::Disabled;
  std::string path;  ///< the cache file (empty when disabled)
};

/// The key of the grid of `mesh` over [domainMin, domainMax] with `cells`.
std::uint64_t meshGridKey(const TriangleMesh& mesh, const Vector3& domainMin,
                          const Vector3& domainMax, const Vector3i& cells,
                          GridInterpolation interpolation);

/// The signed distance grid of the closed mesh `mesh` (MeshDistance) sampled over the
/// domain, from the cache in `folder` when a valid file exists, else built (and cached when
/// `folder` is not empty).
CachedGrid loadOrBuildMeshGrid(const TriangleMesh& mesh, const Vector3& domainMin,
                               const Vector3& domainMax, const Vector3i& cells,
                               GridInterpolation interpolation, const std::string& folder);

}  // namespace pbd
