#include "validation/io/trajectory.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "pbd/io/input_checks.h"
#include "pbd/io/number_text.h"

namespace pbdval {

std::string formatNumber(double value) {
  return pbd::formatReal(value);
}

void writeCsvHeader(std::ostream& out) {
  out << kTrajectoryCsvHeader << '\n';
}

void writeCsvRows(std::ostream& out, const State& state) {
  CsvRowWriter().write(out, state);
}

void CsvRowWriter::write(std::ostream& out, const State& state) {
  // The time exactly as the engine's clock has it (an accumulated clock reads 0.30000000000000004,
  // not 0.3): metrics computed from a CSV then equal the runner's to the bit (docs/python.md).
  // A row is formatted into one buffer and written at once: no string per number (the CSV is
  // most of the cost of a run outside the engine's step; issue 13).
  char time[pbd::kRealTextCapacity];
  const std::size_t timeLength = std::size_t(pbd::writeReal(time, state.time) - time);
  char row[16 * (pbd::kRealTextCapacity + 1)];  // the time, the id, 13 numbers, commas, newline
  static_assert(kCsvNumberCapacity == pbd::kRealTextCapacity);
  if (columns_.size() != 13 * state.bodies.size()) columns_.assign(13 * state.bodies.size(), {});
  Column* column = columns_.data();
  for (const BodyState& b : state.bodies) {
    const Quaternion q = b.rotation.w() < 0 ? Quaternion(-b.rotation.coeffs()) : b.rotation;
    char* end = row;
    std::memcpy(end, time, timeLength);
    end += timeLength;
    *end++ = ',';
    end = std::to_chars(end, end + 16, b.id).ptr;
    for (double v :
         {double(b.position.x()), double(b.position.y()), double(b.position.z()), double(q.w()),
          double(q.x()), double(q.y()), double(q.z()), double(b.velocity.x()),
          double(b.velocity.y()), double(b.velocity.z()), double(b.angularVelocity.x()),
          double(b.angularVelocity.y()), double(b.angularVelocity.z())}) {
      *end++ = ',';
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      if (column->length == 0 || column->bits != bits) {
        column->bits = bits;
        column->length = static_cast<unsigned char>(pbd::writeReal(column->text, v) - column->text);
      }
      std::memcpy(end, column->text, column->length);
      end += column->length;
      ++column;
    }
    *end++ = '\n';
    out.write(row, std::streamsize(end - row));
  }
}

namespace {

/// Where a row is, for messages: "FILE: line 3", "FILE: row 2". The text is made only when a
/// message needs it (a runner reads tens of thousands of rows per second of external runs).
struct RowPlace {
  const std::string& path;
  const char* unit;  ///< "line" or "row"
  std::size_t number;
  std::string text() const { return path + ": " + unit + " " + std::to_string(number); }
};

/// A trajectory file's rows, `columns` doubles each, handed to `row` with their place.
using RowSink = std::function<void(const double* fields, const RowPlace& where)>;

/// The rows of a CSV with exactly `header` on its first line and `columns` numbers per line.
void parseCsvRows(const std::string& text, const char* header, int columns, const std::string& path,
                  const RowSink& row) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != header)
    throw std::runtime_error(path + ": line 1: expected the header '" + std::string(header) + "'");
  std::vector<double> fields(std::size_t(columns), 0.0);
  int lineNumber = 1;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.empty()) continue;
    const char* p = line.data();
    const char* end = line.data() + line.size();
    for (int f = 0; f < columns; ++f) {
      const auto r = std::from_chars(p, end, fields[std::size_t(f)]);
      if (r.ec != std::errc() || (f < columns - 1 && (r.ptr == end || *r.ptr != ',')) ||
          (f == columns - 1 && r.ptr != end))
        throw std::runtime_error(path + ": line " + std::to_string(lineNumber) + ": expected " +
                                 std::to_string(columns) + " comma-separated numbers");
      p = r.ptr + 1;
    }
    row(fields.data(), RowPlace{path, "line", std::size_t(lineNumber)});
  }
}

