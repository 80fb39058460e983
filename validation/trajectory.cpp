#include "validation/trajectory.h"

#include <charconv>
#include <cmath>
#include <fstream>
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
  // The time exactly as the engine's clock has it (an accumulated clock reads 0.30000000000000004,
  // not 0.3): metrics computed from a CSV then equal the runner's to the bit (docs/python.md).
  const std::string time = formatNumber(state.time);
  for (const BodyState& b : state.bodies) {
    const Quaternion q = b.rotation.w() < 0 ? Quaternion(-b.rotation.coeffs()) : b.rotation;
    out << time << ',' << b.id;
    for (double v :
         {double(b.position.x()), double(b.position.y()), double(b.position.z()), double(q.w()),
          double(q.x()), double(q.y()), double(q.z()), double(b.velocity.x()),
          double(b.velocity.y()), double(b.velocity.z()), double(b.angularVelocity.x()),
          double(b.angularVelocity.y()), double(b.angularVelocity.z())})
      out << ',' << formatNumber(v);
    out << '\n';
  }
}

Trajectory readTrajectoryCsv(const std::string& path) {
  const std::string problem = pbd::inputFileProblem(path, "trajectory");
  if (!problem.empty()) throw std::runtime_error(pbd::printableText(path + ": " + problem));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(pbd::printableText(path + ": cannot be read"));
  std::stringstream text;
  text << in.rdbuf();
  return parseTrajectoryCsv(text.str(), path);
}

Trajectory parseTrajectoryCsv(const std::string& text, const std::string& sourceName) {
  const std::string path = pbd::printableText(sourceName);
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kTrajectoryCsvHeader)
    throw std::runtime_error(path + ": line 1: expected the header '" +
                             std::string(kTrajectoryCsvHeader) + "'");
  Trajectory trajectory;
  int lineNumber = 1;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.empty()) continue;
    double fields[15];
    const char* p = line.data();
    const char* end = line.data() + line.size();
    for (int f = 0; f < 15; ++f) {
      const auto r = std::from_chars(p, end, fields[f]);
      if (r.ec != std::errc() || (f < 14 && (r.ptr == end || *r.ptr != ',')) ||
          (f == 14 && r.ptr != end))
        throw std::runtime_error(path + ": line " + std::to_string(lineNumber) +
                                 ": expected 15 comma-separated numbers");
      // The time and the id must be finite; a state may not be: a diverged run's last sample
      // holds its NaN or inf (the runner then reports the run diverged).
      if (f < 2 && !std::isfinite(fields[f]))
        throw std::runtime_error(path + ": line " + std::to_string(lineNumber) + ": field " +
                                 std::to_string(f + 1) + " is not a finite number");
      p = r.ptr + 1;
    }
    if (fields[1] != std::floor(fields[1]) || std::abs(fields[1]) > 2147483647.0)
      throw std::runtime_error(path + ": line " + std::to_string(lineNumber) +
                               ": the body id (field 2) is not an integer");
    if (trajectory.samples.empty() || trajectory.samples.back().time != fields[0]) {
      trajectory.samples.emplace_back();
      trajectory.samples.back().time = fields[0];
    }
    BodyState b;
    b.id = static_cast<int>(fields[1]);
    b.position = Vector3(Real(fields[2]), Real(fields[3]), Real(fields[4]));
    b.rotation = Quaternion(Real(fields[5]), Real(fields[6]), Real(fields[7]), Real(fields[8]));
    b.velocity = Vector3(Real(fields[9]), Real(fields[10]), Real(fields[11]));
    b.angularVelocity = Vector3(Real(fields[12]), Real(fields[13]), Real(fields[14]));
    trajectory.samples.back().bodies.push_back(b);
  }
  return trajectory;
}

}  // namespace pbdval
