// Replays every file of tests/fuzz/corpus/<target>/ through its fuzz target, in the normal
// build: the inputs the fuzzer found (and the seeds) stay fixed forever. A target aborts or
// throws on a regression, which fails this test.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz_targets.h"

namespace pbdval::fuzz {
namespace {

namespace fs = std::filesystem;

}  // namespace

// Test names and failure messages show the target's name (found by GoogleTest through ADL).
void PrintTo(const NamedTarget& target, std::ostream* out);
void PrintTo(const NamedTarget& target, std::ostream* out) {
  *out << target.name;
}

namespace {

class CorpusReplay : public ::testing::TestWithParam<NamedTarget> {};

TEST_P(CorpusReplay, EveryCorpusFileIsHandled) {
  const fs::path folder = fs::path(PBDVAL_FUZZ_CORPUS_DIR) / GetParam().name;
  ASSERT_TRUE(fs::is_directory(folder)) << folder << ": every target has a seed corpus";
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(
        GetParam().run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    ++files;
  }
  EXPECT_GT(files, 0u) << folder;
}

INSTANTIATE_TEST_SUITE_P(Fuzz, CorpusReplay, ::testing::ValuesIn(allTargets()),
                         [](const ::testing::TestParamInfo<NamedTarget>& param) {
                           return std::string(param.param.name);
                         });

}  // namespace
}  // namespace pbdval::fuzz