/// The rows of an NPY file of little-endian float64, shape (rows, `columns`), C order.
void parseNpyRows(const std::string& bytes, int columns, const std::string& path,
                  const RowSink& row) {
  const std::string shape = "shape (rows, " + std::to_string(columns) + ")";
  auto fail = [&](const std::string& expected) -> std::runtime_error {
    return std::runtime_error(path + ": expected " + expected + " (an .npy file of float64, " +
                              shape + ", C order: docs/external-engines.md#trajectory)");
  };
  static const std::string kMagic = "\x93NUMPY";
  if (bytes.size() < 10 || bytes.compare(0, kMagic.size(), kMagic) != 0)
    throw fail("the NPY magic");
  const int major = static_cast<unsigned char>(bytes[6]);
  std::size_t headerLength = 0, offset = 0;
  if (major == 1) {
    headerLength =
        static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
    offset = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw fail("a complete NPY preamble");
    for (int i = 3; i >= 0; --i)
      headerLength = (headerLength << 8) | static_cast<unsigned char>(bytes[8 + std::size_t(i)]);
    offset = 12;
  } else {
    throw fail("NPY format version 1, 2 or 3, got " + std::to_string(major));
  }
  if (bytes.size() < offset + headerLength) throw fail("a complete NPY header");
  const std::string header = bytes.substr(offset, headerLength);
  auto has = [&](const char* text) { return header.find(text) != std::string::npos; };
  if (!has("'descr': '<f8'")) throw fail("'descr': '<f8' (little-endian float64)");
  if (!has("'fortran_order': False")) throw fail("'fortran_order': False");
  const std::size_t shapeAt = header.find("'shape': (");
  if (shapeAt == std::string::npos) throw fail("a 'shape' entry");
  const char* p = header.data() + shapeAt + 10;
  const char* end = header.data() + header.size();
  std::size_t rows = 0, found = 0;
  auto r = std::from_chars(p, end, rows);
  if (r.ec != std::errc() || r.ptr + 2 > end || r.ptr[0] != ',' || r.ptr[1] != ' ')
    throw fail(shape);
  r = std::from_chars(r.ptr + 2, end, found);
  if (r.ec != std::errc() || r.ptr >= end || *r.ptr != ')' || found != std::size_t(columns))
    throw fail(shape);
  const std::size_t rowBytes = std::size_t(columns) * sizeof(double);
  const std::size_t dataAt = offset + headerLength;
  if (rows > (bytes.size() - dataAt) / rowBytes || bytes.size() - dataAt != rows * rowBytes)
    throw fail(std::to_string(rows) + " rows of data (" + std::to_string(rows * rowBytes) +
               " bytes), found " + std::to_string(bytes.size() - dataAt) + " bytes");
  std::vector<double> fields(std::size_t(columns), 0.0);
  for (std::size_t i = 0; i < rows; ++i) {
    std::memcpy(fields.data(), bytes.data() + dataAt + i * rowBytes, rowBytes);
    row(fields.data(), RowPlace{path, "row", i});
  }
}

/// The time and the id or index of a row (fields 1 and 2) must be finite, the second an integer;
/// a state may not be finite: a diverged run's last sample holds its NaN or inf (the runner then
/// reports the run diverged). A new sample starts when the time changes.
State& sampleOfRow(Trajectory& trajectory, const double* fields, const RowPlace& where,
                   const char* idName) {
  for (int f = 0; f < 2; ++f)
    if (!std::isfinite(fields[f]))
      throw std::runtime_error(where.text() + ": field " + std::to_string(f + 1) +
                               " is not a finite number");
  if (fields[1] != std::floor(fields[1]) || std::abs(fields[1]) > 2147483647.0)
    throw std::runtime_error(where.text() + ": the " + std::string(idName) +
                             " (field 2) is not an integer");
  if (trajectory.samples.empty() || trajectory.samples.back().time != fields[0]) {
    trajectory.samples.emplace_back();
    trajectory.samples.back().time = fields[0];
  }
  return trajectory.samples.back();
}

/// One body row (t, id, x y z, qw qx qy qz, vx vy vz, wx wy wz).
void appendBodyRow(Trajectory& trajectory, const double* fields, const RowPlace& where) {
  State& sample = sampleOfRow(trajectory, fields, where, "body id");
  BodyState b;
  b.id = static_cast<int>(fields[1]);
  b.position = Vector3(Real(fields[2]), Real(fields[3]), Real(fields[4]));
  b.rotation = Quaternion(Real(fields[5]), Real(fields[6]), Real(fields[7]), Real(fields[8]));
  b.velocity = Vector3(Real(fields[9]), Real(fields[10]), Real(fields[11]));
  b.angularVelocity = Vector3(Real(fields[12]), Real(fields[13]), Real(fields[14]));
  sample.bodies.push_back(b);
}

