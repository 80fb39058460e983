#include "pbd/io/discregrid_file.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "pbd/io/scene_loader.h"
#include "scene_reading.h"

namespace pbd {
namespace {

/// At most 256³ cells in total, as for grids built from meshes (rigid_body_reader.cpp).
constexpr std::uint64_t kMaxCells = 256ULL * 256 * 256;
/// Discregrid's mark of a discarded cell in the cell map.
constexpr std::uint32_t kDiscardedCell = std::numeric_limits<std::uint32_t>::max();

/// A node of a cell in Discregrid's local order: a corner (axis −1) or an edge node along
/// `axis` on `side` (0: at 1/3, 1: at 2/3), at the lattice offset (di, dj, dk) from the cell's
/// lowest corner.
struct LocalNode {
  int axis, di, dj, dk, side;
};

/// Discregrid's 32 local nodes: corners by bits (x, y, z); the edges along x at the (y, z)
/// offsets (0,0), (0,1), (1,0), (1,1); along y at the (x, z) offsets (0,0), (1,0), (0,1),
/// (1,1); along z at the (x, y) offsets (0,0), (0,1), (1,0), (1,1); each edge's 1/3 node first.
std::vector<LocalNode> discregridLocalNodes() {
  std::vector<LocalNode> nodes;
  for (int corner = 0; corner < 8; ++corner)
    nodes.push_back({-1, corner & 1, corner >> 1 & 1, corner >> 2 & 1, 0});
  for (int q = 0; q < 4; ++q)
    for (int side = 0; side < 2; ++side)
      nodes.push_back({0, 0, q >> 1, q & 1, side});
  for (int q = 0; q < 4; ++q)
    for (int side = 0; side < 2; ++side)
      nodes.push_back({1, q & 1, 0, q >> 1, side});
  for (int q = 0; q < 4; ++q)
    for (int side = 0; side < 2; ++side)
      nodes.push_back({2, q >> 1, q & 1, 0, side});
  return nodes;
}

/// Sequential reads from the file's bytes, failing with the byte offset.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, const std::string& source)
      : bytes_(bytes), source_(source) {}

  [[noreturn]] void fail(const std::string& message) const {
    throw SceneError(SceneDiagnostic{source_, "",
                                     "Discregrid grid (.csdf): " + message + " (at byte " +
                                         std::to_string(offset_) + " of " +
                                         std::to_string(bytes_.size()) + ")"});
  }

  template <typename T>
  T read(const char* what) {
    T value;
    if (bytes_.size() - offset_ < sizeof(T))
      fail("truncated: the file ends inside the " + std::string(what));
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }

  /// A count of items of `itemBytes` each that must fit in the rest of the file.
  std::uint64_t count(const char* what, std::uint64_t itemBytes) {
    const std::uint64_t n = read<std::uint64_t>(what);
    if (n > (bytes_.size() - offset_) / itemBytes)
      fail("truncated or corrupt: " + std::string(what) + " " + std::to_string(n) +
           " does not fit in the rest of the file");
    return n;
  }

  std::size_t remaining() const { return bytes_.size() - offset_; }

 private:
  const std::string& bytes_;
  const std::string& source_;
  std::size_t offset_ = 0;
};

}  // namespace

