#pragma once
// Forward selection of a test set by the margin between the distances of matching and of
// non-matching patches (the "separation" criterion, docs/training.md). For a set S, the
// distance of two unrelated patches has mean mu_n = sum_d 2 alpha_d (1 - alpha_d) and variance
// var_n = sum_{d,e in S} cov_n(d, e); the distance of a matching pair (reference patch, the
// same keypoint in a changed view) has mean mu_m = sum_d f_d and variance var_m = sum cov_m.
// Nearest-neighbour matching succeeds when the match is nearer than the nearest of the
// hundreds of non-matching keypoints, which lies about 3 sigma_n below mu_n; a match lies
// around mu_m + sigma_m. The selection adds, one at a time, the test that maximises
//     M(S) = (mu_n - 3 sigma_n) - (mu_m + sigma_m),
// so a test earns its place by being stable (small f), informative (alpha near 1/2) and little
// correlated with the kept tests: correlation widens both distributions. The paper's hard
// correlation threshold becomes a cost weighed against stability. (Fisher's ratio
// (mu_n - mu_m) / sqrt(var_n + var_m) ignores that the nearest of many non-matches decides,
// and kept strongly correlated tests: docs/training.md.)
//
// Covariances from popcounts: for two independent patches, bit d of the distance is
// t_d(a) xor t_d(b), and E[x_d x_e] = 2 (p00 p11 + p01 p10) with p_ij the joint frequencies of
// (t_d, t_e) over the patches; on the pairs, cov_m(d, e) = P(both flip) - f_d f_e.
//
// Bounded memory, same choice as scoring every candidate at every step: only the covariance
// sample (covarianceWords words of the patches and of the pairs, transposed: patch_lanes.hpp)
// and the kept tests' sample columns are held. A candidate's covariance sums are brought up to
// date (its sample columns recomputed, the terms of the tests kept since its last update added
// in the order they were kept, so the sums are the full scan's to the bit) only when an upper
// bound of its score reaches the best exact score of the step. The bound takes every missed
// term at its smallest value: cov_n(d, e) >= -(2 a_d - 1)^2 (2 a_e - 1)^2 / 4 (the minimum over
// p11 of the expression above, near 0 for informative tests), cov_m(d, e) >= -f_d f_e.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "mdbrief/describe/comparison_set.hpp"
#include "trainer/comparison_responses.hpp"
#include "trainer/patch_lanes.hpp"

namespace mdbrief::train {

struct SeparationOptions {
  size_t tests = 512;   // tests to select
  // Candidates considered: the best by the per-test margin 2 alpha (1 - alpha) - f (the
  // "stability" order). Smaller pools lack the diverse, less stable tests the set needs; all
  // 377,650 cost twice the time for no gain (docs/training.md "Selection criteria").
  size_t pool = 131072;
  double nonMatchingSigmas = 3.0;  // the nearest of ~300 non-matching keypoints
  double matchingSigmas = 1.0;
  // Covariances are estimated on at most this many 64-patch words of the patches and of the
  // pairs (evenly spread): 128 words = 8,192 samples, a standard error near 0.005.
  size_t covarianceWords = 128;
};

struct SeparationResult {
  std::vector<size_t> kept;        // candidate indices in selection order
  std::vector<double> separation;  // J after each addition
};

// candidates: all tests, with their counts on `patches` and on the pairs (reference patch
// counterparts.of[j], counterpart j); order: indices into candidates by the per-test margin,
// best first (sortByCriterion Stability); the pool is order[0, options.pool). Deterministic:
// ties to the earlier candidate in `order`, each sum accumulated in a fixed order, whatever the
// block sizes. progress(kept) is called from the calling thread. Throws std::invalid_argument if
// the pool is smaller than `tests`, the counts or pairs are missing or disagree, or an option is
// out of range.
SeparationResult selectBySeparation(const PatchMatrix& patches, const Counterparts& counterparts,
                                    const std::vector<ComparisonPair>& candidates, const ResponseCounts& counts,
                                    const std::vector<size_t>& order, const SeparationOptions& options,
                                    const std::function<void(size_t)>& progress = {},
                                    const StreamingOptions& streaming = {});

}  // namespace mdbrief::train
