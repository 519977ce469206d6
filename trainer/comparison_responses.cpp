#include "trainer/comparison_responses.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "trainer/comparison_response_kernels.hpp"

namespace mdbrief::train {

namespace {

using kernels::activeResponseKernels;
using kernels::kLanes;
using kernels::ResponseKernels;

// Per-test counts summed over chunks handled by several threads: integer sums, so the total
// does not depend on which thread counted which chunk.
std::vector<uint32_t> sumCounts(tbb::enumerable_thread_specific<std::vector<uint32_t>>& partial, size_t tests) {
  std::vector<uint32_t> total(tests, 0);
  for (const std::vector<uint32_t>& counts : partial)
    for (size_t d = 0; d < tests; ++d) total[d] += counts[d];
  return total;
}

}  // namespace

std::vector<PixelPair> pixelPairsOf(const std::vector<ComparisonPair>& tests) {
  std::vector<PixelPair> pixels(tests.size());
  for (size_t d = 0; d < tests.size(); ++d) {
    const ComparisonPair& t = tests[d];
    for (int v : {t.x1, t.y1, t.x2, t.y2})
      if (v < -kPatchHalf || v >= kPatchHalf)
        throw std::invalid_argument("test " + std::to_string(d) + " has an offset outside [-16, 15]");
    pixels[d] = {static_cast<uint16_t>((t.y1 + kPatchHalf) * kPatchSize + (t.x1 + kPatchHalf)),
                 static_cast<uint16_t>((t.y2 + kPatchHalf) * kPatchSize + (t.x2 + kPatchHalf))};
  }
  return pixels;
}

ComparisonResponses::ComparisonResponses(size_t tests, size_t patches)
    : tests_(tests), patches_(patches), words_((patches + 63) / 64), bits_(tests * words_, 0) {
  const ResponseKernels k = activeResponseKernels();
  popcount_ = k.popcount;
  popcountXor_ = k.popcountXor;
}

size_t ComparisonResponses::ones(size_t test) const { return popcount_(column(test), words_); }

size_t ComparisonResponses::differences(size_t a, size_t b) const { return popcountXor_(column(a), column(b), words_); }

ComparisonResponses evaluateComparisons(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests,
                                        const StreamingOptions& streaming) {
  if (patches.count == 0 || !patches.pixels) throw std::invalid_argument("evaluateComparisons: no patches");
  const std::vector<PixelPair> pixels = pixelPairsOf(tests);
  ComparisonResponses responses(tests.size(), patches.count);
  const ResponseKernels k = activeResponseKernels();
  const PatchRows rows = PatchRows::of(patches);
  // Each chunk writes its own words of every column.
  streamChunks({&rows}, streaming.chunkWords, [&](const std::vector<LaneChunk>& chunk) {
    const LaneChunk& c = chunk[0];
    for (size_t d = 0; d < tests.size(); ++d)
      k.lessMasks(c.row(pixels[d].a), c.row(pixels[d].b), c.words, responses.column(d) + c.firstWord);
  });
  return responses;
}

std::vector<uint32_t> countResponses(const PatchMatrix& patches, const std::vector<ComparisonPair>& tests,
                                     const std::function<void(size_t, size_t)>& progress,
                                     const StreamingOptions& streaming) {
  if (patches.count == 0 || !patches.pixels) throw std::invalid_argument("countResponses: no patches");
  const std::vector<PixelPair> pixels = pixelPairsOf(tests);
  const ResponseKernels k = activeResponseKernels();
  const PatchRows rows = PatchRows::of(patches);
  tbb::enumerable_thread_specific<std::vector<uint32_t>> partial(std::vector<uint32_t>(tests.size(), 0));
  streamChunks(
      {&rows}, streaming.chunkWords,
      [&](const std::vector<LaneChunk>& chunk) {
        const LaneChunk& c = chunk[0];
        std::vector<uint32_t>& counts = partial.local();
        for (size_t d = 0; d < tests.size(); ++d) counts[d] += k.ones(c.row(pixels[d].a), c.row(pixels[d].b), c.words);
      },
      progress);
  return sumCounts(partial, tests.size());
}

std::vector<uint32_t> countDisagreements(const PatchMatrix& reference, const Counterparts& counterparts,
                                         const std::vector<ComparisonPair>& tests,
                                         const std::function<void(size_t, size_t)>& progress,
                                         const StreamingOptions& streaming) {
  const std::vector<PixelPair> pixels = pixelPairsOf(tests);
  const PatchRows paired = PatchRows::pairedReferences(reference, counterparts);
  const PatchRows views = PatchRows::of(counterparts.patches);
  const ResponseKernels k = activeResponseKernels();
  tbb::enumerable_thread_specific<std::vector<uint32_t>> partial(std::vector<uint32_t>(tests.size(), 0));
  streamChunks(
      {&paired, &views}, streaming.chunkWords,
      [&](const std::vector<LaneChunk>& chunk) {
        const LaneChunk &a = chunk[0], &b = chunk[1];
        std::vector<uint32_t>& counts = partial.local();
        for (size_t d = 0; d < tests.size(); ++d) {
          const auto [p1, p2] = pixels[d];
          counts[d] += k.flips(a.row(p1), a.row(p2), b.row(p1), b.row(p2), a.words);
        }
      },
      progress);
  return sumCounts(partial, tests.size());
}

void evaluateColumns(const PatchLanes& lanes, const PixelPair* tests, size_t count, uint64_t* out) {
  const ResponseKernels k = activeResponseKernels();
  const size_t words = lanes.words();
  tbb::parallel_for(size_t(0), lanes.chunks(), [&](size_t c) {
    const LaneChunk chunk = lanes.chunk(c);
    for (size_t n = 0; n < count; ++n)
      k.lessMasks(chunk.row(tests[n].a), chunk.row(tests[n].b), chunk.words, out + n * words + chunk.firstWord);
  });
}

void evaluateFlipColumns(const PatchLanes& a, const PatchLanes& b, const PixelPair* tests, size_t count,
                         uint64_t* out) {
  if (a.rows() != b.rows() || a.chunks() != b.chunks())
    throw std::invalid_argument("evaluateFlipColumns: the two sides of the pairs differ in size");
  const ResponseKernels k = activeResponseKernels();
  const size_t words = a.words();
  tbb::parallel_for(size_t(0), a.chunks(), [&](size_t c) {
    const LaneChunk ca = a.chunk(c), cb = b.chunk(c);
    uint64_t other[64];
    for (size_t n = 0; n < count; ++n) {
      uint64_t* column = out + n * words + ca.firstWord;
      for (size_t w0 = 0; w0 < ca.words; w0 += 64) {
        const size_t len = std::min<size_t>(64, ca.words - w0);
        const size_t o = w0 * kLanes;
        k.lessMasks(ca.row(tests[n].a) + o, ca.row(tests[n].b) + o, len, column + w0);
        k.lessMasks(cb.row(tests[n].a) + o, cb.row(tests[n].b) + o, len, other);
        for (size_t w = 0; w < len; ++w) column[w0 + w] ^= other[w];
      }
    }
  });
}

}  // namespace mdbrief::train
