#include "trainer/greedy_selection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace mdbrief::train {

namespace {

// Candidates screened in parallel between two sequential decisions.
constexpr size_t kScreenBatch = 2048;

// c < t_c  <=>  |2h - P| < t_c * P, with h the number of differing bits. Comparing integers
// (t_c in thousandths) keeps the decision exact and platform-independent.
struct Threshold {
  int64_t milli;  // t_c * 1000
  int64_t patches;
  bool below(int64_t deviation) const { return deviation * 1000 < milli * patches; }
};

// Each candidate's screening so far: the highest |2h - P| against kept[0, reached). A test
// correlated at one threshold stays so at a looser one only if that maximum still reaches it,
// so a new pass resumes each candidate where it stopped instead of restarting.
class ScreeningCache {
 public:
  explicit ScreeningCache(size_t candidates) : reached_(candidates, 0), maxDeviation_(candidates, 0) {}

  // Whether candidate d is below the threshold with every kept test before `to`.
  bool uncorrelated(const TestResponses& r, size_t d, const std::vector<size_t>& kept, size_t to, const Threshold& t) {
    if (!t.below(maxDeviation_[d])) return false;
    const auto p = static_cast<int64_t>(r.patches());
    for (size_t k = reached_[d]; k < to; ++k) {
      const int64_t dev = std::llabs(2 * static_cast<int64_t>(r.differences(d, kept[k])) - p);
      maxDeviation_[d] = std::max(maxDeviation_[d], dev);
      reached_[d] = static_cast<uint32_t>(k + 1);
      if (!t.below(dev)) return false;
    }
    return true;
  }

 private:
  std::vector<uint32_t> reached_;
  std::vector<int64_t> maxDeviation_;
};

}  // namespace

std::vector<size_t> sortByVariance(const TestResponses& responses) {
  const size_t n = responses.tests();
  const uint64_t p = responses.patches();
  // alpha(1 - alpha) * P^2 = ones * (P - ones): an exact integer key.
  std::vector<uint64_t> key(n);
  tbb::parallel_for(size_t(0), n, [&](size_t d) {
    const uint64_t ones = responses.ones(d);
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

std::vector<size_t> sortByCriterion(const TestResponses& responses, SelectionCriterion criterion,
                                    const std::vector<uint32_t>& flips, size_t pairs) {
  if (criterion == SelectionCriterion::Paper) return sortByVariance(responses);
  const size_t n = responses.tests();
  if (pairs == 0 || flips.size() != n)
    throw std::invalid_argument("selection criterion " + selectionCriterionName(criterion) +
                                " needs the flip counts of matching pairs");
  const double p = static_cast<double>(responses.patches()), q = static_cast<double>(pairs);
  // IEEE double keys from the same operations everywhere: deterministic across platforms.
  std::vector<double> key(n);
  tbb::parallel_for(size_t(0), n, [&](size_t d) {
    const double alpha = responses.ones(d) / p;
    const double distinct = 2 * alpha * (1 - alpha);
    key[d] = distinct - flips[d] / q;
  });
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  tbb::parallel_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return key[a] != key[b] ? key[a] > key[b] : a < b;
  });
  return order;
}

double correlation(const TestResponses& responses, size_t a, size_t b) {
  const double p = static_cast<double>(responses.patches());
  return std::fabs(2.0 / p * static_cast<double>(responses.differences(a, b)) - 1.0);
}

GreedyResult selectUncorrelated(const TestResponses& responses, const std::vector<size_t>& sorted,
                                const GreedyOptions& options,
                                const std::function<void(size_t, int)>& progress) {
  if (options.startThreshold <= 0 || options.thresholdStep <= 0)
    throw std::invalid_argument("greedy selection: thresholds must be positive");
  if (sorted.size() < options.tests)
    throw std::invalid_argument("greedy selection: " + std::to_string(options.tests) +
                                " tests requested but only " + std::to_string(sorted.size()) +
                                " candidates");
  GreedyResult result;
  std::vector<char> taken(responses.tests(), 0);
  ScreeningCache cache(responses.tests());
  const int64_t start = std::llround(options.startThreshold * 1000);
  const int64_t step = std::llround(options.thresholdStep * 1000);
  std::vector<char> survives(kScreenBatch);

  for (int pass = 0; result.kept.size() < options.tests; ++pass) {
    const Threshold t{start + pass * step, static_cast<int64_t>(responses.patches())};
    result.passes = pass + 1;
    result.finalThreshold = t.milli / 1000.0;
    // Above 1 every remaining test passes (c <= 1), so the walk always ends.
    for (size_t b0 = 0; b0 < sorted.size() && result.kept.size() < options.tests;
         b0 += kScreenBatch) {
      const size_t b1 = std::min(sorted.size(), b0 + kScreenBatch);
      const size_t keptBefore = result.kept.size();
      tbb::parallel_for(b0, b1, [&](size_t i) {
        const size_t d = sorted[i];
        survives[i - b0] = !taken[d] && cache.uncorrelated(responses, d, result.kept, keptBefore, t);
      });
      for (size_t i = b0; i < b1 && result.kept.size() < options.tests; ++i) {
        const size_t d = sorted[i];
        if (!survives[i - b0]) continue;
        if (!cache.uncorrelated(responses, d, result.kept, result.kept.size(), t)) continue;
        taken[d] = 1;
        result.kept.push_back(d);
      }
      if (progress) progress(result.kept.size(), result.passes);
    }
  }
  return result;
}

}  // namespace mdbrief::train
