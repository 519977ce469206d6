#include "mdbrief/base/simd_level.hpp"

#include <atomic>
#include <cstdlib>

#include <hwy/highway.h>

#include "mdbrief/internal/base/simd_dispatch.hpp"

namespace mdbrief {

namespace {

// The Highway targets that run a level's kernels, best first where a level has two.
int64_t targetsOf(SimdLevel level) {
  switch (level) {
    case SimdLevel::Portable: return HWY_SCALAR | HWY_EMU128;
    case SimdLevel::Sse4: return HWY_SSE4;
    case SimdLevel::Neon: return HWY_NEON;
    case SimdLevel::Avx2: return HWY_AVX2;
    case SimdLevel::Avx512: return HWY_AVX3_DL | HWY_AVX3;
  }
  return 0;
}

// The cap's order: levels of one width are equal, whatever the CPU family. constexpr, so that
// the cap below is initialised before any static initialiser of another file can set it.
constexpr int width(SimdLevel level) {
  switch (level) {
    case SimdLevel::Portable: return 0;
    case SimdLevel::Sse4:
    case SimdLevel::Neon: return 1;
    case SimdLevel::Avx2: return 2;
    case SimdLevel::Avx512: return 3;
  }
  return 0;
}

// The compiled targets (the same set in every kernel source: cmake/mdbrief_highway.cmake) this
// CPU runs. Highway's CPUID check also asks the OS whether it saves the wide registers (XCR0).
// Detected once: CPUID costs more than a kernel call on a small level.
int64_t runnableTargets() {
  static const int64_t runnable = [] {
#if HWY_ARCH_X86 && !defined(MDBRIEF_PORTABLE_KERNELS)
    const int64_t cpu = hwy::SupportedTargets();
#else
    // AArch64 always has NEON; builds for other CPUs, and portable builds, compile only what
    // their baseline runs.
    const int64_t cpu = HWY_TARGETS;
#endif
    return (cpu & HWY_TARGETS) | (HWY_TARGETS & targetsOf(SimdLevel::Portable));
  }();
  return runnable;
}

std::atomic<int> capWidth{width(SimdLevel::Avx512)};

// MDBRIEF_SIMD_LEVEL, parsed on the first kernel call; an unknown name throws there, and again
// on every later call (a static whose initialiser throws is initialised anew).
void applyEnvironmentCap() {
  static const bool applied = [] {
    if (const char* env = std::getenv("MDBRIEF_SIMD_LEVEL"); env && *env)
      capWidth.store(width(parseSimdLevel(env)), std::memory_order_relaxed);
    return true;
  }();
  (void)applied;
}

int64_t bestTarget(int64_t targets) { return targets & -targets; }  // lower bit = better

}  // namespace

std::vector<SimdLevel> supportedSimdLevels() {
  std::vector<SimdLevel> levels;
  for (const auto& entry : kSimdLevelNames)
    if (runnableTargets() & targetsOf(entry.value)) levels.push_back(entry.value);
  return levels;
}

SimdLevel supportedSimdLevel() {
  static const SimdLevel level = supportedSimdLevels().back();
  return level;
}

SimdLevel activeSimdLevel() {
  applyEnvironmentCap();
  static const std::vector<SimdLevel> supported = supportedSimdLevels();
  const int cap = capWidth.load(std::memory_order_relaxed);
  SimdLevel active = SimdLevel::Portable;
  for (const SimdLevel level : supported)
    if (width(level) <= cap) active = level;
  return active;
}

void limitSimdLevel(SimdLevel cap) {
  applyEnvironmentCap();  // so that a later first kernel call cannot override this cap
  capWidth.store(width(cap), std::memory_order_relaxed);
}

std::string activeSimdTargetName() { return hwy::TargetName(simd::activeTarget()); }

namespace simd {

int64_t activeTarget() { return bestTarget(runnableTargets() & targetsOf(activeSimdLevel())); }

}  // namespace simd

}  // namespace mdbrief
