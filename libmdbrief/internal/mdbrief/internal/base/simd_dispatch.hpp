#pragma once
// Run-time choice of a kernel written once with Highway (mdbrief/base/simd_level.hpp). A kernel
// source compiles itself for every target through hwy/foreach_target.h, which puts each target's
// copy in its own namespace (HWY_NAMESPACE: N_AVX2, N_NEON, ...); MDBRIEF_ACTIVE_KERNELS(Fn)
// calls Fn of the active level's target. The library chooses the target itself, instead of
// HWY_DYNAMIC_DISPATCH's process-wide best, so that limitSimdLevel() and MDBRIEF_SIMD_LEVEL can
// lower it. Only Highway's public names are used: the target bits, HWY_TARGETS (which targets
// this build compiles; cmake/mdbrief_highway.cmake gives every kernel source the same) and the
// targets' namespaces; no dispatch table.
#include <cstdint>
#include <stdexcept>
#include <string>

#include <hwy/highway.h>

namespace mdbrief::simd {

// The Highway target (HWY_AVX2, HWY_NEON, ...) of the active level.
int64_t activeTarget();

// A target this build did not compile: a level's target that HWY_TARGETS lacks. (The bit, not
// hwy::TargetName: the AArch64 cross-build has Highway's headers only.)
[[noreturn]] inline void notCompiled(int64_t target) {
  throw std::logic_error("SIMD dispatch: the kernels were not compiled for Highway target bit " +
                         std::to_string(target));
}

}  // namespace mdbrief::simd

// One switch case per target of HWY_TARGETS, each calling FUNC of that target's namespace.
#if HWY_TARGETS & HWY_AVX3_DL
#define MDBRIEF_CASE_AVX3_DL(FUNC) case HWY_AVX3_DL: return N_AVX3_DL::FUNC();
#else
#define MDBRIEF_CASE_AVX3_DL(FUNC)
#endif
#if HWY_TARGETS & HWY_AVX3
#define MDBRIEF_CASE_AVX3(FUNC) case HWY_AVX3: return N_AVX3::FUNC();
#else
#define MDBRIEF_CASE_AVX3(FUNC)
#endif
#if HWY_TARGETS & HWY_AVX2
#define MDBRIEF_CASE_AVX2(FUNC) case HWY_AVX2: return N_AVX2::FUNC();
#else
#define MDBRIEF_CASE_AVX2(FUNC)
#endif
#if HWY_TARGETS & HWY_SSE4
#define MDBRIEF_CASE_SSE4(FUNC) case HWY_SSE4: return N_SSE4::FUNC();
#else
#define MDBRIEF_CASE_SSE4(FUNC)
#endif
#if HWY_TARGETS & HWY_NEON
#define MDBRIEF_CASE_NEON(FUNC) case HWY_NEON: return N_NEON::FUNC();
#else
#define MDBRIEF_CASE_NEON(FUNC)
#endif
#if HWY_TARGETS & HWY_EMU128
#define MDBRIEF_CASE_EMU128(FUNC) case HWY_EMU128: return N_EMU128::FUNC();
#else
#define MDBRIEF_CASE_EMU128(FUNC)
#endif
#if HWY_TARGETS & HWY_SCALAR
#define MDBRIEF_CASE_SCALAR(FUNC) case HWY_SCALAR: return N_SCALAR::FUNC();
#else
#define MDBRIEF_CASE_SCALAR(FUNC)
#endif

// FUNC() of the active level's target; used where FUNC's target namespaces are visible (the
// HWY_ONCE part of the kernel source).
#define MDBRIEF_ACTIVE_KERNELS(FUNC)                                       \
  [] {                                                                     \
    const int64_t target = ::mdbrief::simd::activeTarget();                \
    switch (target) {                                                      \
      MDBRIEF_CASE_AVX3_DL(FUNC)                                           \
      MDBRIEF_CASE_AVX3(FUNC)                                              \
      MDBRIEF_CASE_AVX2(FUNC)                                              \
      MDBRIEF_CASE_SSE4(FUNC)                                              \
      MDBRIEF_CASE_NEON(FUNC)                                              \
      MDBRIEF_CASE_EMU128(FUNC)                                            \
      MDBRIEF_CASE_SCALAR(FUNC)                                            \
      default:                                                             \
        break;                                                             \
    }                                                                      \
    ::mdbrief::simd::notCompiled(target);                                  \
  }()
