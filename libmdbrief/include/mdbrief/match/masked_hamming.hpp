#pragma once
// Masked Hamming distance of mdBRIEF (paper, section "Improving dBRIEF by On-line Mask
// Learning"):
//   H = (1/o_i) |l_i & x| + (1/o_j) |l_j & x|,   x = d_i xor d_j,  o = popcount(mask).
// H lies in [0, 2]. We report it scaled by nbits/2, in "bits", so that it is comparable with
// the plain Hamming distance: 0..nbits, and equal to it when both masks are all ones.
//
// Exact integer (fixed-point) form, used for every comparison (nearest neighbour, ratio test
// ordering):
//   w(o)  = round(2^21 * nbits / o)                     per descriptor, computed once
//   fixed = a * w(o_i) + b * w(o_j),  a = |l_i & x|, b = |l_j & x|      (uint32)
//   bits  = fixed / 2^22
// Why fixed point: integer compares are exact and deterministic (no float summation-order
// effects), fit the SIMD min/compare instructions of the matcher, and cost one multiply per
// side instead of a division.
// Range: a <= o, so a * w <= 2^21 * nbits + o/2 <= 2^30 + 256 and fixed < 2^32 for nbits <= 512.
// Exactness: with an all-ones mask w = 2^21 exactly, so two all-ones masks give exactly the
// plain Hamming distance. In general |w - 2^21 nbits / o| <= 1/2, hence
//   |bits - (nbits/2) H| <= (a + b) / 2 / 2^22 <= nbits / 2^22  (<= 1.2e-4 bits at 512 bits),
// plus float rounding of the reported value (relative 2^-24, <= 3.1e-5 bits at 512 bits).
// So two candidates whose exact distances differ by more than 2.5e-4 bits are ordered exactly.
//
// All-zero mask: no test of that descriptor is known to be stable, so we treat it as all ones
// (every bit counts, o = nbits) instead of dividing by zero or ignoring the descriptor; that
// side then contributes its plain Hamming distance.
#include <cstdint>

#include <opencv2/core.hpp>

namespace mdbrief {

inline constexpr int kMaskWeightShift = 21;             // w = 2^21 * nbits / o
inline constexpr int kMaskedDistanceShift = kMaskWeightShift + 1;  // bits = fixed / 2^22

// w(o) for a mask with `ones` set bits out of `nbits`; ones == 0 counts as ones == nbits.
// Unchecked: 0 <= ones <= nbits <= 512.
inline uint32_t maskWeight(int ones, int nbits) noexcept {
  if (ones == 0) ones = nbits;
  const uint64_t numerator = static_cast<uint64_t>(nbits) << kMaskWeightShift;
  return static_cast<uint32_t>((numerator + static_cast<uint64_t>(ones) / 2) / ones);
}

// Fixed-point distance -> bits (see above).
inline float maskedFixedToBits(uint32_t fixed) noexcept {
  return static_cast<float>(static_cast<double>(fixed) / (1u << kMaskedDistanceShift));
}

// Fixed-point masked distance of two rows of `bytes` bytes (multiple of 4 in [4, 64]); counts
// the masks' ones itself. Unchecked hot-path form.
uint32_t maskedHammingFixed(const uint8_t* di, const uint8_t* li, const uint8_t* dj,
                            const uint8_t* lj, int bytes) noexcept;

// Checked form in bits: all four are single rows (1 x bytes, CV_8UC1) of the same width.
// Throws std::invalid_argument naming the argument otherwise.
float maskedHammingDistance(const cv::Mat& di, const cv::Mat& li, const cv::Mat& dj,
                            const cv::Mat& lj);

}  // namespace mdbrief
