// Trainer stages on synthetic patches (needs mdbrief_trainer_lib): candidate generation,
// bit-packed response evaluation of all 377,650 candidates, the variance sort and the greedy
// selection. The full 20,000-patch run is timed by mdbrief-train itself (docs/training.md).
#include <random>

#include <benchmark/benchmark.h>

#include "trainer/candidate_tests.hpp"
#include "trainer/greedy_selection.hpp"
#include "trainer/test_responses.hpp"

namespace {

using namespace mdbrief::train;

// Smooth random patches: structured enough that variances and correlations differ.
std::vector<uint8_t> syntheticPatches(size_t count) {
  std::mt19937 rng(1);
  std::vector<uint8_t> px(count * 1024);
  for (size_t p = 0; p < count; ++p) {
    const int gx = static_cast<int>(rng() % 9) - 4, gy = static_cast<int>(rng() % 9) - 4;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x)
        px[p * 1024 + y * 32 + x] = static_cast<uint8_t>(128 + gx * (x - 16) + gy * (y - 16) + rng() % 16);
  }
  return px;
}

void BM_CandidateTests(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(candidateTests());
}
BENCHMARK(BM_CandidateTests)->Unit(benchmark::kMillisecond);

void BM_EvaluateAllCandidates(benchmark::State& state) {
  const size_t patches = static_cast<size_t>(state.range(0));
  const auto px = syntheticPatches(patches);
  const auto tests = candidateTests();
  for (auto _ : state) benchmark::DoNotOptimize(evaluateTests({px.data(), patches}, tests));
  state.counters["tests_x_patches/s"] = benchmark::Counter(
      double(tests.size()) * patches, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_EvaluateAllCandidates)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SortAndGreedy512(benchmark::State& state) {
  const size_t patches = 2048;
  const auto px = syntheticPatches(patches);
  const TestResponses r = evaluateTests({px.data(), patches}, candidateTests());
  for (auto _ : state) {
    const auto sorted = sortByVariance(r);
    benchmark::DoNotOptimize(selectUncorrelated(r, sorted, GreedyOptions{}));
  }
}
BENCHMARK(BM_SortAndGreedy512)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
