#include "trainer/candidate_comparisons.hpp"

namespace mdbrief::train {

std::vector<ComparisonPair> candidateComparisons() {
  constexpr int lo = 1, hi = kPatchSize - 2;  // patch pixels 1..30: the border excluded
  constexpr int minD2 = 3 * 3, maxD2 = 29 * 29;
  std::vector<ComparisonPair> tests;
  tests.reserve(kCandidateCount);
  for (int a = 0; a < kPatchSize * kPatchSize; ++a) {
    const int ax = a % kPatchSize, ay = a / kPatchSize;
    if (ax < lo || ax > hi || ay < lo || ay > hi) continue;
    for (int b = a + 1; b < kPatchSize * kPatchSize; ++b) {
      const int bx = b % kPatchSize, by = b / kPatchSize;
      if (bx < lo || bx > hi || by < lo || by > hi) continue;
      const int d2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay);
      if (d2 <= minD2 || d2 >= maxD2) continue;
      tests.push_back({static_cast<int8_t>(ax - kPatchHalf), static_cast<int8_t>(ay - kPatchHalf),
                       static_cast<int8_t>(bx - kPatchHalf), static_cast<int8_t>(by - kPatchHalf)});
    }
  }
  return tests;
}

}  // namespace mdbrief::train
