#pragma once
// A bag of visual words: one image's features as the weighted words of a vocabulary
// (vocabulary.hpp), and the L1 score that compares two of them (Nister and Stewenius 2006, as
// DBoW2 scores).
#include <cstdint>
#include <vector>

namespace mdbrief {

struct BowEntry {
  uint32_t word = 0;
  float value = 0;
};

// Entries in ascending word order, each word once, values > 0 that sum to 1 (L1-normalised).
// Empty when no feature reached a word of non-zero weight.
using BowVector = std::vector<BowEntry>;

// Similarity of two L1-normalised vectors: 1 - |a - b|_1 / 2, which for such vectors is the sum
// over their common words of min(a_w, b_w). In [0, 1]: 1 for equal vectors, 0 without a common
// word. Unchecked: both must be BowVectors as described above.
float l1Score(const BowVector& a, const BowVector& b) noexcept;

}  // namespace mdbrief
