// Trainer stages on synthetic patches (needs mdbrief_trainer_lib): candidate generation,
// the streamed response counts of all 377,650 candidates, the flip counts on matching pairs,
// the variance sort with the greedy selection (recomputing the columns it screens), and the
// separation forward selection. The full 20,000-patch run is timed by mdbrief-train itself (docs/training.md).
#include <algorithm>
#include <random>

#include <benchmark/benchmark.h>

#include "trainer/candidate_comparisons.hpp"
#include "trainer/comparison_responses.hpp"
#include "trainer/greedy_selection.hpp"
#include "trainer/separation_selection.hpp"

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

void BM_CandidateComparisons(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(candidateComparisons());
}
BENCHMARK(BM_CandidateComparisons)->Unit(benchmark::kMillisecond);

void BM_CountAllCandidates(benchmark::State& state) {
  const size_t patches = static_cast<size_t>(state.range(0));
  const auto px = syntheticPatches(patches);
  const auto tests = candidateComparisons();
  for (auto _ : state) benchmark::DoNotOptimize(countResponses({px.data(), patches}, tests));
  state.counters["tests_x_patches/s"] = benchmark::Counter(
      double(tests.size()) * patches, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_CountAllCandidates)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SortAndGreedy512(benchmark::State& state) {
  const size_t patches = 2048;
  const auto px = syntheticPatches(patches);
  const auto candidates = candidateComparisons();
  const ResponseCounts counts{patches, countResponses({px.data(), patches}, candidates), 0, {}};
  const PatchLanes lanes(PatchRows::of({px.data(), patches}), StreamingOptions{}.chunkWords);
  for (auto _ : state) {
    const auto sorted = sortByVariance(counts);
    benchmark::DoNotOptimize(selectUncorrelated(lanes, candidates, sorted, GreedyOptions{}));
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
  Counterparts counterparts() const { return {{counterpart.data(), of.size()}, of.data()}; }
};

void BM_CountDisagreementsAllCandidates(benchmark::State& state) {
  const size_t pairs = static_cast<size_t>(state.range(0));
  const Pairs p(pairs);
  const auto tests = candidateComparisons();
  for (auto _ : state)
    benchmark::DoNotOptimize(countDisagreements({p.reference.data(), pairs}, p.counterparts(), tests));
}
BENCHMARK(BM_CountDisagreementsAllCandidates)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime();

// 512 tests from a pool of 16,384 on 2,048 patches and pairs (the shipped pool is 131,072 on
// 8,192 samples: about 20x this).
void BM_SeparationSelection512(benchmark::State& state) {
  const size_t n = 2048;
  const Pairs p(n);
  const auto candidates = candidateComparisons();
  const ResponseCounts counts{n, countResponses({p.reference.data(), n}, candidates), n,
                              countDisagreements({p.reference.data(), n}, p.counterparts(), candidates)};
  const auto order = sortByCriterion(counts, SelectionCriterion::Stability);
  SeparationOptions o;
  o.pool = 16384;
  for (auto _ : state)
    benchmark::DoNotOptimize(
        selectBySeparation({p.reference.data(), n}, p.counterparts(), candidates, counts, order, o));
}
BENCHMARK(BM_SeparationSelection512)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
