#include "trainer/test_responses.hpp"

#include <atomic>
#include <stdexcept>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "mdbrief/simd_level.hpp"
#include "trainer/test_response_kernels.hpp"

namespace mdbrief::train {

namespace {

using kernels::activeResponseKernels;
using kernels::kLanes;
using kernels::ResponseKernels;

constexpr size_t kPixels = kPatchSize * kPatchSize;
// Work block: kWordGroup words (a cache line of each column) x kTestBlock tests.
constexpr size_t kWordGroup = 8;
constexpr size_t kTestBlock = 4096;

// Transposes the patches into 64-patch blocks, pixel-major. Padding lanes of the last block are
// 0 in both pixels of every test, so their bits are 0 (0 < 0 is false).
std::vector<uint8_t> transposeIntoLanes(const PatchMatrix& patches, size_t words) {
  std::vector<uint8_t> lanes(words * kPixels * kLanes, 0);
  tbb::parallel_for(size_t(0), words, [&](size_t w) {
    uint8_t* block = lanes.data() + w * kPixels * kLanes;
    const size_t end = std::min(patches.count, (w + 1) * kLanes);
    for (size_t p = w * kLanes; p < end; ++p) {
      const uint8_t* src = patches.pixels + p * kPixels;
      for (size_t i = 0; i < kPixels; ++i) block[i * kLanes + (p - w * kLanes)] = src[i];
    }
  });
  return lanes;
}

// Bit k = a[k] < b[k] (unsigned), k = 0..63.
uint64_t lessMask(const uint8_t* a, const uint8_t* b) {
  uint64_t m = 0;
  for (size_t k = 0; k < kLanes; ++k) m |= uint64_t(a[k] < b[k]) << k;
  return m;
}


int pixelIndex(int x, int y) { return (y + kPatchHalf) * kPatchSize + (x + kPatchHalf); }

std::vector<std::pair<int, int>> pixelPairsOf(const std::vector<TestPair>& tests) {
  std::vector<std::pair<int, int>> pixelPairs(tests.size());
  for (size_t d = 0; d < tests.size(); ++d) {
    const TestPair& t = tests[d];
    for (int v : {t.x1, t.y1, t.x2, t.y2})
      if (v < -kPatchHalf || v >= kPatchHalf)
        throw std::invalid_argument("evaluateTests: test " + std::to_string(d) +
                                    " has an offset outside [-16, 15]");
    pixelPairs[d] = {pixelIndex(t.x1, t.y1), pixelIndex(t.x2, t.y2)};
  }
  return pixelPairs;
}

// The reference patch of every pair, in pair order, so both sides of a pair share one layout.
std::vector<uint8_t> pairedReferences(const PatchMatrix& reference, const PatchMatrix& counterparts,
                                      const std::vector<int32_t>& counterpartOf) {
  if (counterparts.count == 0 || counterpartOf.size() != counterparts.count)
    throw std::invalid_argument("matching pairs: no counterparts, or their reference index is missing");
  std::vector<uint8_t> paired(counterparts.count * kPixels);
  for (size_t j = 0; j < counterparts.count; ++j) {
    const auto r = static_cast<size_t>(counterpartOf[j]);
    if (counterpartOf[j] < 0 || r >= reference.count)
      throw std::invalid_argument("matching pairs: counterpart index out of range");
    std::copy_n(reference.pixels + r * kPixels, kPixels, paired.data() + j * kPixels);
  }
  return paired;
}

}  // namespace

ResponseKernels kernels::portableResponseKernels() { return responseKernelsWith<lessMask>(); }

ResponseKernels kernels::activeResponseKernels() {
#if defined(MDBRIEF_X86_KERNELS)
  switch (activeSimdLevel()) {
    case SimdLevel::Avx512: return avx512ResponseKernels();
    case SimdLevel::Avx2: return avx2ResponseKernels();
    case SimdLevel::Portable: break;
  }
#endif
  return portableResponseKernels();
}

TestResponses::TestResponses(size_t tests, size_t patches)
    : tests_(tests), patches_(patches), words_((patches + 63) / 64), bits_(tests * words_, 0) {
  const ResponseKernels k = activeResponseKernels();
  popcount_ = k.popcount;
  popcountXor_ = k.popcountXor;
}

size_t TestResponses::ones(size_t test) const { return popcount_(column(test), words_); }

size_t TestResponses::differences(size_t a, size_t b) const { return popcountXor_(column(a), column(b), words_); }

TestResponses evaluateTests(const PatchMatrix& patches, const std::vector<TestPair>& tests,
                            const std::function<void(size_t, size_t)>& progress) {
  if (patches.count == 0 || !patches.pixels)
    throw std::invalid_argument("evaluateTests: no patches");
  const auto pixelPairs = pixelPairsOf(tests);

  TestResponses responses(tests.size(), patches.count);
  const size_t words = responses.words();
  const std::vector<uint8_t> lanes = transposeIntoLanes(patches, words);
  const ResponseKernels k = activeResponseKernels();

  const size_t wordBlocks = (words + kWordGroup - 1) / kWordGroup;
  const size_t testBlocks = (tests.size() + kTestBlock - 1) / kTestBlock;
  const size_t totalBlocks = wordBlocks * testBlocks;
  std::atomic<size_t> done{0};
  tbb::parallel_for(
      tbb::blocked_range2d<size_t>(0, wordBlocks, 1, 0, testBlocks, 1),
      [&](const tbb::blocked_range2d<size_t>& r) {
        for (size_t wb = r.rows().begin(); wb != r.rows().end(); ++wb) {
          const size_t w0 = wb * kWordGroup, w1 = std::min(words, w0 + kWordGroup);
          for (size_t tb = r.cols().begin(); tb != r.cols().end(); ++tb) {
            const size_t d1 = std::min(tests.size(), (tb + 1) * kTestBlock);
            for (size_t d = tb * kTestBlock; d < d1; ++d) {
              const auto [a, b] = pixelPairs[d];
              k.lessMasks(lanes.data(), kPixels * kLanes, a, b, w0, w1, responses.column(d));
            }
            const size_t n = ++done;
            if (progress) progress(n, totalBlocks);
          }
        }
      });
  return responses;
}

std::vector<uint32_t> countDisagreements(const PatchMatrix& reference, const PatchMatrix& counterparts,
                                         const std::vector<int32_t>& counterpartOf,
                                         const std::vector<TestPair>& tests,
                                         const std::function<void(size_t, size_t)>& progress) {
  const auto pixelPairs = pixelPairsOf(tests);
  const std::vector<uint8_t> paired = pairedReferences(reference, counterparts, counterpartOf);
  const size_t words = (counterparts.count + kLanes - 1) / kLanes;
  const std::vector<uint8_t> a = transposeIntoLanes({paired.data(), counterparts.count}, words);
  const std::vector<uint8_t> b = transposeIntoLanes(counterparts, words);

  std::vector<uint32_t> flips(tests.size(), 0);
  const ResponseKernels k = activeResponseKernels();
  const size_t testBlocks = (tests.size() + kTestBlock - 1) / kTestBlock;
  std::atomic<size_t> done{0};
  // Parallel over tests only: each count is then summed by one thread, in word order.
  tbb::parallel_for(size_t(0), testBlocks, [&](size_t tb) {
    const size_t d0 = tb * kTestBlock, d1 = std::min(tests.size(), d0 + kTestBlock);
    for (size_t w0 = 0; w0 < words; w0 += kWordGroup) {
      const size_t w1 = std::min(words, w0 + kWordGroup);
      for (size_t d = d0; d < d1; ++d) {
        const auto [p1, p2] = pixelPairs[d];
        flips[d] += k.flips(a.data(), b.data(), kPixels * kLanes, p1, p2, w0, w1);
      }
    }
    const size_t n = ++done;
    if (progress) progress(n, testBlocks);
  });
  return flips;
}

TestResponses disagreementBits(const PatchMatrix& reference, const PatchMatrix& counterparts,
                               const std::vector<int32_t>& counterpartOf, const std::vector<TestPair>& tests) {
  const std::vector<uint8_t> paired = pairedReferences(reference, counterparts, counterpartOf);
  TestResponses bits = evaluateTests({paired.data(), counterparts.count}, tests);
  const TestResponses other = evaluateTests(counterparts, tests);
  for (size_t d = 0; d < tests.size(); ++d)
    for (size_t w = 0; w < bits.words(); ++w) bits.column(d)[w] ^= other.column(d)[w];
  return bits;
}

}  // namespace mdbrief::train
