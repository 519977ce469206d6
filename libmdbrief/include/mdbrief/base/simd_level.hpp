#pragma once
// Which instruction-set kernels the library runs. Each hot loop (smoothing, the Hessian response
// and its maxima, descriptor sampling, matching, mask weights) is written once with Google
// Highway and compiled for every level of the build's CPU family; the level is chosen at run time
// from what the CPU supports, so one binary runs on any CPU of its family and is fast on recent
// ones. Every level gives bit-identical results (tests check it, on x86 and on AArch64).
//
// The environment variable MDBRIEF_SIMD_LEVEL caps the level for the whole process, as
// limitSimdLevel() does. It is read once, at the first call that runs a kernel. A value that is
// no level name (they are lower case) makes every such call throw std::invalid_argument naming
// the variable, its value and the names, until limitSimdLevel() is called: an explicit level
// replaces the variable, whatever its value.
#include <string>
#include <vector>

#include "mdbrief/base/enum_names.hpp"

namespace mdbrief {

enum class SimdLevel {
  Portable,  // plain C++, one lane: any CPU, and builds with -DMDBRIEF_PORTABLE_KERNELS=ON
  Sse4,      // x86: SSE4.2 + CLMUL + AES, 128-bit (every x86-64 CPU since about 2010)
  Neon,      // AArch64: NEON, 128-bit (Raspberry Pi 4 and 5, Jetson, Apple, Graviton)
  Avx2,      // x86: AVX2 + BMI2 + F16C + FMA, 256-bit (the FMA is never used: same bits)
  Avx512,    // x86: AVX-512 F/VL/DQ/BW, 512-bit; with VPOPCNTDQ and the other Ice Lake
             // extensions (Ice Lake, Zen 4 and later) its bit counts are one instruction
};

// The highest level this CPU and this build support; detected once.
SimdLevel supportedSimdLevel();

// Every level this CPU and this build support, lowest first (Portable always).
std::vector<SimdLevel> supportedSimdLevels();

// The level the kernels use now: the highest supported level no wider than the cap
// (limitSimdLevel()'s, else the MDBRIEF_SIMD_LEVEL environment variable's). Throws
// std::invalid_argument for a bad MDBRIEF_SIMD_LEVEL when limitSimdLevel() was never called:
// tools call it first, to refuse the variable before any work.
SimdLevel activeSimdLevel();

// Caps the level for the whole process (e.g. to compare kernels, or to measure what a smaller
// CPU runs). The cap orders levels by width: Portable < Sse4 = Neon < Avx2 < Avx512, so a cap
// of avx2 on an ARM board gives neon, and a cap above the supported level leaves the supported
// one. Calls in flight keep the level they started with: each call resolves its kernels once.
// Replaces MDBRIEF_SIMD_LEVEL, a bad value included. Never throws.
void limitSimdLevel(SimdLevel cap);

// The Highway target name of the active level's kernels (e.g. "AVX3_DL", "AVX2", "SSE4",
// "NEON", "SCALAR"): what a benchmark reports beside the level.
std::string activeSimdTargetName();

inline constexpr EnumName<SimdLevel> kSimdLevelNames[] = {{SimdLevel::Portable, "portable"},
                                                           {SimdLevel::Sse4, "sse4"},
                                                           {SimdLevel::Neon, "neon"},
                                                           {SimdLevel::Avx2, "avx2"},
                                                           {SimdLevel::Avx512, "avx512"}};
inline std::string toString(SimdLevel level) { return nameOf(level, kSimdLevelNames); }
inline SimdLevel parseSimdLevel(const std::string& name) { return parseName(name, kSimdLevelNames, "SIMD level"); }

}  // namespace mdbrief
