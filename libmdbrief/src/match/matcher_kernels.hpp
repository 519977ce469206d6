#pragma once
// Kernels of the brute-force matcher (matcher.cpp), of the vocabulary's descent (vocabulary.cpp)
// and of the guided matcher (guided_matcher.cpp): the two nearest train descriptors of one
// query, or its distances to a few chosen ones. Written once with Highway in
// matcher_kernels.cpp and compiled for every SIMD level (simd_level.hpp).
#include <cstdint>

namespace mdbrief::matcher_kernels {

constexpr int kMaxWords = 16;            // 32-bit words of the widest descriptor (512 bits)
constexpr uint32_t kNone = 0xFFFFFFFFu;  // above any distance

// Distances are plain Hamming or the masked fixed-point form (masked_hamming.hpp), both exact
// integers.
struct Nearest {
  uint32_t best = kNone;
  uint32_t second = kNone;
  int index = -1;
};

// One query row: words, effective mask words and mask weight w(o) (masked matching only).
struct QueryRow {
  uint32_t d[kMaxWords];
  uint32_t l[kMaxWords];
  uint32_t w = 0;
};

// The train side, packed once per call by matcher.cpp in the layout of the kernel. lanes = 1:
// row-major. lanes = L > 1: blocks of L descriptors, element (block b, word k, lane l) at
// [(b * nwords + k) * L + l], the padding lanes of the last block zero and excluded by `count`.
// mask and weight are null for plain matching.
struct TrainView {
  const uint32_t* desc = nullptr;
  const uint32_t* mask = nullptr;
  const uint32_t* weight = nullptr;
  int count = 0;
  int nwords = 0;
  int lanes = 1;
};

// Ties keep the lowest train index in every kernel, so all give the same result.
struct MatcherKernels {
  // Over a train set packed with `lanes` lanes.
  Nearest (*nearestTwo)(const QueryRow& q, const TrainView& t);
  int lanes;
  // Over a row-major train set (lanes = 1): for the few children of a vocabulary node.
  Nearest (*nearestTwoRows)(const QueryRow& q, const TrainView& t);
  // out[i] = distance to row rows[i] of a row-major train set (lanes = 1): for the few
  // candidates of a guided search, where packing them into blocks would cost more.
  void (*distancesRows)(const QueryRow& q, const TrainView& t, const int* rows, int count, uint32_t* out);  int64_t target = 0;  // the Highway target these kernels were compiled for (HWY_AVX2, ...)
};

// The kernels of the active SIMD level.
MatcherKernels activeMatcherKernels();

}  // namespace mdbrief::matcher_kernels
