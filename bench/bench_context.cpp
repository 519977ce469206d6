// The benchmarks' context: the CPU, the SIMD level and its Highway target, so that every figure
// says where it was measured. The level is the one MDBRIEF_SIMD_LEVEL names (portable, sse4,
// neon, avx2, avx512; the library reads it; default: the highest the CPU supports), so one build
// measures every level.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "mdbrief/base/simd_level.hpp"
#include "toolkit/cpu_model.hpp"

namespace {

const bool kLevelChosen = [] {
  try {
    benchmark::AddCustomContext("mdbrief_simd_level", mdbrief::toString(mdbrief::activeSimdLevel()) + " (" +
                                                          mdbrief::activeSimdTargetName() + ")");
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "MDBRIEF_SIMD_LEVEL: %s\n", e.what());
    std::exit(2);
  }
  benchmark::AddCustomContext("cpu_model", mdbrief::toolkit::cpuModel());
  return true;
}();

}  // namespace
