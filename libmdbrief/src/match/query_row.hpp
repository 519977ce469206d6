#pragma once
// Loading one descriptor row (and its mask) into the kernels' QueryRow (matcher_kernels.hpp),
// shared by the matcher and the vocabulary. Internal linkage, as popcount.hpp.
#include <algorithm>
#include <cstring>

#include "match/matcher_kernels.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "mdbrief/internal/base/popcount.hpp"

namespace mdbrief::matcher_kernels {
namespace {

// Reads 32-bit word k of a row (rows need not be aligned).
inline uint32_t rowWord(const uint8_t* row, int k) {
  uint32_t w;
  std::memcpy(&w, row + 4 * k, 4);
  return w;
}

// Effective mask words of one row (an all-zero mask acts as all ones) and its weight w(o).
inline uint32_t effectiveMaskWords(const uint8_t* mask, int nwords, uint32_t* out) {
  int ones = 0;
  for (int k = 0; k < nwords; ++k) {
    out[k] = rowWord(mask, k);
    ones += popcount64(out[k]);
  }
  if (ones == 0) std::fill(out, out + nwords, ~uint32_t{0});
  return maskWeight(ones, nwords * 32);
}

// Row `row` of desc, with its mask row when masks is not null.
inline QueryRow loadQueryRow(const cv::Mat& desc, const cv::Mat* masks, int row, int nwords) {
  QueryRow q;
  const uint8_t* p = desc.ptr<uint8_t>(row);
  for (int k = 0; k < nwords; ++k) q.d[k] = rowWord(p, k);
  if (masks) q.w = effectiveMaskWords(masks->ptr<uint8_t>(row), nwords, q.l);
  return q;
}

}  // namespace
}  // namespace mdbrief::matcher_kernels
