// The cost of writing one number as shortest round-trip text: std::to_chars(double) against
// pbd::writeShortestDouble (the same bytes), on a trajectory's usual values (uniform in
// [-10, 10]) and on random bit patterns (every exponent). Instructions per number:
//
//   valgrind --tool=callgrind --callgrind-out-file=/tmp/cg.out
//       build/release/bench/pbdval_bench_number_text --benchmark_min_time=0.05
//   callgrind_annotate --inclusive=yes /tmp/cg.out | grep -E 'to_chars|writeShortestDouble'
//
// (a function's inclusive count over its calls, `callgrind_annotate --tree=caller`).
#include <benchmark/benchmark.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "pbd/io/shortest_double.h"

namespace {

constexpr std::size_t kNumbers = 4096;

std::vector<double> trajectoryValues() {
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0);
  std::vector<double> values(kNumbers);
  for (double& value : values)
    value = uniform(random);
  return values;
}

std::vector<double> randomBitPatterns() {
  std::mt19937_64 random(2);
  std::vector<double> values;
  while (values.size() < kNumbers) {
    const std::uint64_t bits = random();
    double value = 0;
    std::memcpy(&value, &bits, sizeof(value));
    if (std::isfinite(value)) values.push_back(value);
  }
  return values;
}

template <typename Write>
void writeAll(benchmark::State& state, const std::vector<double>& values, Write write) {
  char text[64];
  std::size_t bytes = 0;
  for (auto _ : state) {
    for (const double value : values) {
      char* const end = write(text, value);
      bytes += static_cast<std::size_t>(end - text);
      benchmark::DoNotOptimize(text);
    }
  }
  benchmark::DoNotOptimize(bytes);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * values.size()));
}

char* withToChars(char* text, double value) {
  return std::to_chars(text, text + 64, value).ptr;
}
char* withShortestDouble(char* text, double value) {
  return pbd::writeShortestDouble(text, value);
}

void BM_ToChars_Trajectory(benchmark::State& state) {
  writeAll(state, trajectoryValues(), withToChars);
}
void BM_ShortestDouble_Trajectory(benchmark::State& state) {
  writeAll(state, trajectoryValues(), withShortestDouble);
}
void BM_ToChars_RandomBits(benchmark::State& state) {
  writeAll(state, randomBitPatterns(), withToChars);
}
void BM_ShortestDouble_RandomBits(benchmark::State& state) {
  writeAll(state, randomBitPatterns(), withShortestDouble);
}

BENCHMARK(BM_ToChars_Trajectory);
BENCHMARK(BM_ShortestDouble_Trajectory);
BENCHMARK(BM_ToChars_RandomBits);
BENCHMARK(BM_ShortestDouble_RandomBits);

}  // namespace

BENCHMARK_MAIN();
