#pragma once
// ORB's greedy learning as in the paper's "Off-line Learning": tests sorted by variance
// alpha(1 - alpha), high first; then walk the sorted list keeping a test when its correlation
// c = |2/P * sum_p |t_d,p - t_s,p| - 1| with every kept test is below t_c; t_c starts at 0.2
// and rises by 0.1 after each full pass until the requested number is kept.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mdbrief/base/enum_names.hpp"
#include "trainer/comparison_responses.hpp"

namespace mdbrief::train {

// Test indices sorted by variance, highest first; equal variances by index, so the order does
// not depend on the sort implementation.
std::vector<size_t> sortByVariance(const ResponseCounts& counts);

// What the greedy walk ranks the candidates by (docs/training.md "Selection criteria"). With
// alpha = the fraction of patches where a test is 1 and f = the fraction of matching pairs
// (reference patch, counterpart in a changed view) on which it flips:
enum class SelectionCriterion {
  Paper,      // alpha(1 - alpha): the paper's (ORB's) unsupervised order; needs no pairs
  // 2 alpha(1 - alpha) - f: the test's expected contribution to the distance of two unrelated
  // patches minus its contribution to the distance of a matching pair, i.e. to the margin
  // between the non-matching and matching distance distributions.
  Stability,
  // Forward selection by the Fisher-like separation of the whole set's matching and
  // non-matching distance distributions (separation_selection.hpp), over the best candidates
  // of the Stability order; no correlation threshold.
  Separation,
};

// The names users type (mdbrief/base/enum_names.hpp).
inline constexpr EnumName<SelectionCriterion> kSelectionCriterionNames[] = {
    {SelectionCriterion::Paper, "paper"},
    {SelectionCriterion::Stability, "stability"},
    {SelectionCriterion::Separation, "separation"}};
// Throws std::invalid_argument naming the accepted values.
inline SelectionCriterion parseSelectionCriterion(const std::string& name) {
  return parseName(name, kSelectionCriterionNames, "selection criterion");
}
inline std::string selectionCriterionName(SelectionCriterion criterion) {
  return nameOf(criterion, kSelectionCriterionNames);
}
bool needsCounterparts(SelectionCriterion criterion);

// Test indices sorted by the criterion, best first, ties by index. The flip counts are ignored,
// and may be missing, for Paper (which gives exactly sortByVariance); Separation sorts as
// Stability, the order its pool is taken from. Throws std::invalid_argument if a criterion needs
// pairs and has none.
std::vector<size_t> sortByCriterion(const ResponseCounts& counts, SelectionCriterion criterion);

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

// Walks `sorted` (indices into `candidates`), recomputing from `patches` the columns of the
// candidates a batch still has to screen; only the kept tests' columns are held. Deterministic:
// the result equals the sequential walk (candidates are screened in parallel against the tests
// kept so far, survivors are then decided in order), whatever the block sizes. progress(kept,
// pass), if set, is called from the calling thread. Throws std::invalid_argument if there are
// fewer candidates than requested tests, the thresholds are not positive or an offset lies
// outside [-16, 15].
GreedyResult selectUncorrelated(const PatchLanes& patches, const std::vector<ComparisonPair>& candidates,
                                const std::vector<size_t>& sorted, const GreedyOptions& options,
                                const std::function<void(size_t, int)>& progress = {},
                                const StreamingOptions& streaming = {});

// Correlation of the paper between two columns, in [0, 1].
double correlation(const ComparisonResponses& responses, size_t a, size_t b);

}  // namespace mdbrief::train
