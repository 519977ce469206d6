#include "trainer/greedy_selection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "trainer/comparison_response_kernels.hpp"

namespace mdbrief::train {

namespace {

// c < t_c  <=>  |2h - P| < t_c * P, with h the number of differing bits. Comparing integers
// (t_c in thousandths) keeps the decision exact and platform-independent.
struct Threshold {
  int64_t milli;  // t_c * 1000
  int64_t patches;
  bool below(int64_t deviation) const { return deviation * 1000 < milli * patches; }
};

// Each candidate's screening so far: the highest |2h - P| against kept[0, reached). A test
// correlated at one threshold stays so at a looser one only if that maximum still reaches it,
// so a new pass resumes each candidate where it stopped instead of restarting, and skips (does
// not even recompute) the candidates whose maximum already exceeds the threshold.
class ScreeningCache {
 public:
  ScreeningCache(size_t candidates, size_t words, int64_t patches)
      : words_(words), patches_(patches), reached_(candidates, 0), maxDeviation_(candidates, 0),
        popcountXor_(kernels::activeResponseKernels().popcountXor) {}

  bool mayPass(size_t d, const Threshold& t) const { return t.below(maxDeviation_[d]); }

  // Whether candidate d, whose column is `column`, is below the threshold with every kept test
  // before `to` (kept: their columns, one after the other).
  bool uncorrelated(size_t d, const uint64_t* column, const std::vector<uint64_t>& kept, size_t to,
                    const Threshold& t) {
    if (!t.below(maxDeviation_[d])) return false;
    for (size_t k = reached_[d]; k < to; ++k) {
      const auto h = static_cast<int64_t>(popcountXor_(column, kept.data() + k * words_, words_));
      const int64_t dev = std::llabs(2 * h - patches_);
      maxDeviation_[d] = std::max(maxDeviation_[d], dev);
      reached_[d] = static_cast<uint32_t>(k + 1);
      if (!t.below(dev)) return false;
    }
    return true;
  }

 private:
  size_t words_;
  int64_t patches_;
  std::vector<uint32_t> reached_;
  std::vector<int64_t> maxDeviation_;
  size_t (*popcountXor_)(const uint64_t*, const uint64_t*, size_t);
};

}  // namespace

std::vector<size_t> sortByVariance(const ResponseCounts& counts) {
  const size_t n = counts.ones.size();
  const uint64_t p = counts.patches;
  // alpha(1 - alpha) * P^2 = ones * (P - ones): an exact integer key.
  std::vector<uint64_t> key(n);
  tbb::parallel_for(size_t(0), n, [&](size_t d) {
    const uint64_t ones = counts.ones[d];
    key[d] = ones * (p - ones);
  });
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  tbb::parallel_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return key[a] != key[b] ? key[a] > key[b] : a < b;
  });
  return order;
}

bool needsCounterparts(SelectionCriterion criterion) { return criterion != SelectionCriterion::Paper; }

std::vector<size_t> sortByCriterion(const ResponseCounts& counts, SelectionCriterion criterion) {
  if (criterion == SelectionCriterion::Paper) return sortByVariance(counts);
  const size_t n = counts.ones.size();
  if (counts.pairs == 0 || counts.flips.size() != n)
    throw std::invalid_argument("selection criterion " + selectionCriterionName(criterion) +
                                " needs the flip counts of matching pairs");
  const double p = static_cast<double>(counts.patches), q = static_cast<double>(counts.pairs);
  // IEEE double keys from the same operations everywhere: deterministic across platforms.
  std::vector<double> key(n);
  tbb::parallel_for(size_t(0), n, [&](size_t d) {
    const double alpha = counts.ones[d] / p;
    const double distinct = 2 * alpha * (1 - alpha);
    key[d] = distinct - counts.flips[d] / q;
  });
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  tbb::parallel_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return key[a] != key[b] ? key[a] > key[b] : a < b;
  });
  return order;
}

double correlation(const ComparisonResponses& responses, size_t a, size_t b) {
  const double p = static_cast<double>(responses.patches());
  return std::fabs(2.0 / p * static_cast<double>(responses.differences(a, b)) - 1.0);
}

GreedyResult selectUncorrelated(const PatchLanes& patches, const std::vector<ComparisonPair>& candidates,
                                const std::vector<size_t>& sorted, const GreedyOptions& options,
                                const std::function<void(size_t, int)>& progress,
                                const StreamingOptions& streaming) {
  if (options.startThreshold <= 0 || options.thresholdStep <= 0)
    throw std::invalid_argument("greedy selection: thresholds must be positive");
  if (sorted.size() < options.tests)
    throw std::invalid_argument("greedy selection: " + std::to_string(options.tests) +
                                " tests requested but only " + std::to_string(sorted.size()) +
                                " candidates");
  if (streaming.candidateBatch == 0) throw std::invalid_argument("greedy selection: candidateBatch must be positive");
  for (size_t d : sorted)
    if (d >= candidates.size())
      throw std::invalid_argument("greedy selection: candidate " + std::to_string(d) + " does not exist");
  const std::vector<PixelPair> pixels = pixelPairsOf(candidates);
  const size_t words = patches.words(), batch = streaming.candidateBatch;
  GreedyResult result;
  std::vector<char> taken(candidates.size(), 0);
  ScreeningCache cache(candidates.size(), words, static_cast<int64_t>(patches.rows()));
  std::vector<uint64_t> keptColumns;  // the kept tests' columns, in order
  keptColumns.reserve(options.tests * words);
  const int64_t start = std::llround(options.startThreshold * 1000);
  const int64_t step = std::llround(options.thresholdStep * 1000);
  // The candidates of a batch still to screen, and their recomputed columns.
  std::vector<size_t> open;
  std::vector<PixelPair> openPixels;
  std::vector<uint64_t> columns(std::min(batch, sorted.size()) * words);
  std::vector<char> survives(batch);

  for (int pass = 0; result.kept.size() < options.tests; ++pass) {
    const Threshold t{start + pass * step, static_cast<int64_t>(patches.rows())};
    result.passes = pass + 1;
    result.finalThreshold = t.milli / 1000.0;
    // Above 1 every remaining test passes (c <= 1), so the walk always ends.
    for (size_t b0 = 0; b0 < sorted.size() && result.kept.size() < options.tests; b0 += batch) {
      const size_t b1 = std::min(sorted.size(), b0 + batch);
      const size_t keptBefore = result.kept.size();
      open.clear();
      openPixels.clear();
      for (size_t i = b0; i < b1; ++i)
        if (!taken[sorted[i]] && cache.mayPass(sorted[i], t)) {
          open.push_back(sorted[i]);
          openPixels.push_back(pixels[sorted[i]]);
        }
      evaluateColumns(patches, openPixels.data(), open.size(), columns.data());
      tbb::parallel_for(size_t(0), open.size(), [&](size_t z) {
        survives[z] = cache.uncorrelated(open[z], columns.data() + z * words, keptColumns, keptBefore, t);
      });
      for (size_t z = 0; z < open.size() && result.kept.size() < options.tests; ++z) {
        const uint64_t* column = columns.data() + z * words;
        if (!survives[z] || !cache.uncorrelated(open[z], column, keptColumns, result.kept.size(), t)) continue;
        taken[open[z]] = 1;
        result.kept.push_back(open[z]);
        keptColumns.insert(keptColumns.end(), column, column + words);
      }
      if (progress) progress(result.kept.size(), result.passes);
    }
  }
  return result;
}

}  // namespace mdbrief::train
