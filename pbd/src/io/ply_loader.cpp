// Stanford PLY surface meshes (Turk 1994; the format as Paul Bourke documents it): ASCII,
// binary little-endian and binary big-endian. The header declares elements, each with scalar
// properties or list properties; the data follow element by element. pbdval reads the
// `vertex` element's x, y, z (any numeric type) and the `face` element's `vertex_indices` (or
// `vertex_index`) list; every other element and property is read past. Polygons are split into
// a fan around their first vertex, as OBJ faces are.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "pbd/io/mesh_loader.h"
#include "pbd/io/number_text.h"
#include "pbd/io/scene_loader.h"

namespace pbd {
namespace {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<PlyType> plyType(const std::string& name) {
  if (name == "char" || name == "int8") return PlyType::Int8;
  if (name == "uchar" || name == "uint8") return PlyType::UInt8;
  if (name == "short" || name == "int16") return PlyType::Int16;
  if (name == "ushort" || name == "uint16") return PlyType::UInt16;
  if (name == "int" || name == "int32") return PlyType::Int32;
  if (name == "uint" || name == "uint32") return PlyType::UInt32;
  if (name == "float" || name == "float32") return PlyType::Float32;
  if (name == "double" || name == "float64") return PlyType::Float64;
  return std::nullopt;
}

std::size_t sizeOf(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 0;
}

bool isInteger(PlyType type) {
  return type != PlyType::Float32 && type != PlyType::Float64;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  ///< the value type (a list's item type)
  bool isList = false;
  PlyType countType = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

[[noreturn]] void failPly(const std::string& path, const std::string& message) {
  throw SceneError(SceneDiagnostic{path, "", message});
}

/// The data section: values in file order, ASCII tokens or binary numbers of either byte order.
class PlyData {
 public:
  PlyData(const std::string& bytes, std::size_t start, PlyFormat format, std::string path)
      : bytes_(bytes), position_(start), format_(format), path_(std::move(path)) {}

  /// The next value of `type`, as a double; `what` names it in messages.
  double next(PlyType type, const std::string& what) {
    return format_ == PlyFormat::Ascii ? nextAscii(type, what) : nextBinary(type, what);
  }

  /// Bytes (binary) or characters (ASCII) left: bounds the counts a header may claim.
  std::size_t remaining() const { return bytes_.size() - position_; }
  bool binary() const { return format_ != PlyFormat::Ascii; }

  /// Only whitespace (ASCII) or nothing (binary) may follow the last element.
  void expectEnd() {
    if (format_ == PlyFormat::Ascii) {
      while (position_ < bytes_.size() &&
             std::isspace(static_cast<unsigned char>(bytes_[position_])))
        ++position_;
    }
    if (position_ != bytes_.size())
      failPly(path_, std::to_string(bytes_.size() - position_) +
                         " bytes after the last element the header declares");
  }

 private:
  double nextAscii(PlyType type, const std::string& what) {
    while (position_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[position_])))
      ++position_;
    const std::size_t begin = position_;
    while (position_ < bytes_.size() &&
           !std::isspace(static_cast<unsigned char>(bytes_[position_])))
      ++position_;
    if (begin == position_) failPly(path_, what + ": the file ends early");
    const std::string token = bytes_.substr(begin, position_ - begin);
    if (isInteger(type)) {
      const std::optional<std::int64_t> value = parseInteger(token);
      if (!value) failPly(path_, what + ": expected an integer, got '" + token + "'");
      return double(*value);
    }
    const std::optional<double> value = parseReal(token);
    if (!value || !std::isfinite(*value))
      failPly(path_, what + ": expected a finite number, got '" + token + "'");
    return *value;
  }

