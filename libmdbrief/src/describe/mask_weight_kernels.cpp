// The mask weight kernel (mask_weight_kernels.hpp) for every SIMD level: compiled once per
// Highway target (hwy/foreach_target.h), so that the bit count is one instruction wherever the
// target has it; the active level's copy is chosen at run time (simd_dispatch.hpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "describe/mask_weight_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include "mdbrief/internal/base/bit_count-inl.h"

#include <cstring>

#include "describe/mask_weight_kernels.hpp"
#include "mdbrief/internal/base/simd_dispatch.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::mask_weight_kernels::HWY_NAMESPACE {

using mdbrief::HWY_NAMESPACE::Ones;  // mdbrief/internal/base/bit_count-inl.h

// 64-bit counts plus a 32-bit tail word for odd word counts.
size_t Weights(const uint32_t* rows, size_t count, int nwords, const uint32_t* weightOfOnes, uint32_t* weights) {
  const int nlong = nwords / 2;
  for (size_t i = 0; i < count; ++i) {
    const uint32_t* row = rows + i * static_cast<size_t>(nwords);
    int ones = 0;
    for (int k = 0; k < nlong; ++k) {
      uint64_t v;
      std::memcpy(&v, row + 2 * k, 8);
      ones += Ones(v);
    }
    if (nwords % 2) ones += Ones(row[nwords - 1]);
    if (ones == 0) return i;
    weights[i] = weightOfOnes[ones];
  }
  return count;
}

MaskWeightKernels Kernel() { return {Weights, HWY_TARGET}; }

}  // namespace mdbrief::mask_weight_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::mask_weight_kernels {

MaskWeightKernels activeMaskWeights() { return MDBRIEF_ACTIVE_KERNELS(Kernel); }

}  // namespace mdbrief::mask_weight_kernels
#endif
