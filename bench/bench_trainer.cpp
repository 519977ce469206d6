// Trainer stages on synthetic patches (needs mdbrief_trainer_lib): candidate generation,
// bit-packed response evaluation of all 377,650 candidates, the flip counts on matching pairs,
// the variance sort with the greedy selection, and the separation forward selection. The full 20,000-patch run is timed by mdbrief-train itself (docs/training.md).
#include <algorithm>
#include <random>

#include <benchmark/benchmark.h>

#include "trainer/candidate_tests.hpp"
#include "trainer/greedy_selection.hpp"
#include "trainer/separation_selection.hpp"
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

// Counterparts: the same patches with a little more noise (pairs j -> j).
struct Pairs {
  std::vector<uint8_t> reference, counterpart;
  std::vector<int32_t> of;
  explicit Pairs(size_t count) : reference(syntheticPatches(count)), counterpart(reference), of(count) {
    std::mt19937 rng(2);
    for (auto& v : counterpart) v = static_cast<uint8_t>(std::min<uint32_t>(255, v + rng() % 12));
    for (size_t j = 0; j < count; ++j) of[j] = static_cast<int32_t>(j);
  }
};

void BM_CountDisagreementsAllCandidates(benchmark::State& state) {
  const size_t pairs = static_cast<size_t>(state.range(0));
  const Pairs p(pairs);
  const auto tests = candidateTests();
  for (auto _ : state)
    benchmark::DoNotOptimize(countDisagreements({p.reference.data(), pairs}, {p.counterpart.data(), pairs}, p.of, tests));
}
BENCHMARK(BM_CountDisagreementsAllCandidates)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// 512 tests from a pool of 16,384 on 2,048 patches and pairs (the shipped pool is 131,072 on
// 8,192 samples: about 20x this).
void BM_SeparationSelection512(benchmark::State& state) {
  const size_t n = 2048;
  const Pairs p(n);
  const auto candidates = candidateTests();
  const TestResponses r = evaluateTests({p.reference.data(), n}, candidates);
  const auto flips = countDisagreements({p.reference.data(), n}, {p.counterpart.data(), n}, p.of, candidates);
  const auto order = sortByCriterion(r, SelectionCriterion::Stability, flips, n);
  SeparationOptions o;
  o.pool = 16384;
  std::vector<mdbrief::TestPair> poolTests;
  for (size_t i = 0; i < o.pool; ++i) poolTests.push_back(candidates[order[i]]);
  const TestResponses poolFlips = disagreementBits({p.reference.data(), n}, {p.counterpart.data(), n}, p.of, poolTests);
  for (auto _ : state) benchmark::DoNotOptimize(selectBySeparation(r, order, poolFlips, o));
}
BENCHMARK(BM_SeparationSelection512)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
