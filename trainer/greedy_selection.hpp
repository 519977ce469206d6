#pragma once
// ORB's greedy learning as in the paper's "Off-line Learning": tests sorted by variance
// alpha(1 - alpha), high first; then walk the sorted list keeping a test when its correlation
// c = |2/P * sum_p |t_d,p - t_s,p| - 1| with every kept test is below t_c; t_c starts at 0.2
// and rises by 0.1 after each full pass until the requested number is kept.
#include <cstddef>
#include <functional>
#include <vector>

#include "trainer/test_responses.hpp"

namespace mdbrief::train {

// Test indices sorted by variance, highest first; equal variances by index, so the order does
// not depend on the sort implementation.
std::vector<size_t> sortByVariance(const TestResponses& responses);

struct GreedyOptions {
  size_t tests = 512;             // number of tests to keep
  double startThreshold = 0.2;    // t_c of the first pass (paper: 0.2)
  double thresholdStep = 0.1;     // t_c increase after each full pass (paper: 0.1)
};

struct GreedyResult {
  std::vector<size_t> kept;       // test indices in the order they were kept
  int passes = 0;                 // passes started (1 = the first pass sufficed)
  double finalThreshold = 0.0;    // t_c of the last pass
};

// Deterministic: the result equals the sequential walk (candidates are screened in parallel
// against the tests kept so far, survivors are then decided in order). progress(kept, pass),
// if set, is called from the calling thread. Throws std::invalid_argument if there are fewer
// candidates than requested tests or the thresholds are not positive.
GreedyResult selectUncorrelated(const TestResponses& responses, const std::vector<size_t>& sorted,
                                const GreedyOptions& options,
                                const std::function<void(size_t, int)>& progress = {});

// Correlation of the paper between two columns, in [0, 1].
double correlation(const TestResponses& responses, size_t a, size_t b);

}  // namespace mdbrief::train
