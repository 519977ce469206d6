#pragma once
// The whole off-line learning on a patch set: candidates -> response and flip counts (streamed)
// -> sort by the criterion -> greedy or separation selection (recomputing the responses of the
// candidates they examine), with the per-test statistics the pattern header records. Memory
// grows with the patches and the pool, not with candidates x patches (docs/training.md "Trainer").
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "trainer/pattern_writer.hpp"
#include "mdbrief/describe/comparison_set.hpp"
#include "trainer/greedy_selection.hpp"
#include "trainer/separation_selection.hpp"
#include "trainer/comparison_responses.hpp"

namespace mdbrief::train {

struct StageTimes {
  double evaluateSeconds = 0;  // all candidates counted on all patches
  double flipSeconds = 0;      // all candidates counted on all matching pairs (stability criteria)
  double sortSeconds = 0;      // variance + sort
  double greedySeconds = 0;    // all greedy passes
};

struct LearnedComparisons {
  std::vector<ComparisonPair> tests;          // in selection order
  std::vector<double> mean;             // per test: fraction of patches where it is 1
  std::vector<double> maxCorrelation;   // per test: max correlation with the other kept tests
  std::vector<double> flipRate;         // per test: fraction of matching pairs where it flips
                                        // (empty without pairs)
  SelectionCriterion criterion = SelectionCriterion::Paper;
  size_t candidates = 0;
  size_t patches = 0;
  size_t pairs = 0;                     // matching pairs (counterparts) used
  int passes = 0;
  double finalThreshold = 0;
  StageTimes times;
};

// stage is "evaluate", "pairs" or "greedy"; done/total in stage units (work blocks, kept tests).
using TrainingProgress = std::function<void(const char* stage, size_t done, size_t total)>;

// The candidates are ranked by `criterion` (with the flip rates measured on `counterparts`
// when it needs them) and kept greedily as the paper does (Paper, Stability), or by forward
// selection with `separation`'s pool and weights (Separation; its tests come from
// options.tests, a pool below it is raised to it). With pairs, the flip rate of every kept test
// is reported even for the paper's criterion. Throws std::invalid_argument if the patch set is
// empty, options.tests exceeds the number of candidates, or the criterion needs pairs and there
// are none. `streaming` changes time and memory only, never the tests.
LearnedComparisons learnComparisons(const PatchMatrix& patches, const GreedyOptions& options,
                                    SelectionCriterion criterion = SelectionCriterion::Paper,
                                    const Counterparts& counterparts = {}, const TrainingProgress& progress = {},
                                    const SeparationOptions& separation = {}, const StreamingOptions& streaming = {});

// Quality of a test set on a patch set: the learning's two criteria.
struct ComparisonSetQuality {
  double meanVariance = 0;     // mean over tests of alpha(1 - alpha) (max 0.25)
  double meanCorrelation = 0;  // mean over test pairs of the paper's correlation
};
ComparisonSetQuality measureComparisonSet(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests);

// The content digest (toolkit/content_digest.hpp) of the patch pixels: the header's data digest.
std::string patchDigest(const PatchMatrix& patches);

}  // namespace mdbrief::train