  double nextBinary(PlyType type, const std::string& what) {
    const std::size_t size = sizeOf(type);
    if (remaining() < size) failPly(path_, what + ": the file ends early");
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + position_, size);
    position_ += size;
    const bool fileIsLittle = format_ == PlyFormat::BinaryLittleEndian;
    const std::uint16_t probe = 1;
    unsigned char first;
    std::memcpy(&first, &probe, 1);
    const bool hostIsLittle = first == 1;
    if (fileIsLittle != hostIsLittle) std::reverse(raw, raw + size);
    switch (type) {
      case PlyType::Int8: {
        std::int8_t v;
        std::memcpy(&v, raw, 1);
        return v;
      }
      case PlyType::UInt8: {
        std::uint8_t v;
        std::memcpy(&v, raw, 1);
        return v;
      }
      case PlyType::Int16: {
        std::int16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case PlyType::UInt16: {
        std::uint16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case PlyType::Int32: {
        std::int32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case PlyType::UInt32: {
        std::uint32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case PlyType::Float32: {
        float v;
        std::memcpy(&v, raw, 4);
        if (!std::isfinite(v)) failPly(path_, what + ": not a finite number");
        return double(v);
      }
      case PlyType::Float64: {
        double v;
        std::memcpy(&v, raw, 8);
        if (!std::isfinite(v)) failPly(path_, what + ": not a finite number");
        return v;
      }
    }
    return 0;
  }

  const std::string& bytes_;
  std::size_t position_;
  PlyFormat format_;
  std::string path_;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::size_t dataStart = 0;
};

PlyHeader readHeader(const std::string& bytes, const std::string& path) {
  PlyHeader header;
  std::size_t position = 0;
  int lineNumber = 0;
  bool sawFormat = false;
  const auto fail = [&](const std::string& message) {
    failPly(path, "header line " + std::to_string(lineNumber) + ": " + message);
  };
  while (true) {
    const std::size_t end = bytes.find('\n', position);
    if (end == std::string::npos) {
      ++lineNumber;
      fail("no end_header line");
    }
    std::string line = bytes.substr(position, end - position);
    position = end + 1;
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::vector<std::string> tokens;
    for (std::string word; words >> word;)
      tokens.push_back(word);
    if (lineNumber == 1) {
      if (tokens.size() != 1 || tokens[0] != "ply") fail("a PLY file starts with the line 'ply'");
      continue;
    }
    if (tokens.empty()) continue;
    const std::string& keyword = tokens[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (tokens.size() != 3 || tokens[2] != "1.0")
        fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      if (tokens[1] == "ascii")
        header.format = PlyFormat::Ascii;
      else if (tokens[1] == "binary_little_endian")
        header.format = PlyFormat::BinaryLittleEndian;
      else if (tokens[1] == "binary_big_endian")
        header.format = PlyFormat::BinaryBigEndian;
      else
        fail("unknown format '" + tokens[1] + "' (ascii, binary_little_endian, binary_big_endian)");
      sawFormat = true;
    } else if (keyword == "element") {
      if (tokens.size() != 3) fail("expected 'element <name> <count>'");
      const std::optional<std::int64_t> count = parseInteger(tokens[2]);
      if (!count || *count < 0) fail("expected a count ≥ 0, got '" + tokens[2] + "'");
      header.elements.push_back({tokens[1], std::uint64_t(*count), {}});
    } else if (keyword == "property") {
      if (header.elements.empty()) fail("a property before any element");
      PlyProperty property;
      if (tokens.size() == 5 && tokens[1] == "list") {
        const std::optional<PlyType> countType = plyType(tokens[2]), itemType = plyType(tokens[3]);
        if (!countType || !isInteger(*countType))
          fail("a list's count type must be an integer type, got '" + tokens[2] + "'");
        if (!itemType) fail("unknown type '" + tokens[3] + "'");
        property = {tokens[4], *itemType, true, *countType};
      } else if (tokens.size() == 3) {
        const std::optional<PlyType> type = plyType(tokens[1]);
        if (!type) fail("unknown type '" + tokens[1] + "'");
        property = {tokens[2], *type, false, PlyType::UInt8};
      } else {
        fail("expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      }
      header.elements.back().properties.push_back(property);
    } else {
      fail("unknown keyword '" + keyword + "'");
    }
  }
  if (!sawFormat) failPly(path, "the header has no format line");
  header.dataStart = position;
  return header;
}

}  // namespace

TriangleMesh parsePly(const std::string& bytes, const std::string& sourceName) {
  const PlyHeader header = readHeader(bytes, sourceName);
  PlyData data(bytes, header.dataStart, header.format, sourceName);
  TriangleMesh mesh;
  bool sawVertices = false;
  std::vector<int> polygon;
  for (const PlyElement& element : header.elements) {
    // Every value takes at least one byte (binary) or two characters (ASCII): a count that
    // claims more values than the file has bytes is an error before anything is allocated.
    const std::uint64_t perItem = std::max<std::uint64_t>(1, element.properties.size());
    if (element.count > data.remaining() / (data.binary() ? 1 : 2) / perItem + 1)
      failPly(sourceName, "element '" + element.name + "' claims " + std::to_string(element.count) +
                              " items; the file is too short");
    const bool isVertex = element.name == "vertex";
    const bool isFace = element.name == "face";
    std::array<int, 3> axis{-1, -1, -1};
    int indexList = -1;
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      if (isVertex && !property.isList) {
        if (property.name == "x") axis[0] = int(p);
        if (property.name == "y") axis[1] = int(p);
        if (property.name == "z") axis[2] = int(p);
      }
      if (isFace && property.isList &&
          (property.name == "vertex_indices" || property.name == "vertex_index"))
        indexList = int(p);
    }
    if (isVertex) {
      if (axis[0] < 0 || axis[1] < 0 || axis[2] < 0)
        failPly(sourceName, "the vertex element needs scalar properties x, y and z");
      sawVertices = true;
      mesh.vertices.reserve(std::size_t(element.count));
    }
    if (isFace && indexList < 0)
      failPly(sourceName, "the face element needs a list property vertex_indices");
    if (isFace && !isInteger(element.properties[std::size_t(indexList)].type))
      failPly(sourceName, "the face element's vertex_indices must be of an integer type");
    if (isFace && !sawVertices)
      failPly(sourceName, "the face element comes before the vertex element");
    for (std::uint64_t item = 0; item < element.count; ++item) {
      const std::string where = element.name + " " + std::to_string(item);
      Vector3 position = Vector3::Zero();
      polygon.clear();
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.isList) {
          const double value = data.next(property.type, where + ", " + property.name);
          for (int a = 0; a < 3; ++a)
            if (isVertex && axis[std::size_t(a)] == int(p)) position[a] = Real(value);
          continue;
        }
        const double count =
            data.next(property.countType, where + ", the count of " + property.name);
        if (count < 0 || count > double(data.remaining()))
          failPly(sourceName, where + ": a list of " + std::to_string(std::int64_t(count)) +
                                  " items does not fit in the file");
        for (std::int64_t k = 0; k < std::int64_t(count); ++k) {
          const double value = data.next(property.type, where + ", " + property.name);
          if (isFace && int(p) == indexList) {
            // An integer type (checked above): exact in a double, and within int64.
            if (!(value >= 0 && value < double(mesh.vertices.size())))
              failPly(sourceName, where + ": vertex index " + std::to_string(std::int64_t(value)) +
                                      " out of range (the file has " +
                                      std::to_string(mesh.vertices.size()) + " vertices)");
            polygon.push_back(int(value));
          }
        }
      }
      if (isVertex) mesh.vertices.push_back(position);
      if (isFace) {
        if (polygon.size() < 3)
          failPly(sourceName, where + ": a face needs at least 3 vertices, got " +
                                  std::to_string(polygon.size()));
        for (std::size_t k = 1; k + 1 < polygon.size(); ++k)  // fan around the first vertex
          mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
      }
    }
  }
  data.expectEnd();
  if (!sawVertices) failPly(sourceName, "no vertex element");
  return mesh;
}

TriangleMesh loadSurfaceMesh(const std::string& path, ObjPrecision objPrecision) {
  std::string extension = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  for (char& c : extension)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".ply" ? loadPly(path) : loadObj(path, objPrecision);
}

TriangleMesh loadPly(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) failPly(path, "cannot open the file");
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  return parsePly(bytes, path);
}

}  // namespace pbd