DistanceGrid parseDiscregridGrid(const std::string& bytes, const std::string& sourceName) {
  ByteReader in(bytes, sourceName);
  double domain[6];
  for (double& d : domain)
    d = in.read<double>("domain");
  Vector3i cells;
  for (int axis = 0; axis < 3; ++axis) {
    const std::uint32_t n = in.read<std::uint32_t>("resolution");
    if (n < 1 || n > std::uint32_t(scene_io::kMaxGridCellsPerAxis))
      in.fail("resolution " + std::to_string(n) + ": expected 1 to " +
              std::to_string(scene_io::kMaxGridCellsPerAxis) + " cells per axis");
    cells(axis) = int(n);
  }
  for (int axis = 0; axis < 3; ++axis)
    if (!std::isfinite(domain[axis]) || !std::isfinite(domain[3 + axis]) ||
        !(domain[axis] < domain[3 + axis]))
      in.fail("the domain must be finite with min < max on every axis");
  const std::uint64_t cellCount =
      std::uint64_t(cells.x()) * std::uint64_t(cells.y()) * std::uint64_t(cells.z());
  if (cellCount > kMaxCells) in.fail("at most 256^3 cells in total");
  for (int k = 0; k < 6; ++k)
    in.read<double>("cell size");  // derived from the domain and resolution; recomputed
  if (in.read<std::uint64_t>("cell count") != cellCount)
    in.fail("the cell count differs from the product of the resolution");
  const std::uint64_t fields = in.read<std::uint64_t>("field count");
  if (fields < 1) in.fail("the grid holds no field");

  // Nodes, cells and cell map of every field; field 0 is kept.
  std::vector<double> nodes;
  if (in.count("node table's field count", 8) != fields)
    in.fail("the node table's field count differs from the header's");
  for (std::uint64_t f = 0; f < fields; ++f) {
    const std::uint64_t n = in.count("node count", sizeof(double));
    for (std::uint64_t k = 0; k < n; ++k) {
      const double value = in.read<double>("node values");
      if (f == 0) nodes.push_back(value);
    }
  }
  using CellNodes = std::array<std::uint32_t, 32>;
  std::vector<CellNodes> cellTable;
  if (in.count("cell table's field count", 8) != fields)
    in.fail("the cell table's field count differs from the header's");
  for (std::uint64_t f = 0; f < fields; ++f) {
    const std::uint64_t n = in.count("cell count", sizeof(CellNodes));
    for (std::uint64_t k = 0; k < n; ++k) {
      CellNodes cell;
      for (std::uint32_t& index : cell)
        index = in.read<std::uint32_t>("cell table");
      if (f == 0) cellTable.push_back(cell);
    }
  }
  std::vector<std::uint32_t> cellMap;
  if (in.count("cell map's field count", 8) != fields)
    in.fail("the cell map's field count differs from the header's");
  for (std::uint64_t f = 0; f < fields; ++f) {
    if (in.count("cell map count", sizeof(std::uint32_t)) != cellCount)
      in.fail("the cell map of field " + std::to_string(f) + " must list every cell");
    for (std::uint64_t k = 0; k < cellCount; ++k) {
      const std::uint32_t row = in.read<std::uint32_t>("cell map");
      if (f == 0) cellMap.push_back(row);
    }
  }
  if (in.remaining() != 0)
    in.fail(std::to_string(in.remaining()) + " bytes after the cell map (not a Discregrid grid)");

  // Field 0 in pbdval's layout, through the cells table; every node once, shared nodes equal.
  const std::vector<LocalNode> local = discregridLocalNodes();
  const std::size_t count = DistanceGrid::nodeCount(cells, GridInterpolation::CubicLagrange);
  std::vector<Real> values(count, Real(0));
  std::vector<char> filled(count, 0);
  std::vector<double> filledWith(count, 0);
  const auto fieldError = [&](const std::string& message) {
    throw SceneError(SceneDiagnostic{sourceName, "", "Discregrid grid (.csdf): " + message});
  };
  for (std::uint64_t l = 0; l < cellCount; ++l) {
    const int i = int(l % std::uint64_t(cells.x()));
    const int j = int(l / std::uint64_t(cells.x()) % std::uint64_t(cells.y()));
    const int k = int(l / (std::uint64_t(cells.x()) * std::uint64_t(cells.y())));
    const std::uint32_t row = cellMap[l];
    if (row == kDiscardedCell)
      fieldError("cell " + std::to_string(l) +
                 " was discarded (a reduced grid); pbdval needs every cell");
    if (row >= cellTable.size())
      fieldError("the cell map sends cell " + std::to_string(l) + " to row " + std::to_string(row) +
                 " of a cell table of " + std::to_string(cellTable.size()));
    for (std::size_t m = 0; m < 32; ++m) {
      const std::uint32_t source = cellTable[row][m];
      if (source >= nodes.size())
        fieldError("cell " + std::to_string(l) + " names node " + std::to_string(source) + " of " +
                   std::to_string(nodes.size()));
      const double value = nodes[source];
      if (!std::isfinite(value) || value == std::numeric_limits<double>::max())
        fieldError("node " + std::to_string(source) +
                   " has no finite value (a grid sampled with a predicate); pbdval needs every "
                   "node");
      const LocalNode& n = local[m];
      const std::size_t target =
          n.axis < 0 ? DistanceGrid::lagrangeCornerIndex(cells, i + n.di, j + n.dj, k + n.dk)
                     : DistanceGrid::lagrangeEdgeIndex(cells, n.axis, i + n.di, j + n.dj, k + n.dk,
                                                       n.side);
      if (filled[target] && filledWith[target] != value)
        fieldError("cell " + std::to_string(l) +
                   " gives a node it shares with another cell a "
                   "different value (a corrupt cell table)");
      filled[target] = 1;
      filledWith[target] = value;
      values[target] = Real(value);
    }
  }
  const Vector3 domainMin(static_cast<Real>(domain[0]), static_cast<Real>(domain[1]),
                          static_cast<Real>(domain[2]));
  const Vector3 domainMax(static_cast<Real>(domain[3]), static_cast<Real>(domain[4]),
                          static_cast<Real>(domain[5]));
  return DistanceGrid(domainMin, domainMax, cells, GridInterpolation::CubicLagrange,
                      std::move(values));
}

DistanceGrid readDiscregridGrid(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw SceneError(SceneDiagnostic{path, "", "Discregrid grid (.csdf): cannot open the file"});
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw SceneError(SceneDiagnostic{path, "", "Discregrid grid (.csdf): cannot read the file"});
  return parseDiscregridGrid(bytes, path);
}

}  // namespace pbd
