#pragma once
// Run-time choice of a kernel written once with Highway (mdbrief/base/simd_level.hpp). A kernel
// source compiles itself for every target through hwy/foreach_target.h and exports one function
// that returns its kernels (HWY_EXPORT); MDBRIEF_ACTIVE_KERNELS(Fn)() calls that function of
// the active level's target. The library chooses the target itself, instead of
// HWY_DYNAMIC_DISPATCH's process-wide best, so that limitSimdLevel() and MDBRIEF_SIMD_LEVEL can
// lower it. Every kernel source is compiled with the same Highway definitions
// (cmake/mdbrief_highway.cmake), so HWY_TARGETS, and the table layout, is the same in each.
#include <cstddef>
#include <cstdint>

#include <hwy/highway.h>

namespace mdbrief::simd {

// The Highway target (HWY_AVX2, HWY_NEON, ...) of the active level.
int64_t activeTarget();

// The HWY_EXPORT table slot of `target`, as hwy::ChosenTarget computes it for the process-wide
// choice; the scalar fallback is the last slot.
inline size_t tableIndex(int64_t target) {
#if (HWY_TARGETS & (HWY_TARGETS - 1)) == 0
  (void)target;
  return 0;  // one target (a portable build): HWY_EXPORT's table has one slot
#else
  const int64_t chosen = HWY_CHOSEN_TARGET_SHIFT(target) | HWY_CHOSEN_TARGET_MASK_SCALAR;
  return hwy::Num0BitsBelowLS1Bit_Nonzero64(static_cast<uint64_t>(chosen & HWY_CHOSEN_TARGET_MASK_TARGETS));
#endif
}

}  // namespace mdbrief::simd

#define MDBRIEF_ACTIVE_KERNELS(FUNC) HWY_DISPATCH_TABLE(FUNC)[::mdbrief::simd::tableIndex(::mdbrief::simd::activeTarget())]
