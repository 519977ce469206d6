// Ones(v): the set bits of a 64-bit word, for kernel sources compiled once per Highway target
// (hwy/foreach_target.h). SSE4.2 implies POPCNT and AArch64 has CNT, so the builtin is one
// instruction there; the scalar target keeps the x86-64 baseline, where the builtin would be a
// libgcc call, and counts bit-parallel (popcount.hpp). Highway's -inl.h convention: the guard
// toggles, so that each target's pass includes it again.
#if defined(MDBRIEF_BIT_COUNT_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef MDBRIEF_BIT_COUNT_INL_H_
#undef MDBRIEF_BIT_COUNT_INL_H_
#else
#define MDBRIEF_BIT_COUNT_INL_H_
#endif

#include <hwy/highway.h>

#include "mdbrief/internal/base/popcount.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::HWY_NAMESPACE {

HWY_INLINE uint32_t Ones(uint64_t v) {
#if HWY_TARGET == HWY_SCALAR || HWY_TARGET == HWY_EMU128
  return static_cast<uint32_t>(popcount64(v));
#else
  return static_cast<uint32_t>(__builtin_popcountll(v));
#endif
}

}  // namespace mdbrief::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // MDBRIEF_BIT_COUNT_INL_H_
