#include "trainer/trainer.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "toolkit/content_digest.hpp"
#include "trainer/candidate_comparisons.hpp"
#include "trainer/patch_lanes.hpp"
#include "trainer/separation_selection.hpp"

namespace mdbrief::train {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

LearnedComparisons learnComparisons(const PatchMatrix& patches, const GreedyOptions& options,
                                    SelectionCriterion criterion, const Counterparts& counterparts,
                                    const TrainingProgress& progress, const SeparationOptions& separation,
                                    const StreamingOptions& streaming) {
  if (patches.count == 0) throw std::invalid_argument("training: no patches");
  if (needsCounterparts(criterion) && counterparts.patches.count == 0)
    throw std::invalid_argument("training: selection criterion " + selectionCriterionName(criterion) +
                                " needs counterpart patches");
  const std::vector<ComparisonPair> candidates = candidateComparisons();
  LearnedComparisons out;
  out.candidates = candidates.size();
  out.patches = patches.count;
  out.criterion = criterion;
  out.pairs = counterparts.patches.count;

  auto t0 = std::chrono::steady_clock::now();
  ResponseCounts counts;
  counts.patches = patches.count;
  counts.ones = countResponses(
      patches, candidates,
      [&](size_t done, size_t total) {
        if (progress) progress("evaluate", done, total);
      },
      streaming);
  out.times.evaluateSeconds = secondsSince(t0);

  if (out.pairs > 0) {
    t0 = std::chrono::steady_clock::now();
    counts.pairs = out.pairs;
    counts.flips = countDisagreements(
        patches, counterparts, candidates,
        [&](size_t done, size_t total) {
          if (progress) progress("pairs", done, total);
        },
        streaming);
    out.times.flipSeconds = secondsSince(t0);
  }

  t0 = std::chrono::steady_clock::now();
  const std::vector<size_t> sorted = sortByCriterion(counts, criterion);
  out.times.sortSeconds = secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  GreedyResult greedy;
  if (criterion == SelectionCriterion::Separation) {
    SeparationOptions so = separation;
    so.tests = options.tests;
    so.pool = std::max(options.tests, so.pool);
    greedy.kept = selectBySeparation(
                      patches, counterparts, candidates, counts, sorted, so,
                      [&](size_t kept) {
                        if (progress) progress("greedy", kept, options.tests);
                      },
                      streaming)
                      .kept;
  } else {
    const PatchLanes lanes(PatchRows::of(patches), streaming.chunkWords);
    greedy = selectUncorrelated(
        lanes, candidates, sorted, options,
        [&](size_t kept, int) {
          if (progress) progress("greedy", kept, options.tests);
        },
        streaming);
  }
  out.times.greedySeconds = secondsSince(t0);
  out.passes = greedy.passes;
  out.finalThreshold = greedy.finalThreshold;

  const size_t n = greedy.kept.size();
  for (size_t d : greedy.kept) out.tests.push_back(candidates[d]);
  const ComparisonResponses kept = evaluateComparisons(patches, out.tests, streaming);
  out.mean.resize(n);
  out.maxCorrelation.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    out.mean[i] = static_cast<double>(kept.ones(i)) / patches.count;
    if (out.pairs > 0) out.flipRate.push_back(static_cast<double>(counts.flips[greedy.kept[i]]) / out.pairs);
  }
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    for (size_t j = 0; j < n; ++j)
      if (j != i) out.maxCorrelation[i] = std::max(out.maxCorrelation[i], correlation(kept, i, j));
  });
  return out;
}

ComparisonSetQuality measureComparisonSet(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests) {
  if (tests.size() < 2) throw std::invalid_argument("measureComparisonSet: need at least 2 tests");
  const ComparisonResponses r = evaluateComparisons(patches, tests);
  ComparisonSetQuality q;
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
  return contentDigest(patches.pixels, patches.count * kPatchSize * kPatchSize);
}

}  // namespace mdbrief::train
