#pragma once
// A binary test set: pairs of integer offsets (x1, y1, x2, y2) relative to the keypoint, in
// the 32x32 patch frame. The patch's pixel (i, j), i, j = 0..31, has offset (i - 16, j - 16),
// so the keypoint is patch pixel (16, 16) and offsets lie in [-16, 15]. Test d compares
// I(x1, y1) < I(x2, y2) and yields bit d (see descriptor.hpp for the bit order).
#include <cstdint>
#include <string>
#include <vector>

namespace mdbrief {

struct TestPair {
  int8_t x1, y1, x2, y2;
};

inline constexpr int kPatchSize = 32;
inline constexpr int kPatchHalf = 16;  // offset = patch index - kPatchHalf

struct TestSet {
  std::string name;
  std::vector<TestPair> tests;
  // Digests (16 hex digits) of the decoded grey pixels of the images the set was learned from,
  // so an evaluation can prove it never saw them; empty for a random set.
  std::vector<std::string> trainingImages;

  // The first n tests (n in 32..size(), multiple of 32). Throws std::invalid_argument otherwise.
  TestSet first(int n) const;
};

}  // namespace mdbrief
