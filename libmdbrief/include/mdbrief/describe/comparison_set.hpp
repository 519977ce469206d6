#pragma once
// A comparison set (the paper's binary test set): pairs of integer offsets (x1, y1, x2, y2)
// relative to the keypoint, in the 32x32 patch frame. The patch's pixel (i, j), i, j = 0..31, has
// offset (i - 16, j - 16), so the keypoint is patch pixel (16, 16) and offsets lie in [-16, 15].
// Comparison d is I(x1, y1) < I(x2, y2) and yields bit d (see descriptor.hpp for the bit order).
// The member `tests` keeps the name of the JSON files' key.
#include <cstdint>
#include <string>
#include <vector>

namespace mdbrief {

struct ComparisonPair {
  int8_t x1, y1, x2, y2;
};

inline constexpr int kPatchSize = 32;
inline constexpr int kPatchHalf = 16;  // offset = patch index - kPatchHalf

struct ComparisonSet {
  std::string name;
  std::vector<ComparisonPair> tests;
  // Digests (16 hex digits) of the decoded grey pixels of the images the set was learned from,
  // so an evaluation can prove it never saw them; empty for a random set.
  std::vector<std::string> trainingImages;

  // The first n tests (n in 32..size(), multiple of 32). Throws std::invalid_argument otherwise.
  ComparisonSet first(int n) const;
};

// The names of 0.2, deprecated: in this project "test" now means a unit test, and a BRIEF test
// is a comparison. The header mdbrief/describe/test_set.hpp still works and includes this one.
using TestPair [[deprecated("renamed ComparisonPair")]] = ComparisonPair;
using TestSet [[deprecated("renamed ComparisonSet")]] = ComparisonSet;

}  // namespace mdbrief
