#include "trainer/patch_lanes.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "mdbrief/describe/comparison_set.hpp"
#include "trainer/comparison_response_kernels.hpp"

namespace mdbrief::train {

namespace {

using kernels::kLanes;
constexpr size_t kPixels = kPatchSize * kPatchSize;

void checkChunkWords(size_t chunkWords) {
  if (chunkWords == 0) throw std::invalid_argument("patch lanes: chunkWords must be positive");
}

// Words [w0, w1) of `rows` into `lanes` (kPixels x (w1 - w0) x 64). Padding lanes are 0 in every
// pixel, so their bits are 0 (0 < 0 is false).
void transposeChunk(const PatchRows& rows, size_t w0, size_t w1, uint8_t* lanes) {
  const size_t words = w1 - w0, rowBytes = words * kLanes;
  if (rows.size() < w1 * kLanes) std::memset(lanes, 0, kPixels * rowBytes);
  for (size_t r = w0 * kLanes; r < std::min(rows.size(), w1 * kLanes); ++r) {
    const uint8_t* src = rows.patch(r);
    uint8_t* dst = lanes + (r / kLanes - w0) * kLanes + r % kLanes;
    for (size_t i = 0; i < kPixels; ++i) dst[i * rowBytes] = src[i];
  }
}

}  // namespace

PatchRows PatchRows::of(const PatchMatrix& patches) {
  PatchRows rows;
  rows.patch_.resize(patches.count);
  for (size_t p = 0; p < patches.count; ++p) rows.patch_[p] = patches.pixels + p * kPixels;
  return rows;
}

PatchRows PatchRows::pairedReferences(const PatchMatrix& reference, const Counterparts& counterparts) {
  const size_t n = counterparts.patches.count;
  if (n == 0 || !counterparts.of)
    throw std::invalid_argument("matching pairs: no counterparts, or their reference index is missing");
  PatchRows rows;
  rows.patch_.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const int32_t r = counterparts.of[j];
    if (r < 0 || static_cast<size_t>(r) >= reference.count)
      throw std::invalid_argument("matching pairs: counterpart " + std::to_string(j) + " names reference " +
                                  std::to_string(r) + " of " + std::to_string(reference.count));
    rows.patch_[j] = reference.pixels + static_cast<size_t>(r) * kPixels;
  }
  return rows;
}

PatchRows PatchRows::words(const std::vector<size_t>& words) const {
  PatchRows rows;
  for (size_t w : words)
    for (size_t r = w * kLanes; r < std::min(size(), (w + 1) * kLanes); ++r) rows.patch_.push_back(patch_[r]);
  return rows;
}

PatchLanes::PatchLanes(const PatchRows& rows, size_t chunkWords)
    : rows_(rows.size()), words_(rows.wordCount()), chunkWords_(chunkWords) {
  checkChunkWords(chunkWords);
  lanes_.resize(words_ * kLanes * kPixels);
  tbb::parallel_for(size_t(0), chunks(), [&](size_t c) {
    const size_t w0 = c * chunkWords_, w1 = std::min(words_, w0 + chunkWords_);
    transposeChunk(rows, w0, w1, lanes_.data() + w0 * kLanes * kPixels);
  });
}

LaneChunk PatchLanes::chunk(size_t c) const {
  const size_t w0 = c * chunkWords_, w1 = std::min(words_, w0 + chunkWords_);
  return {w0, w1 - w0, lanes_.data() + w0 * kLanes * kPixels};
}

void streamChunks(const std::vector<const PatchRows*>& sets, size_t chunkWords,
                  const std::function<void(const std::vector<LaneChunk>&)>& visit,
                  const std::function<void(size_t, size_t)>& progress) {
  checkChunkWords(chunkWords);
  if (sets.empty()) return;
  for (const PatchRows* s : sets)
    if (s->size() != sets.front()->size())
      throw std::invalid_argument("patch lanes: row sets of different sizes streamed together");
  const size_t words = sets.front()->wordCount(), chunks = (words + chunkWords - 1) / chunkWords;
  tbb::enumerable_thread_specific<std::vector<uint8_t>> buffers;
  std::atomic<size_t> done{0};
  tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
    const size_t w0 = c * chunkWords, w1 = std::min(words, w0 + chunkWords), bytes = (w1 - w0) * kLanes * kPixels;
    std::vector<uint8_t>& buffer = buffers.local();
    buffer.resize(sets.size() * chunkWords * kLanes * kPixels);
    std::vector<LaneChunk> chunk(sets.size());
    for (size_t s = 0; s < sets.size(); ++s) {
      uint8_t* lanes = buffer.data() + s * bytes;
      transposeChunk(*sets[s], w0, w1, lanes);
      chunk[s] = {w0, w1 - w0, lanes};
    }
    visit(chunk);
    const size_t n = ++done;
    if (progress) progress(n, chunks);
  });
}

}  // namespace mdbrief::train
