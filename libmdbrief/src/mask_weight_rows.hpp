#pragma once
// The mask weight kernel (mask_weight_kernels.hpp), shared by the portable and the POPCNT
// translation units: each includes it once and compiles it with its own flags, so popcount64
// (popcount.hpp) is the bit-parallel count in one and the POPCNT instruction in the other.
// Internal linkage keeps the two copies apart.
#include <cstring>

#include "mask_weight_kernels.hpp"
#include "popcount.hpp"

namespace mdbrief::mask_weight_kernels {
namespace {

// 64-bit popcounts plus a 32-bit tail word for odd word counts.
inline size_t maskWeightRows(const uint32_t* rows, size_t count, int nwords, const uint32_t* weightOfOnes,
                             uint32_t* weights) {
  const int nlong = nwords / 2;
  for (size_t i = 0; i < count; ++i) {
    const uint32_t* row = rows + i * static_cast<size_t>(nwords);
    int ones = 0;
    for (int k = 0; k < nlong; ++k) {
      uint64_t v;
      std::memcpy(&v, row + 2 * k, 8);
      ones += popcount64(v);
    }
    if (nwords % 2) ones += popcount64(row[nwords - 1]);
    if (ones == 0) return i;
    weights[i] = weightOfOnes[ones];
  }
  return count;
}

}  // namespace
}  // namespace mdbrief::mask_weight_kernels