/// One particle row (t, index, x y z, vx vy vz); the indices of a sample run 0, 1, 2, ...
void appendParticleRow(Trajectory& trajectory, const double* fields, const RowPlace& where) {
  State& sample = sampleOfRow(trajectory, fields, where, "particle index");
  if (fields[1] != double(sample.particles.size()))
    throw std::runtime_error(where.text() + ": particle " + formatNumber(fields[1]) +
                             ", expected " + std::to_string(sample.particles.size()) +
                             " (each sample lists every particle in scene order, from 0)");
  ParticleState p;
  p.position = Vector3(Real(fields[2]), Real(fields[3]), Real(fields[4]));
  p.velocity = Vector3(Real(fields[5]), Real(fields[6]), Real(fields[7]));
  sample.particles.push_back(p);
}

/// One segment row (t, index, qw qx qy qz, wx wy wz); the indices of a sample run 0, 1, 2, ...
void appendSegmentRow(Trajectory& trajectory, const double* fields, const RowPlace& where) {
  State& sample = sampleOfRow(trajectory, fields, where, "segment index");
  if (fields[1] != double(sample.segments.size()))
    throw std::runtime_error(where.text() + ": segment " + formatNumber(fields[1]) + ", expected " +
                             std::to_string(sample.segments.size()) +
                             " (each sample lists every rod segment in order, from 0)");
  SegmentState q;
  q.rotation = Quaternion(Real(fields[2]), Real(fields[3]), Real(fields[4]), Real(fields[5]));
  q.angularVelocity = Vector3(Real(fields[6]), Real(fields[7]), Real(fields[8]));
  sample.segments.push_back(q);
}

std::string readWholeFile(const std::string& path, const char* what) {
  const std::string problem = pbd::inputFileProblem(path, what);
  if (!problem.empty()) throw std::runtime_error(pbd::printableText(path + ": " + problem));
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error(pbd::printableText(path + ": cannot be read"));
  // Read in one piece into a string of the file's size (through a stringstream the bytes were
  // copied twice: a tenth of an external run's cost on the runner's side).
  const std::streamoff size = in.tellg();
  std::string bytes(size > 0 ? std::size_t(size) : 0, '\0');
  in.seekg(0);
  in.read(bytes.data(), std::streamsize(bytes.size()));
  bytes.resize(std::size_t(in.gcount()));  // a file that shrank meanwhile
  // and the rest of one that grew, or whose size was not known
  char rest[4096];
  while (in.read(rest, sizeof rest) || in.gcount() > 0)
    bytes.append(rest, std::size_t(in.gcount()));
  return bytes;
}

}  // namespace

Trajectory readTrajectoryCsv(const std::string& path) {
  return parseTrajectoryCsv(readWholeFile(path, "trajectory"), path);
}

Trajectory parseTrajectoryCsv(const std::string& text, const std::string& sourceName) {
  Trajectory trajectory;
  parseCsvRows(
      text, kTrajectoryCsvHeader, 15, pbd::printableText(sourceName),
      [&](const double* f, const RowPlace& where) { appendBodyRow(trajectory, f, where); });
  return trajectory;
}

Trajectory readTrajectoryNpy(const std::string& path) {
  return parseTrajectoryNpy(readWholeFile(path, "trajectory"), path);
}

Trajectory parseTrajectoryNpy(const std::string& bytes, const std::string& sourceName) {
  Trajectory trajectory;
  parseNpyRows(
      bytes, 15, pbd::printableText(sourceName),
      [&](const double* f, const RowPlace& where) { appendBodyRow(trajectory, f, where); });
  return trajectory;
}

Trajectory parseParticleTrajectoryCsv(const std::string& text, const std::string& sourceName) {
  Trajectory trajectory;
  parseCsvRows(
      text, kParticleCsvHeader, 8, pbd::printableText(sourceName),
      [&](const double* f, const RowPlace& where) { appendParticleRow(trajectory, f, where); });
  return trajectory;
}

