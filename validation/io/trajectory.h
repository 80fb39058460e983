// Trajectories: the states sampled during a run, and their CSV form.
//
// CSV (docs/cli.md#csv): header `t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz`, one row per rigid
// body per sample, bodies in scene order. x,y,z: centre of mass (world); q: the body's scene
// frame → world (w ≥ 0); v, w: linear and angular velocity (world). Numbers are written in
// the shortest form that reads back to the same double, so a CSV round-trips bit for bit.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "adapters/engine.h"

namespace pbdval {

/// How the runner writes trajectories (`pbdval run --trajectory-format`).
enum class TrajectoryFormat { Csv, Npy };

struct Trajectory {
  std::vector<State> samples;
};

inline constexpr const char* kTrajectoryCsvHeader = "t,id,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";
/// Room one number of a trajectory CSV takes at most (pbd::kRealTextCapacity).
inline constexpr std::size_t kCsvNumberCapacity = 32;

/// Writes the header.
void writeCsvHeader(std::ostream& out);
/// Writes the rows of one sample.
void writeCsvRows(std::ostream& out, const State& state);

/// writeCsvRows for the samples of one trajectory, in order, the same bytes: a number equal (bit
/// for bit) to the one in the same column of the body's previous row reuses that row's text
/// instead of formatting it again (a static body's 13 columns, a planar motion's zero
/// components; formatting is most of a CSV trajectory's cost, docs/benchmarks.md).
class CsvRowWriter {
 public:
  void write(std::ostream& out, const State& state);

 private:
  /// One column of one body: the last number written there and its text.
  struct Column {
    std::uint64_t bits = 0;
    unsigned char length = 0;  ///< 0: nothing written yet
    char text[kCsvNumberCapacity];
  };
  std::vector<Column> columns_;  ///< 13 per body, bodies in state order
};
/// Reads a trajectory CSV (bodies only). Throws std::runtime_error naming the file and line.
Trajectory readTrajectoryCsv(const std::string& path);
/// The same on the file's text; `sourceName` names it in messages.
Trajectory parseTrajectoryCsv(const std::string& text, const std::string& sourceName);

/// Reads a trajectory as NPY (the binary form external engines may write instead of the CSV):
/// a little-endian float64 array of shape (rows, 15), C order, rows as the CSV's lines (time,
/// id, x y z, qw qx qy qz, vx vy vz, wx wy wz). Throws std::runtime_error naming the file, the
/// row, and what was expected.
Trajectory readTrajectoryNpy(const std::string& path);
/// The same on the file's bytes; `sourceName` names it in messages.
Trajectory parseTrajectoryNpy(const std::string& bytes, const std::string& sourceName);

/// Writes `samples` (bodies only) as NPY: little-endian float64, shape (rows, 15), the CSV's
/// rows and columns (quaternions with w ≥ 0, as in the CSV), exactly the values (no text
/// conversion), readable by readTrajectoryNpy and numpy.load.
void writeTrajectoryNpy(std::ostream& out, const std::vector<State>& samples);

/// Particle trajectories (`pbdval simulate --particles FILE`): header
/// `t,index,x,y,z,vx,vy,vz`, one row per particle per sample, particles in scene order (index:
/// the particle's place in it: triangle models', then tet models' vertices, as the loader
/// appends them); the numbers as in the body CSV. NPY: float64, shape (rows, 8), the same
/// columns.
inline constexpr const char* kParticleCsvHeader = "t,index,x,y,z,vx,vy,vz";
void writeParticleCsvHeader(std::ostream& out);
void writeParticleCsvRows(std::ostream& out, const State& state);
void writeParticleTrajectoryNpy(std::ostream& out, const std::vector<State>& samples);
/// The particle table of `samples`: CSV (header and rows) or NPY.
void writeParticleTrajectory(std::ostream& out, const std::vector<State>& samples,
                             TrajectoryFormat format);
/// Reads a particle trajectory (what `pbdval simulate --particles` and external engines write):
/// samples with their time and particles only (no bodies). Every sample must list its particles
/// in order from index 0. Throws std::runtime_error naming the file, the line or row, and what
/// was expected.
Trajectory parseParticleTrajectoryCsv(const std::string& text, const std::string& sourceName);
Trajectory parseParticleTrajectoryNpy(const std::string& bytes, const std::string& sourceName);
/// By the file's extension: ".npy" as NPY, anything else as CSV.
Trajectory readParticleTrajectory(const std::string& path);

/// Rod segment trajectories (`pbdval simulate --segments FILE`): header
/// `t,index,qw,qx,qy,qz,wx,wy,wz`, one row per Cosserat-rod segment per sample, segments in the
/// order of State::segments (line models in scene order); q: the segment's director frame →
/// world (w ≥ 0, as the body CSV), w: its angular velocity (world); the numbers as in the body
/// CSV. NPY: float64, shape (rows, 9), the same columns.
inline constexpr const char* kSegmentCsvHeader = "t,index,qw,qx,qy,qz,wx,wy,wz";
void writeSegmentCsvHeader(std::ostream& out);
void writeSegmentCsvRows(std::ostream& out, const State& state);
void writeSegmentTrajectoryNpy(std::ostream& out, const std::vector<State>& samples);
/// The segment table of `samples`: CSV (header and rows) or NPY.
void writeSegmentTrajectory(std::ostream& out, const std::vector<State>& samples,
                            TrajectoryFormat format);
/// Reads a segment trajectory: samples with their time and segments only. Every sample must
/// list its segments in order from index 0. Throws std::runtime_error naming the file, the line
/// or row, and what was expected.
Trajectory parseSegmentTrajectoryCsv(const std::string& text, const std::string& sourceName);
Trajectory parseSegmentTrajectoryNpy(const std::string& bytes, const std::string& sourceName);
/// By the file's extension: ".npy" as NPY, anything else as CSV.
Trajectory readSegmentTrajectory(const std::string& path);

/// Whether `path` names an NPY trajectory (ends in ".npy"); every other name is a CSV.
bool hasNpyExtension(const std::string& path);

/// Reads a trajectory file by its extension: ".npy" as NPY, anything else as CSV.
Trajectory readTrajectory(const std::string& path);

/// "csv" or "npy" (the file extension).
const char* trajectoryFormatName(TrajectoryFormat format);

/// The shortest decimal text that reads back to `value` exactly.
std::string formatNumber(double value);

}  // namespace pbdval
