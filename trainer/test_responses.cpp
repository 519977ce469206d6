#include "trainer/test_responses.hpp"

#include <atomic>
#include <stdexcept>

#include <immintrin.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

namespace mdbrief::train {

namespace {

constexpr size_t kPixels = kPatchSize * kPatchSize;
// 64 patches (one result word) are transposed into a 1024 x 64 byte block: a test on 64 patches
// is then one comparison of two contiguous 64-byte rows.
constexpr size_t kLanes = 64;
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
inline uint64_t lessMask(const uint8_t* a, const uint8_t* b) {
#if defined(__AVX512BW__)
  return _mm512_cmplt_epu8_mask(_mm512_loadu_si512(a), _mm512_loadu_si512(b));
#else
  uint64_t m = 0;
  for (size_t k = 0; k < kLanes; ++k) m |= uint64_t(a[k] < b[k]) << k;
  return m;
#endif
}

int pixelIndex(int x, int y) { return (y + kPatchHalf) * kPatchSize + (x + kPatchHalf); }

}  // namespace

TestResponses::TestResponses(size_t tests, size_t patches)
    : tests_(tests), patches_(patches), words_((patches + 63) / 64), bits_(tests * words_, 0) {}

size_t TestResponses::ones(size_t test) const {
  const uint64_t* c = column(test);
  size_t n = 0;
  for (size_t w = 0; w < words_; ++w) n += static_cast<size_t>(__builtin_popcountll(c[w]));
  return n;
}

size_t TestResponses::differences(size_t a, size_t b) const {
  const uint64_t* ca = column(a);
  const uint64_t* cb = column(b);
  size_t n = 0;
  for (size_t w = 0; w < words_; ++w) n += static_cast<size_t>(__builtin_popcountll(ca[w] ^ cb[w]));
  return n;
}

TestResponses evaluateTests(const PatchMatrix& patches, const std::vector<TestPair>& tests,
                            const std::function<void(size_t, size_t)>& progress) {
  if (patches.count == 0 || !patches.pixels)
    throw std::invalid_argument("evaluateTests: no patches");
  std::vector<std::pair<int, int>> pixelPairs(tests.size());
  for (size_t d = 0; d < tests.size(); ++d) {
    const TestPair& t = tests[d];
    for (int v : {t.x1, t.y1, t.x2, t.y2})
      if (v < -kPatchHalf || v >= kPatchHalf)
        throw std::invalid_argument("evaluateTests: test " + std::to_string(d) +
                                    " has an offset outside [-16, 15]");
    pixelPairs[d] = {pixelIndex(t.x1, t.y1), pixelIndex(t.x2, t.y2)};
  }

  TestResponses responses(tests.size(), patches.count);
  const size_t words = responses.words();
  const std::vector<uint8_t> lanes = transposeIntoLanes(patches, words);

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
              uint64_t* column = responses.column(d);
              const auto [a, b] = pixelPairs[d];
              for (size_t w = w0; w < w1; ++w) {
                const uint8_t* block = lanes.data() + w * kPixels * kLanes;
                column[w] = lessMask(block + a * kLanes, block + b * kLanes);
              }
            }
            const size_t n = ++done;
            if (progress) progress(n, totalBlocks);
          }
        }
      });
  return responses;
}

}  // namespace mdbrief::train
