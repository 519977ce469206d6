#include "mdbrief/simd_level.hpp"

#include <atomic>

namespace mdbrief {

namespace {

SimdLevel detect() {
#if defined(MDBRIEF_X86_KERNELS)
  // libgcc/compiler-rt also check that the OS saves the AVX and AVX-512 registers (XCR0).
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512vpopcntdq"))
    return SimdLevel::Avx512;
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt")) return SimdLevel::Avx2;
#endif
  return SimdLevel::Portable;
}

std::atomic<SimdLevel> cap{SimdLevel::Avx512};

}  // namespace

SimdLevel supportedSimdLevel() {
  static const SimdLevel level = detect();
  return level;
}

SimdLevel activeSimdLevel() {
  const SimdLevel c = cap.load(std::memory_order_relaxed);
  const SimdLevel s = supportedSimdLevel();
  return c < s ? c : s;
}

void limitSimdLevel(SimdLevel level) { cap.store(level, std::memory_order_relaxed); }

}  // namespace mdbrief
