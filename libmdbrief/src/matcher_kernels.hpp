#pragma once
// Kernels of the brute-force matcher (matcher.cpp): the two nearest train descriptors of one
// query. One translation unit per instruction set, each compiled with its own target flags
// (libmdbrief/CMakeLists.txt) and chosen at run time (simd_level.hpp). Only plain data crosses
// this boundary, so no inline function or template of another header is emitted with AVX
// flags, where the linker could pick it for baseline code.
#include <cstdint>

namespace mdbrief::matcher_kernels {

constexpr int kMaxWords = 16;                // 32-bit words of the widest descriptor (512 bits)
constexpr uint32_t kNone = 0xFFFFFFFFu;      // above any distance
constexpr int kAvx512Lanes = 16;             // train descriptors per AVX-512 step

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
// row-major. lanes = 16: element (block b, word k, lane l) at [(b * nwords + k) * 16 + l], the
// padding lanes of the last block zero and excluded by `count`. mask and weight are null for
// plain matching.
struct TrainView {
  const uint32_t* desc = nullptr;
  const uint32_t* mask = nullptr;
  const uint32_t* weight = nullptr;
  int count = 0;
  int nwords = 0;
  int lanes = 1;
};

// Ties keep the lowest train index in every kernel, so all give the same result.
Nearest nearestTwoPortable(const QueryRow& q, const TrainView& t);  // lanes = 1
Nearest nearestTwoAvx2(const QueryRow& q, const TrainView& t);      // lanes = 1, POPCNT
Nearest nearestTwoAvx512(const QueryRow& q, const TrainView& t);    // lanes = 16

}  // namespace mdbrief::matcher_kernels
