#pragma once
// Patches transposed for the response kernels (comparison_response_kernels.hpp): 64 patches make one
// word, one byte per patch, so a test on 64 patches is one comparison of two 64-byte rows. The
// words are cut into chunks of a few words, and inside a chunk the layout is pixel-major (each
// pixel's bytes for all of the chunk's words in a row): a test reads two short contiguous rows,
// and a chunk stays in the L2 cache while every candidate is evaluated on it. The trainer either
// streams the chunks (each transposed, used and dropped: nothing as large as candidates x
// patches is ever held) or keeps all chunks of a set of patches to recompute the responses of
// the candidates a selection examines (docs/training.md "Trainer").
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace mdbrief::train {

// Patches: count x 32 x 32 uint8, row-major (pixel (x, y) of patch p at p*1024 + y*32 + x, the
// keypoint at (16, 16), as the offsets of comparison_set.hpp).
struct PatchMatrix {
  const uint8_t* pixels = nullptr;
  size_t count = 0;
};

// The matching pairs of the stability criteria: counterpart patch j is reference patch of[j]
// seen in a changed view.
struct Counterparts {
  PatchMatrix patches;
  const int32_t* of = nullptr;
};

// Block sizes of the streaming. The learned tests do not depend on them (tests/test_trainer.cpp
// trains with tiny blocks and with these), only time and memory do.
struct StreamingOptions {
  // 64-patch words per transposed chunk: one chunk stays in the L2 cache while every
  // candidate is evaluated on it (docs/training.md "Trainer").
  size_t chunkWords = 8;
  // Candidates whose responses are recomputed together (and, in the greedy walk, screened in
  // parallel between two sequential decisions).
  size_t candidateBatch = 2048;
};

// Which patch each bit position (row) of a response column holds, in order; 64 rows per word,
// the last word padded with zero bits.
class PatchRows {
 public:
  // Every patch, in order.
  static PatchRows of(const PatchMatrix& patches);
  // The reference patch of every pair, in pair order. Throws std::invalid_argument on no
  // counterparts or a reference index out of range.
  static PatchRows pairedReferences(const PatchMatrix& reference, const Counterparts& counterparts);
  // The rows of the given whole words (ascending, only the last may be the partial last word).
  PatchRows words(const std::vector<size_t>& words) const;

  size_t size() const { return patch_.size(); }
  size_t wordCount() const { return (patch_.size() + 63) / 64; }
  const uint8_t* patch(size_t row) const { return patch_[row]; }
  bool operator==(const PatchRows& other) const { return patch_ == other.patch_; }

 private:
  std::vector<const uint8_t*> patch_;
};

// Words [firstWord, firstWord + words) of a row set, pixel-major.
struct LaneChunk {
  size_t firstWord = 0;
  size_t words = 0;
  const uint8_t* lanes = nullptr;  // 1024 pixels x words x 64 bytes
  const uint8_t* row(size_t pixel) const { return lanes + pixel * words * 64; }
};

// Every chunk of a row set, kept (the size of the patches themselves, rounded up to 64).
class PatchLanes {
 public:
  PatchLanes(const PatchRows& rows, size_t chunkWords);
  size_t rows() const { return rows_; }
  size_t words() const { return words_; }
  size_t chunks() const { return (words_ + chunkWords_ - 1) / chunkWords_; }
  LaneChunk chunk(size_t c) const;

 private:
  size_t rows_ = 0, words_ = 0, chunkWords_ = 0;
  std::vector<uint8_t> lanes_;
};

// Streams the chunks of row sets of equal size: each chunk of every set is transposed into a
// buffer of the thread that handles it, then visit(the chunks, in set order) runs, in parallel
// (TBB) over the chunks. progress(done, total), if set, is called from the worker threads after
// each chunk, so it must be thread-safe. Throws std::invalid_argument if the sets differ in size.
void streamChunks(const std::vector<const PatchRows*>& sets, size_t chunkWords,
                  const std::function<void(const std::vector<LaneChunk>&)>& visit,
                  const std::function<void(size_t, size_t)>& progress = {});

}  // namespace mdbrief::train