Trajectory parseParticleTrajectoryNpy(const std::string& bytes, const std::string& sourceName) {
  Trajectory trajectory;
  parseNpyRows(
      bytes, 8, pbd::printableText(sourceName),
      [&](const double* f, const RowPlace& where) { appendParticleRow(trajectory, f, where); });
  return trajectory;
}

Trajectory readParticleTrajectory(const std::string& path) {
  const std::string content = readWholeFile(path, "particle trajectory");
  return hasNpyExtension(path) ? parseParticleTrajectoryNpy(content, path)
                               : parseParticleTrajectoryCsv(content, path);
}

Trajectory parseSegmentTrajectoryCsv(const std::string& text, const std::string& sourceName) {
  Trajectory trajectory;
  parseCsvRows(
      text, kSegmentCsvHeader, 9, pbd::printableText(sourceName),
      [&](const double* f, const RowPlace& where) { appendSegmentRow(trajectory, f, where); });
  return trajectory;
}

Trajectory parseSegmentTrajectoryNpy(const std::string& bytes, const std::string& sourceName) {
  Trajectory trajectory;
  parseNpyRows(
      bytes, 9, pbd::printableText(sourceName),
      [&](const double* f, const RowPlace& where) { appendSegmentRow(trajectory, f, where); });
  return trajectory;
}

Trajectory readSegmentTrajectory(const std::string& path) {
  const std::string content = readWholeFile(path, "segment trajectory");
  return hasNpyExtension(path) ? parseSegmentTrajectoryNpy(content, path)
                               : parseSegmentTrajectoryCsv(content, path);
}

namespace {

/// NPY 1.0 preamble of a little-endian float64 array of shape (rows, columns), C order: magic,
/// version, header length (uint16 LE), then a Python dict literal padded with spaces and ended
/// by '\n' so that the data starts at a multiple of 64 bytes.
void writeNpyPreamble(std::ostream& out, std::size_t rows, int columns) {
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                       std::to_string(rows) + ", " + std::to_string(columns) + "), }";
  const std::size_t preamble = 10;
  const std::size_t total = (preamble + header.size() + 1 + 63) / 64 * 64;
  header.append(total - preamble - header.size() - 1, ' ');
  header += '\n';
  const char magic[8] = {'\x93', 'N', 'U', 'M', 'P', 'Y', 1, 0};
  out.write(magic, sizeof magic);
  const char length[2] = {char(header.size() & 0xff), char((header.size() >> 8) & 0xff)};
  out.write(length, sizeof length);
  out.write(header.data(), std::streamsize(header.size()));
}

/// One row of doubles as the file's '<f8' (x86-64 and AArch64 are little-endian).
template <std::size_t N>
void writeNpyRow(std::ostream& out, const double (&row)[N]) {
  static_assert(sizeof(double) == 8, "float64 rows");
  out.write(reinterpret_cast<const char*>(row), sizeof row);
}

}  // namespace

void writeTrajectoryNpy(std::ostream& out, const std::vector<State>& samples) {
  std::size_t rows = 0;
  for (const State& s : samples)
    rows += s.bodies.size();
  writeNpyPreamble(out, rows, 15);
  for (const State& s : samples)
    for (const BodyState& b : s.bodies) {
      const Quaternion q = b.rotation.w() < 0 ? Quaternion(-b.rotation.coeffs()) : b.rotation;
      const double row[15] = {s.time,
                              double(b.id),
                              double(b.position.x()),
                              double(b.position.y()),
                              double(b.position.z()),
                              double(q.w()),
                              double(q.x()),
                              double(q.y()),
                              double(q.z()),
                              double(b.velocity.x()),
                              double(b.velocity.y()),
                              double(b.velocity.z()),
                              double(b.angularVelocity.x()),
                              double(b.angularVelocity.y()),
                              double(b.angularVelocity.z())};
      writeNpyRow(out, row);
    }
}

void writeParticleCsvHeader(std::ostream& out) {
  out << kParticleCsvHeader << '\n';
}

