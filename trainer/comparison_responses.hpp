#pragma once
// Comparisons (the paper's binary tests) evaluated on patches (1 when I(p1) < I(p2), as the
// runtime descriptor): as counts per comparison, streamed chunk by chunk for every candidate, or
// as bit-packed columns for the few a selection examines. A column holds bit p = the comparison on
// patch p, in `words` uint64 words, the padding bits after the last patch zero; variances and
// pairwise correlations are then popcounts over contiguous words.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "mdbrief/describe/comparison_set.hpp"
#include "trainer/patch_lanes.hpp"

namespace mdbrief::train {

// A test as the indices of its two patch pixels (y * 32 + x).
struct PixelPair {
  uint16_t a = 0, b = 0;
};
// Throws std::invalid_argument naming the test if an offset lies outside [-16, 15].
std::vector<PixelPair> pixelPairsOf(const std::vector<ComparisonPair>& tests);

// What the rankings need of every candidate (countResponses, countDisagreements).
struct ResponseCounts {
  size_t patches = 0;
  std::vector<uint32_t> ones;   // per test: patches on which it is 1
  size_t pairs = 0;             // matching pairs (0: none, and flips is empty)
  std::vector<uint32_t> flips;  // per test: pairs on which it flips
};

class ComparisonResponses {
 public:
  ComparisonResponses() : ComparisonResponses(0, 0) {}
  ComparisonResponses(size_t tests, size_t patches);

  size_t tests() const { return tests_; }
  size_t patches() const { return patches_; }
  size_t words() const { return words_; }
  const uint64_t* column(size_t test) const { return bits_.data() + test * words_; }
  uint64_t* column(size_t test) { return bits_.data() + test * words_; }
  // Number of patches on which the test is 1.
  size_t ones(size_t test) const;
  // Hamming distance between two columns (patches where the tests differ).
  size_t differences(size_t a, size_t b) const;

 private:
  size_t tests_ = 0, patches_ = 0, words_ = 0;
  std::vector<uint64_t> bits_;
  // Population counts of the SIMD level active at construction (comparison_response_kernels.hpp).
  size_t (*popcount_)(const uint64_t*, size_t) = nullptr;
  size_t (*popcountXor_)(const uint64_t*, const uint64_t*, size_t) = nullptr;
};

// The columns of a few tests on all patches (tests x patches bits: for the kept tests, not for
// every candidate). Throws std::invalid_argument on an empty patch set or an offset outside
// [-16, 15].
ComparisonResponses evaluateComparisons(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests,
                                        const StreamingOptions& streaming = {});

// Per test, the number of patches on which it is 1; the patches are streamed chunk by chunk and
// no response is stored. progress(done, total), if set, is called from worker threads after each
// chunk, so it must be thread-safe. Same errors as evaluateComparisons.
std::vector<uint32_t> countResponses(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests,
                                     const std::function<void(size_t, size_t)>& progress = {},
                                     const StreamingOptions& streaming = {});

// Stability data: for every test, on how many pairs (counterpart j, reference patch
// counterparts.of[j]) its outcome differs, streamed as countResponses. Throws
// std::invalid_argument on no counterparts, a reference index out of range or an offset
// outside [-16, 15].
std::vector<uint32_t> countDisagreements(const PatchMatrix& reference, const Counterparts& counterparts,
                                         const std::vector<ComparisonPair>& tests,
                                         const std::function<void(size_t, size_t)>& progress = {},
                                         const StreamingOptions& streaming = {});

// Columns recomputed from kept lanes: out[n * lanes.words() + w] for test n < count, in parallel
// over the chunks.
void evaluateColumns(const PatchLanes& lanes, const PixelPair* tests, size_t count, uint64_t* out);
// The same for pairs of row sets of equal size: bit r = the test differs between row r of `a`
// and row r of `b`.
void evaluateFlipColumns(const PatchLanes& a, const PatchLanes& b, const PixelPair* tests, size_t count,
                         uint64_t* out);

}  // namespace mdbrief::train
