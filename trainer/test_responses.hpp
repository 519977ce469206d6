#pragma once
// Every test evaluated on every patch, stored as bit-packed columns: column d holds bit p =
// test d on patch p (1 when I(p1) < I(p2), as the runtime descriptor), in `words` uint64 words,
// the padding bits after the last patch zero. Column-major, so the variance and the pairwise
// correlations of the greedy selection are popcounts over contiguous words.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "mdbrief/test_set.hpp"

namespace mdbrief::train {

// Patches: count x 32 x 32 uint8, row-major (pixel (x, y) of patch p at p*1024 + y*32 + x, the
// keypoint at (16, 16), as the offsets of test_set.hpp).
struct PatchMatrix {
  const uint8_t* pixels = nullptr;
  size_t count = 0;
};

class TestResponses {
 public:
  TestResponses() : TestResponses(0, 0) {}
  TestResponses(size_t tests, size_t patches);

  size_t tests() const { return tests_; }
  size_t patches() const { return patches_; }
  size_t words() const { return words_; }
  const uint64_t* column(size_t test) const { return bits_.data() + test * words_; }
  uint64_t* column(size_t test) { return bits_.data() + test * words_; }
  // Number of patches on which the test is 1.
  size_t ones(size_t test) const;
  // Hamming distance between two columns (patches where the tests differ).
  size_t differences(size_t a, size_t b) const;
  size_t bytes() const { return bits_.size() * sizeof(uint64_t); }

 private:
  size_t tests_ = 0, patches_ = 0, words_ = 0;
  std::vector<uint64_t> bits_;
  // Population counts of the SIMD level active at construction (test_response_kernels.hpp).
  size_t (*popcount_)(const uint64_t*, size_t) = nullptr;
  size_t (*popcountXor_)(const uint64_t*, const uint64_t*, size_t) = nullptr;
};

// Evaluates all tests on all patches in parallel (TBB). progress(done, total), if set, is called
// from worker threads after each finished work block, so it must be thread-safe. Throws std::invalid_argument on an empty patch set or an offset outside [-16, 15].
TestResponses evaluateTests(const PatchMatrix& patches, const std::vector<TestPair>& tests,
                            const std::function<void(size_t, size_t)>& progress = {});

// Stability data: for every test, on how many pairs (counterpart j, reference patch
// counterpartOf[j]) its outcome differs. The pairs' bits are compared on the fly and never
// stored. progress(done, total) as above. Throws std::invalid_argument on no counterparts, a
// reference index out of range or an offset outside [-16, 15].
std::vector<uint32_t> countDisagreements(const PatchMatrix& reference, const PatchMatrix& counterparts,
                                         const std::vector<int32_t>& counterpartOf,
                                         const std::vector<TestPair>& tests,
                                         const std::function<void(size_t, size_t)>& progress = {});

// The pairs' flip bits of a few tests, as columns: bit j of column d = test d differs between
// pair j's two patches. Same errors as countDisagreements.
TestResponses disagreementBits(const PatchMatrix& reference, const PatchMatrix& counterparts,
                               const std::vector<int32_t>& counterpartOf, const std::vector<TestPair>& tests);

}  // namespace mdbrief::train