void writeParticleCsvRows(std::ostream& out, const State& state) {
  char time[pbd::kRealTextCapacity];
  const std::size_t timeLength = std::size_t(pbd::writeReal(time, state.time) - time);
  char row[9 * (pbd::kRealTextCapacity + 1)];  // the time, the index, 6 numbers, commas, newline
  for (std::size_t i = 0; i < state.particles.size(); ++i) {
    const ParticleState& p = state.particles[i];
    char* end = row;
    std::memcpy(end, time, timeLength);
    end += timeLength;
    *end++ = ',';
    end = std::to_chars(end, end + 24, i).ptr;
    for (double v : {double(p.position.x()), double(p.position.y()), double(p.position.z()),
                     double(p.velocity.x()), double(p.velocity.y()), double(p.velocity.z())}) {
      *end++ = ',';
      end = pbd::writeReal(end, v);
    }
    *end++ = '\n';
    out.write(row, std::streamsize(end - row));
  }
}

void writeParticleTrajectoryNpy(std::ostream& out, const std::vector<State>& samples) {
  std::size_t rows = 0;
  for (const State& s : samples)
    rows += s.particles.size();
  writeNpyPreamble(out, rows, 8);
  for (const State& s : samples)
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
      const ParticleState& p = s.particles[i];
      const double row[8] = {s.time,
                             double(i),
                             double(p.position.x()),
                             double(p.position.y()),
                             double(p.position.z()),
                             double(p.velocity.x()),
                             double(p.velocity.y()),
                             double(p.velocity.z())};
      writeNpyRow(out, row);
    }
}

void writeSegmentCsvHeader(std::ostream& out) {
  out << kSegmentCsvHeader << '\n';
}

void writeSegmentCsvRows(std::ostream& out, const State& state) {
  char time[pbd::kRealTextCapacity];
  const std::size_t timeLength = std::size_t(pbd::writeReal(time, state.time) - time);
  char row[10 * (pbd::kRealTextCapacity + 1)];  // the time, the index, 7 numbers, commas, newline
  for (std::size_t i = 0; i < state.segments.size(); ++i) {
    const SegmentState& s = state.segments[i];
    const Quaternion q = s.rotation.w() < 0 ? Quaternion(-s.rotation.coeffs()) : s.rotation;
    char* end = row;
    std::memcpy(end, time, timeLength);
    end += timeLength;
    *end++ = ',';
    end = std::to_chars(end, end + 24, i).ptr;
    for (double v :
         {double(q.w()), double(q.x()), double(q.y()), double(q.z()), double(s.angularVelocity.x()),
          double(s.angularVelocity.y()), double(s.angularVelocity.z())}) {
      *end++ = ',';
      end = pbd::writeReal(end, v);
    }
    *end++ = '\n';
    out.write(row, std::streamsize(end - row));
  }
}

void writeSegmentTrajectoryNpy(std::ostream& out, const std::vector<State>& samples) {
  std::size_t rows = 0;
  for (const State& s : samples)
    rows += s.segments.size();
  writeNpyPreamble(out, rows, 9);
  for (const State& s : samples)
    for (std::size_t i = 0; i < s.segments.size(); ++i) {
      const SegmentState& g = s.segments[i];
      const Quaternion q = g.rotation.w() < 0 ? Quaternion(-g.rotation.coeffs()) : g.rotation;
      const double row[9] = {s.time,
                             double(i),
                             double(q.w()),
                             double(q.x()),
                             double(q.y()),
                             double(q.z()),
                             double(g.angularVelocity.x()),
                             double(g.angularVelocity.y()),
                             double(g.angularVelocity.z())};
      writeNpyRow(out, row);
    }
}

void writeParticleTrajectory(std::ostream& out, const std::vector<State>& samples,
                             TrajectoryFormat format) {
  if (format == TrajectoryFormat::Npy) return writeParticleTrajectoryNpy(out, samples);
  writeParticleCsvHeader(out);
  for (const State& s : samples)
    writeParticleCsvRows(out, s);
}

void writeSegmentTrajectory(std::ostream& out, const std::vector<State>& samples,
                            TrajectoryFormat format) {
  if (format == TrajectoryFormat::Npy) return writeSegmentTrajectoryNpy(out, samples);
  writeSegmentCsvHeader(out);
  for (const State& s : samples)
    writeSegmentCsvRows(out, s);
}

bool hasNpyExtension(const std::string& path) {
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".npy") == 0;
}

Trajectory readTrajectory(const std::string& path) {
  return hasNpyExtension(path) ? readTrajectoryNpy(path) : readTrajectoryCsv(path);
}

const char* trajectoryFormatName(TrajectoryFormat format) {
  return format == TrajectoryFormat::Npy ? "npy" : "csv";
}

}  // namespace pbdval
