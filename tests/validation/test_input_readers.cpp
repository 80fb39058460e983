// validation's readers on hostile input: the trajectory CSV reader and results.json metadata.
// Each case was accepted, or escaped as the wrong exception, before (issue 9).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "validation/io/results.h"
#include "validation/io/trajectory.h"

namespace pbdval {
namespace {

const std::string kHeader = std::string(kTrajectoryCsvHeader) + "\n";
const std::string kRow = "0.5,1,0,1,2,1,0,0,0,0,0,0,0,0,0\n";

template <class Exception, class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const Exception& e) {
    return e.what();
  }
  return "(no error of the expected type)";
}

TEST(TrajectoryCsv, ReadsWhatWriteCsvRowsWrites) {
  State state;
  state.time = 0.25;
  BodyState body;
  body.id = 7;
  body.position = Vector3(1, -2, 3);
  state.bodies = {body};
  std::ostringstream csv;
  writeCsvHeader(csv);
  writeCsvRows(csv, state);
  const Trajectory t = parseTrajectoryCsv(csv.str(), "t.csv");
  ASSERT_EQ(t.samples.size(), 1u);
  EXPECT_EQ(t.samples[0].bodies.at(0).id, 7);
  EXPECT_EQ(t.samples[0].bodies.at(0).position, Vector3(1, -2, 3));  // exact: shortest round trip
}

TEST(TrajectoryCsv, ARowWriterWritesEachSampleAsFormattingEveryNumberAloneWould) {
  // CsvRowWriter reuses a column's text when its number is bit for bit the previous row's:
  // the bytes must be those of every number formatted on its own (pbd::formatReal, the
  // shortest round trip), through repeats, a change of sign of zero, NaN and a change in the
  // number of bodies.
  const auto expectedRows = [](const State& s) {
    std::string rows;
    for (const BodyState& b : s.bodies) {
      rows += formatNumber(s.time) + "," + std::to_string(b.id);
      for (double v :
           {b.position.x(), b.position.y(), b.position.z(), b.rotation.w(), b.rotation.x(),
            b.rotation.y(), b.rotation.z(), b.velocity.x(), b.velocity.y(), b.velocity.z(),
            b.angularVelocity.x(), b.angularVelocity.y(), b.angularVelocity.z()})
        rows += "," + formatNumber(v);
      rows += "\n";
    }
    return rows;
  };
  std::vector<State> samples(5);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    State& s = samples[k];
    s.time = 0.1 * double(k);
    BodyState ground;  // static: every column repeats
    ground.id = 0;
    ground.position = Vector3(0, -0.5, 0);
    BodyState moving;
    moving.id = 4;
    moving.position = Vector3(1.0 / double(k + 3), 2.0, k == 2 ? 2.0 : 1.0 / 3);
    moving.rotation = Quaternion(1, 0, 0, 0);
    moving.velocity = Vector3(k % 2 == 0 ? 0.0 : -0.0, k == 3 ? std::nan("") : 0.25, 1e-300);
    moving.angularVelocity = Vector3(0, 0, double(k));
    s.bodies = {ground, moving};
    if (k == 4) s.bodies.pop_back();  // the writer starts its columns again
  }
  CsvRowWriter writer;
  std::ostringstream written;
  std::string expected;
  for (const State& s : samples) {
    writer.write(written, s);
    expected += expectedRows(s);
  }
  EXPECT_EQ(written.str(), expected);
  EXPECT_NE(expected.find(",-0,"), std::string::npos);  // the sign of zero is in the text
}

