#pragma once
// Plain Hamming distance between binary descriptor rows (layout: descriptor.hpp).
// Widths are 4..64 bytes (32..512 bits) in steps of 4 bytes, so every width is a whole number
// of 32-bit words; the distance loop uses 64-bit popcounts plus one 32-bit tail word.
//
// A single pair is computed with scalar popcounts: for at most eight 64-bit words a SIMD
// horizontal reduction costs more than it saves. The brute-force matcher (matcher.hpp) is
// where SIMD pays: it compares one query against 16 train descriptors per instruction
// (simd_level.hpp).
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief {

inline constexpr int kMinDescriptorBytes = 4;
inline constexpr int kMaxDescriptorBytes = 64;

// Throws std::invalid_argument naming `name` unless m has no rows (0 x 0 or 0 x bytes) or is a
// CV_8UC1 matrix whose width is a multiple of 4 in [4, 64] bytes (so N x 0 is refused).
void validateDescriptorMatrix(const cv::Mat& m, const std::string& name);

// Hamming distance of two rows of `bytes` bytes. Unchecked hot-path form: `bytes` must be a
// multiple of 4 in [4, 64] (what validateDescriptorMatrix guarantees). Compiled in the library,
// not inline, so its code does not depend on the caller's compiler flags.
int hammingDistance(const uint8_t* a, const uint8_t* b, int bytes) noexcept;

// Checked form: a and b are single rows (1 x bytes, CV_8UC1) of the same width.
// Throws std::invalid_argument naming the argument otherwise.
int hammingDistance(const cv::Mat& a, const cv::Mat& b);

}  // namespace mdbrief
