#include "pbd/io/mesh_writer.h"

#include <cstdint>
#include <cstring>

#include "pbd/io/number_text.h"

namespace pbd {
namespace {

/// `value`'s bytes in little-endian order.
template <class T>
void putLittleEndian(std::ostream& out, T value) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  const std::uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  if (first != 1)  // a big-endian host
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
      std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  out.write(reinterpret_cast<const char*>(raw), sizeof(T));
}

}  // namespace

void writeObj(std::ostream& out, const std::vector<Vector3>& vertices,
              const std::vector<std::array<int, 3>>& triangles) {
  for (const Vector3& v : vertices)
    out << "v " << formatReal(double(v.x())) << ' ' << formatReal(double(v.y())) << ' '
        << formatReal(double(v.z())) << '\n';
  for (const auto& t : triangles)
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

void writePly(std::ostream& out, const std::vector<Vector3>& vertices,
              const std::vector<std::array<int, 3>>& triangles) {
  out << "ply\nformat binary_little_endian 1.0\ncomment written by pbdval\nelement vertex "
      << vertices.size() << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "element face " << triangles.size() << "\nproperty list uchar int vertex_indices\n"
      << "end_header\n";
  for (const Vector3& v : vertices)
    for (int a = 0; a < 3; ++a)
      putLittleEndian<double>(out, double(v[a]));
  for (const auto& t : triangles) {
    putLittleEndian<std::uint8_t>(out, 3);
    for (int index : t)
      putLittleEndian<std::int32_t>(out, std::int32_t(index));
  }
}

}  // namespace pbd
