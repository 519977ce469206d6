#pragma once
// Plain Hamming distance between binary descriptor rows (layout: descriptor.hpp).
// Widths are 4..64 bytes (32..512 bits) in steps of 4 bytes, so every width is a whole number
// of 32-bit words; the distance loop uses 64-bit popcounts plus one 32-bit tail word.
//
// A single pair is computed with scalar popcounts: for at most eight 64-bit words a SIMD
// horizontal reduction costs more than it saves. The brute-force matcher (matcher.hpp) is
// where SIMD pays: it compares one query against 16 train descriptors per instruction.
#include <cstdint>
#include <cstring>
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief {

inline constexpr int kMinDescriptorBytes = 4;
inline constexpr int kMaxDescriptorBytes = 64;

// Throws std::invalid_argument naming `name` unless m is empty or a CV_8UC1 matrix whose width
// is a multiple of 4 in [4, 64] bytes.
void validateDescriptorMatrix(const cv::Mat& m, const std::string& name);

// With the POPCNT instruction compiled in, the builtin is one instruction. Without it (e.g.
// -DMDBRIEF_NATIVE_ARCH=OFF: x86-64 baseline) GCC turns the builtin into a libgcc call, which
// is slower in the matcher than this inline bit-parallel count (docs/matching.md).
inline int popcount64(uint64_t v) noexcept {
#if defined(__POPCNT__) || !defined(__x86_64__)
  return __builtin_popcountll(v);
#else
  v = v - ((v >> 1) & 0x5555555555555555ull);
  v = (v & 0x3333333333333333ull) + ((v >> 2) & 0x3333333333333333ull);
  v = (v + (v >> 4)) & 0x0F0F0F0F0F0F0F0Full;
  return static_cast<int>((v * 0x0101010101010101ull) >> 56);
#endif
}

// Hamming distance of two rows of `bytes` bytes. Unchecked hot-path form: `bytes` must be a
// multiple of 4 in [4, 64] (what validateDescriptorMatrix guarantees).
inline int hammingDistance(const uint8_t* a, const uint8_t* b, int bytes) noexcept {
  int distance = 0;
  int i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t x, y;  // memcpy: rows need not be 8-byte aligned
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    distance += popcount64(x ^ y);
  }
  if (i < bytes) {  // widths like 36 bytes end with one 32-bit word
    uint32_t x, y;
    std::memcpy(&x, a + i, 4);
    std::memcpy(&y, b + i, 4);
    distance += popcount64(x ^ y);
  }
  return distance;
}

// Checked form: a and b are single rows (1 x bytes, CV_8UC1) of the same width.
// Throws std::invalid_argument naming the argument otherwise.
int hammingDistance(const cv::Mat& a, const cv::Mat& b);

}  // namespace mdbrief
