#include "pbd/collision/grid_cache.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "pbd/collision/mesh_distance.h"

namespace pbd {
namespace {

constexpr char kMagic[8] = {'P', 'B', 'D', 'V', 'G', 'R', 'I', 'D'};
constexpr std::uint32_t kVersion = 2;
constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

void hashBytes(std::uint64_t& hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= kFnvPrime;
  }
}

template <typename T>
void hashValue(std::uint64_t& hash, const T& value) {
  hashBytes(hash, &value, sizeof value);
}

/// Serialises the grid with its header and checksum.
std::string encode(const DistanceGrid& grid, std::uint64_t key) {
  std::string bytes(kMagic, sizeof kMagic);
  auto append = [&bytes](const auto& value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
  };
  append(kVersion);
  append(key);
  for (int axis = 0; axis < 3; ++axis)
    append(std::int32_t(grid.cells()(axis)));
  for (int axis = 0; axis < 3; ++axis)
    append(double(grid.domainMin()(axis)));
  for (int axis = 0; axis < 3; ++axis)
    append(double(grid.domainMax()(axis)));
  append(std::uint32_t(grid.interpolation()));
  append(std::uint64_t(grid.nodes().size()));
  for (Real value : grid.nodes())
    append(double(value));
  std::uint64_t checksum = kFnvOffset;
  hashBytes(checksum, bytes.data(), bytes.size());
  append(checksum);
  return bytes;
}

/// Reads `bytes` as a grid with exactly this key, domain and resolution; false if anything
/// differs or the checksum fails.
bool decode(const std::string& bytes, std::uint64_t key, const Vector3& domainMin,
            const Vector3& domainMax, const Vector3i& cells, GridInterpolation interpolation,
            DistanceGrid& grid) {
  const std::size_t count = DistanceGrid::nodeCount(cells, interpolation);
  const std::size_t header = sizeof kMagic + 4 + 8 + 3 * 4 + 6 * 8 + 4 + 8;
  if (bytes.size() != header + 8 * count + 8) return false;
  if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) return false;
  std::size_t offset = sizeof kMagic;
  auto read = [&](auto& value) {
    std::memcpy(&value, bytes.data() + offset, sizeof value);
    offset += sizeof value;
  };
  std::uint32_t version = 0, fileInterpolation = 0;
  std::uint64_t fileKey = 0, fileCount = 0, checksum = 0;
  std::int32_t fileCells[3];
  double bounds[6];
  read(version);
  read(fileKey);
  for (std::int32_t& c : fileCells)
    read(c);
  for (double& b : bounds)
    read(b);
  read(fileInterpolation);
  read(fileCount);
  if (version != kVersion || fileKey != key || fileCount != count ||
      fileInterpolation != std::uint32_t(interpolation))
    return false;
  for (int axis = 0; axis < 3; ++axis) {
    if (fileCells[axis] != cells(axis) || bounds[axis] != double(domainMin(axis)) ||
        bounds[3 + axis] != double(domainMax(axis)))
      return false;
  }
  std::vector<Real> nodes(count);
  for (Real& value : nodes) {
    double stored;
    read(stored);
    if (!std::isfinite(stored)) return false;
    value = static_cast<Real>(stored);
  }
  std::uint64_t expected = kFnvOffset;
  hashBytes(expected, bytes.data(), offset);
  read(checksum);
  if (checksum != expected) return false;
  grid = DistanceGrid(domainMin, domainMax, cells, interpolation, std::move(nodes));
  return true;
}

bool readFile(const std::filesystem::path& path, std::string& bytes) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) return false;
  std::ostringstream buffer;
  buffer << stream.rdbuf();
  bytes = buffer.str();
  return true;
}

/// Writes atomically: a temporary file in the same folder, then rename. Best effort.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes) {
  std::error_code error;
  std::filesystem::create_directories(path.parent_path(), error);
  if (error) return;
  int stackMarker = 0;
  const auto unique = std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count()) ^
                      std::uint64_t(reinterpret_cast<std::uintptr_t>(&stackMarker));
  const std::filesystem::path temporary =
      path.string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(unique);
  {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    stream.flush();
    if (!stream) {
      std::filesystem::remove(temporary, error);
      return;
    }
  }
  std::filesystem::rename(temporary, path, error);
  if (error) std::filesystem::remove(temporary, error);
}

std::string hexadecimal(std::uint64_t value) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text(16, '0');
  for (int i = 15; i >= 0; --i, value >>= 4)
    text[std::size_t(i)] = kDigits[value & 15];
  return text;
}

}  // namespace

const char* gridCacheOutcomeName(GridCacheOutcome outcome) {
  switch (outcome) {
    case GridCacheOutcome::Disabled:
      return "disabled";
    case GridCacheOutcome::Loaded:
      return "loaded";
    case GridCacheOutcome::Built:
      return "built";
    case GridCacheOutcome::Rebuilt:
      return "rebuilt";
  }
  return "?";
}

std::uint64_t meshGridKey(const TriangleMesh& mesh, const Vector3& domainMin,
                          const Vector3& domainMax, const Vector3i& cells,
                          GridInterpolation interpolation) {
  std::uint64_t hash = kFnvOffset;
  hashValue(hash, kVersion);
  hashValue(hash, std::uint32_t(sizeof(Real)));
  hashValue(hash, std::uint64_t(mesh.vertices.size()));
  for (const Vector3& v : mesh.vertices)
    for (int axis = 0; axis < 3; ++axis)
      hashValue(hash, double(v(axis)));
  hashValue(hash, std::uint64_t(mesh.triangles.size()));
  for (const auto& t : mesh.triangles)
    for (int index : t)
      hashValue(hash, std::int32_t(index));
  for (int axis = 0; axis < 3; ++axis) {
    hashValue(hash, double(domainMin(axis)));
    hashValue(hash, double(domainMax(axis)));
    hashValue(hash, std::int32_t(cells(axis)));
  }
  hashValue(hash, std::uint32_t(interpolation));
  return hash;
}

CachedGrid loadOrBuildMeshGrid(const TriangleMesh& mesh, const Vector3& domainMin,
                               const Vector3& domainMax, const Vector3i& cells,
                               GridInterpolation interpolation, const std::string& folder) {
  CachedGrid result;
  const std::uint64_t key = meshGridKey(mesh, domainMin, domainMax, cells, interpolation);
  bool fileExisted = false;
  if (!folder.empty()) {
    const std::filesystem::path path =
        std::filesystem::path(folder) / ("sdf-" + hexadecimal(key) + ".grid");
    result.path = path.string();
    std::string bytes;
    fileExisted = readFile(path, bytes);
    DistanceGrid cached;
    if (fileExisted && decode(bytes, key, domainMin, domainMax, cells, interpolation, cached)) {
      result.grid = std::make_shared<const DistanceGrid>(std::move(cached));
      result.outcome = GridCacheOutcome::Loaded;
      return result;
    }
  }
  const MeshDistance distance(mesh);
  auto grid = std::make_shared<const DistanceGrid>(DistanceGrid::sample(
      domainMin, domainMax, cells, [&](const Vector3& x) { return distance.signedDistance(x); },
      interpolation));
  result.grid = grid;
  if (folder.empty()) return result;
  writeFileAtomically(result.path, encode(*grid, key));
  result.outcome = fileExisted ? GridCacheOutcome::Rebuilt : GridCacheOutcome::Built;
  return result;
}

}  // namespace pbd
