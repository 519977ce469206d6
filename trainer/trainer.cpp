#include "trainer/trainer.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "trainer/candidate_tests.hpp"
#include "trainer/separation_selection.hpp"

namespace mdbrief::train {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

LearnedTests learnTests(const PatchMatrix& patches, const GreedyOptions& options, SelectionCriterion criterion,
                        const Counterparts& counterparts, const TrainingProgress& progress,
                        const SeparationOptions& separation) {
  if (patches.count == 0) throw std::invalid_argument("training: no patches");
  if (needsCounterparts(criterion) && counterparts.patches.count == 0)
    throw std::invalid_argument("training: selection criterion " + selectionCriterionName(criterion) +
                                " needs counterpart patches");
  const std::vector<TestPair> candidates = candidateTests();
  LearnedTests out;
  out.candidates = candidates.size();
  out.patches = patches.count;
  out.criterion = criterion;
  out.pairs = counterparts.patches.count;

  auto t0 = std::chrono::steady_clock::now();
  const TestResponses responses =
      evaluateTests(patches, candidates, [&](size_t done, size_t total) {
        if (progress) progress("evaluate", done, total);
      });
  out.responseBytes = responses.bytes();
  out.times.evaluateSeconds = secondsSince(t0);

  std::vector<uint32_t> flips;
  if (out.pairs > 0) {
    t0 = std::chrono::steady_clock::now();
    flips = countDisagreements(patches, counterparts.patches,
                               std::vector<int32_t>(counterparts.of, counterparts.of + out.pairs), candidates,
                               [&](size_t done, size_t total) {
                                 if (progress) progress("pairs", done, total);
                               });
    out.times.flipSeconds = secondsSince(t0);
  }

  t0 = std::chrono::steady_clock::now();
  const std::vector<size_t> sorted = sortByCriterion(responses, criterion, flips, out.pairs);
  out.times.sortSeconds = secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  GreedyResult greedy;
  if (criterion == SelectionCriterion::Separation) {
    SeparationOptions so = separation;
    so.tests = options.tests;
    so.pool = std::max(options.tests, so.pool);
    std::vector<TestPair> poolTests;
    for (size_t i = 0; i < std::min(so.pool, sorted.size()); ++i) poolTests.push_back(candidates[sorted[i]]);
    const TestResponses poolFlips = disagreementBits(
        patches, counterparts.patches, std::vector<int32_t>(counterparts.of, counterparts.of + out.pairs), poolTests);
    greedy.kept = selectBySeparation(responses, sorted, poolFlips, so, [&](size_t kept) {
                    if (progress) progress("greedy", kept, options.tests);
                  }).kept;
  } else {
    greedy = selectUncorrelated(responses, sorted, options, [&](size_t kept, int) {
      if (progress) progress("greedy", kept, options.tests);
    });
  }
  out.times.greedySeconds = secondsSince(t0);
  out.passes = greedy.passes;
  out.finalThreshold = greedy.finalThreshold;

  const size_t n = greedy.kept.size();
  out.tests.reserve(n);
  out.mean.resize(n);
  out.maxCorrelation.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    out.tests.push_back(candidates[greedy.kept[i]]);
    out.mean[i] = static_cast<double>(responses.ones(greedy.kept[i])) / patches.count;
    if (out.pairs > 0) out.flipRate.push_back(static_cast<double>(flips[greedy.kept[i]]) / out.pairs);
  }
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    for (size_t j = 0; j < n; ++j)
      if (j != i)
        out.maxCorrelation[i] =
            std::max(out.maxCorrelation[i], correlation(responses, greedy.kept[i], greedy.kept[j]));
  });
  return out;
}

TestSetQuality measureTestSet(const PatchMatrix& patches, const std::vector<TestPair>& tests) {
  if (tests.size() < 2) throw std::invalid_argument("measureTestSet: need at least 2 tests");
  const TestResponses r = evaluateTests(patches, tests);
  TestSetQuality q;
  const double p = static_cast<double>(r.patches());
  for (size_t d = 0; d < tests.size(); ++d) {
    const double alpha = r.ones(d) / p;
    q.meanVariance += alpha * (1 - alpha);
  }
  q.meanVariance /= tests.size();
  double sum = 0;
  for (size_t a = 0; a < tests.size(); ++a)
    for (size_t b = a + 1; b < tests.size(); ++b) sum += correlation(r, a, b);
  q.meanCorrelation = sum / (tests.size() * (tests.size() - 1) / 2.0);
  return q;
}

std::string patchDigest(const PatchMatrix& patches) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a 64 offset basis
  const size_t n = patches.count * kPatchSize * kPatchSize;
  for (size_t i = 0; i < n; ++i) {
    h ^= patches.pixels[i];
    h *= 1099511628211ull;  // FNV-1a 64 prime
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace mdbrief::train
