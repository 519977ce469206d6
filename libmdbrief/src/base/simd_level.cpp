#include "mdbrief/base/simd_level.hpp"

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>

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

// MDBRIEF_SIMD_LEVEL, read once: its cap, none when unset or empty, or why its value is no
// level.
struct EnvironmentCap {
  int width = -1;  // -1: no cap
  std::string problem;
};

const EnvironmentCap& environmentCap() {
  static const EnvironmentCap cap = [] {
    EnvironmentCap c;
    const char* env = std::getenv("MDBRIEF_SIMD_LEVEL");
    if (!env || !*env) return c;
    for (const auto& entry : kSimdLevelNames)
      if (std::string(env) == entry.name) {
        c.width = width(entry.value);
        return c;
      }
    std::string names;
    for (const auto& entry : kSimdLevelNames) names += (names.empty() ? "" : ", ") + std::string(entry.name);
    c.problem = "the environment variable MDBRIEF_SIMD_LEVEL is '" + std::string(env) + "', not a SIMD level: " +
                names + " (lower case), or unset it";
    return c;
  }();
  return cap;
}

// limitSimdLevel's cap, which replaces the environment's; -1 until it is called. constexpr
// initialised, so that no static initialiser of another file can run before it.
std::atomic<int> explicitWidth{-1};

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
  static const std::vector<SimdLevel> supported = supportedSimdLevels();
  int cap = explicitWidth.load(std::memory_order_relaxed);
  if (cap < 0) {
    const EnvironmentCap& environment = environmentCap();
    if (!environment.problem.empty()) throw std::invalid_argument(environment.problem);
    cap = environment.width < 0 ? width(SimdLevel::Avx512) : environment.width;
  }
  SimdLevel active = SimdLevel::Portable;
  for (const SimdLevel level : supported)
    if (width(level) <= cap) active = level;
  return active;
}

void limitSimdLevel(SimdLevel cap) { explicitWidth.store(width(cap), std::memory_order_relaxed); }

std::string activeSimdTargetName() { return hwy::TargetName(simd::activeTarget()); }

namespace simd {

int64_t activeTarget() { return bestTarget(runnableTargets() & targetsOf(activeSimdLevel())); }

}  // namespace simd

}  // namespace mdbrief