TEST(TrajectoryNpy, ReadsBackExactlyWhatWriteTrajectoryNpyWrites) {
  // Two samples of two bodies with values no short decimal holds, a quaternion with w < 0
  // (written with w ≥ 0, as the CSV writes it) and a non-finite state (a diverged run's last
  // sample is data).
  std::vector<State> samples(2);
  for (std::size_t k = 0; k < 2; ++k) {
    samples[k].time = 0.1 * double(k + 1) / 3;
    for (int id : {3, 9}) {
      BodyState b;
      b.id = id;
      b.position = Vector3(1.0 / 3, -2.0 / 7, double(id) + 1e-17);
      b.rotation = Quaternion(-0.5, 0.5, -0.5, 0.5);
      b.velocity = Vector3(std::nextafter(1.0, 2.0), -0.0, 1e-300);
      b.angularVelocity = Vector3(0.1, 0.2, k == 1 ? std::nan("") : 0.3);
      samples[k].bodies.push_back(b);
    }
  }
  std::ostringstream npy;
  writeTrajectoryNpy(npy, samples);
  // The data starts at a multiple of 64 bytes (NPY 1.0) and holds 4 rows × 15 doubles.
  EXPECT_EQ((npy.str().size() - 4 * 15 * 8) % 64, 0u);
  const Trajectory t = parseTrajectoryNpy(npy.str(), "t.npy");
  ASSERT_EQ(t.samples.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(t.samples[k].time, samples[k].time);
    ASSERT_EQ(t.samples[k].bodies.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      const BodyState& read = t.samples[k].bodies[i];
      const BodyState& written = samples[k].bodies[i];
      EXPECT_EQ(read.id, written.id);
      EXPECT_EQ(read.position, written.position);
      EXPECT_EQ(read.rotation.coeffs(), -written.rotation.coeffs());  // w ≥ 0
      EXPECT_EQ(read.velocity, written.velocity);
      EXPECT_EQ(std::signbit(read.velocity.y()), true);  // −0 kept: the bits, not text
      EXPECT_EQ(read.angularVelocity.head<2>(), written.angularVelocity.head<2>());
    }
  }
  EXPECT_TRUE(std::isnan(t.samples[1].bodies[0].angularVelocity.z()));
}

TEST(TrajectoryNpy, AnEmptyRunIsAValidFileOfNoRows) {
  std::ostringstream npy;
  writeTrajectoryNpy(npy, {});
  EXPECT_TRUE(parseTrajectoryNpy(npy.str(), "t.npy").samples.empty());
  EXPECT_TRUE(hasNpyExtension("out/trajectories/a/pbd-pbd.npy"));
  EXPECT_FALSE(hasNpyExtension("out/trajectories/a/pbd-pbd.csv"));
  EXPECT_FALSE(hasNpyExtension("npy"));
}

TEST(TrajectoryCsv, NonFiniteTimesAndBadIdsAreLocatedErrors) {
  EXPECT_EQ(parseTrajectoryCsv(kHeader + kRow, "t.csv").samples.size(), 1u);
  // A non-finite state is data (a diverged run's last sample), read as it is; the runner
  // reports the run diverged.
  const Trajectory diverged =
      parseTrajectoryCsv(kHeader + kRow + "0.6,1,nan,1,2,1,0,0,0,0,0,0,0,0,0\n", "t.csv");
  ASSERT_EQ(diverged.samples.size(), 2u);
  EXPECT_TRUE(std::isnan(diverged.samples[1].bodies.at(0).position.x()));
  EXPECT_NE(errorOf<std::runtime_error>([&] {
              parseTrajectoryCsv(kHeader + "inf,1,0,1,2,1,0,0,0,0,0,0,0,0,0\n", "t.csv");
            }).find("line 2: field 1 is not a finite number"),
            std::string::npos);
  // 1e300 as an int is undefined behaviour; 1.5 is not an id.
  for (const char* id : {"1e300", "1.5", "-3e9"})
    EXPECT_NE(errorOf<std::runtime_error>([&] {
                parseTrajectoryCsv(
                    kHeader + "0," + std::string(id) + ",0,1,2,1,0,0,0,0,0,0,0,0,0\n", "t.csv");
              }).find("line 2: the body id (field 2) is not an integer"),
              std::string::npos)
        << id;
  EXPECT_NE(errorOf<std::runtime_error>([] {
              readTrajectoryCsv("/dev/null");
            }).find("/dev/null: the trajectory is a character device, not a regular file"),
            std::string::npos);
}

TEST(ResultsReader, MetadataOfTheWrongTypeIsALocatedError) {
  const std::string head = R"({"schema": "pbdval-results", "schemaVersion": )" +
                           std::to_string(kResultsSchemaVersion) + R"(, "cases": {}, "runs": [], )";
  EXPECT_NE(errorOf<std::invalid_argument>([&] {
              parseResultsText(head + R"("metadata": 5})", "r.json");
            }).find("r.json: metadata: expected an object, got 5"),
            std::string::npos);
  EXPECT_NE(errorOf<std::invalid_argument>([&] {
              parseResultsText(head + R"("metadata": {"machine": {"cores": "x"}}})", "r.json");
            }).find("metadata.machine.cores: expected an integer"),
            std::string::npos);
  EXPECT_NE(errorOf<std::invalid_argument>([&] {
              parseResultsText(head + R"("metadata": {"pbdval": {"commit": 3}}})", "r.json");
            }).find("metadata.pbdval.commit: expected a string, got 3"),
            std::string::npos);
}

}  // namespace
}  // namespace pbdval
