// The trajectory readers' targets (CSV and NPY): validation/io/trajectory.cpp needs only the pbd
// library, so its fuzz program is built from it directly, without the engines
// (tests/fuzz/CMakeLists.txt).
#include <stdexcept>

#include "fuzz_support.h"
#include "fuzz_targets.h"
#include "validation/io/trajectory.h"

namespace pbdval::fuzz {

void trajectoryTarget(const std::uint8_t* data, std::size_t size) {
  try {
    (void)parseTrajectoryCsv(text(data, size), "trajectory.csv");
  } catch (const std::runtime_error& e) {
    expectPrintable(e.what());
  }
}

void trajectoryNpyTarget(const std::uint8_t* data, std::size_t size) {
  try {
    (void)parseTrajectoryNpy(std::string(reinterpret_cast<const char*>(data), size),
                             "trajectory.npy");
  } catch (const std::runtime_error& e) {
    expectPrintable(e.what());
  }
}

}  // namespace pbdval::fuzz
