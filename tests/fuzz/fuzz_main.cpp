// The libFuzzer entry point of one target; PBDVAL_FUZZ_TARGET names its function
// (tests/fuzz/CMakeLists.txt builds one program per target).
#include "fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pbdval::fuzz::PBDVAL_FUZZ_TARGET(data, size);
  return 0;
}
