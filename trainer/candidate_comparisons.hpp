#pragma once
// The trainer's candidate comparisons (the paper's candidate tests, "Off-line Learning"): every
// pair of pixels of the 32x32 patch with both pixels off the 1-pixel border (offsets -15..14) and
// Euclidean distance 3 < d < 29 (the paper's "d < 3 or d > 9S/10" removed, with the
// integer-distance pairs on the limits also removed): exactly kCandidateCount comparisons.
#include <cstddef>
#include <vector>

#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief::train {

inline constexpr size_t kCandidateCount = 377650;

// Ordered by first pixel, then second pixel, both row-major (y, then x) with first < second,
// so a candidate's index is a stable tie-breaker.
std::vector<ComparisonPair> candidateComparisons();

}  // namespace mdbrief::train
