#pragma once
// Which instruction-set kernels the library runs. The library is compiled for the x86-64
// baseline; its hot loops (descriptor sampling, brute-force matching) also exist as AVX2 and
// AVX-512 kernels, chosen at run time from what the CPU supports, so one binary runs on any
// x86-64 and is fast on recent ones. Every level gives bit-identical results (tests check it).
// Builds for other CPUs, or with -DMDBRIEF_PORTABLE_KERNELS=ON, have only the portable level.
#include <string>

#include "mdbrief/enum_names.hpp"

namespace mdbrief {

enum class SimdLevel {
  Portable,  // plain C++ (x86-64 baseline on x86)
  Avx2,      // AVX2 + POPCNT
  Avx512,    // AVX-512 F/BW + VPOPCNTDQ (Ice Lake, Zen 4 and later)
};

// The highest level this CPU and this build support; detected once.
SimdLevel supportedSimdLevel();

// The level the kernels use now: the supported level, or lower after limitSimdLevel().
SimdLevel activeSimdLevel();

// Caps the level for the whole process (e.g. to compare kernels, or to rule one out). A cap
// above the supported level leaves the supported one. Calls in flight keep the level they
// started with: each call resolves its kernels once.
void limitSimdLevel(SimdLevel cap);

inline constexpr EnumName<SimdLevel> kSimdLevelNames[] = {
    {SimdLevel::Portable, "portable"}, {SimdLevel::Avx2, "avx2"}, {SimdLevel::Avx512, "avx512"}};
inline std::string toString(SimdLevel level) { return nameOf(level, kSimdLevelNames); }
inline SimdLevel parseSimdLevel(const std::string& name) { return parseName(name, kSimdLevelNames, "SIMD level"); }

}  // namespace mdbrief
