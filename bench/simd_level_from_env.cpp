// Benchmarks run at the level named by MDBRIEF_SIMD_LEVEL (portable, avx2, avx512; default: the
// highest the CPU supports), so one build measures every kernel. The level in use is printed
// in the benchmark context.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "mdbrief/simd_level.hpp"

namespace {

const bool kLevelChosen = [] {
  if (const char* env = std::getenv("MDBRIEF_SIMD_LEVEL"); env && *env) {
    bool known = false;
    for (const auto level : {mdbrief::SimdLevel::Portable, mdbrief::SimdLevel::Avx2, mdbrief::SimdLevel::Avx512})
      if (mdbrief::toString(level) == env) mdbrief::limitSimdLevel(level), known = true;
    if (!known) {
      std::fprintf(stderr, "MDBRIEF_SIMD_LEVEL=%s: expected portable, avx2 or avx512\n", env);
      std::exit(2);
    }
  }
  benchmark::AddCustomContext("mdbrief_simd_level", mdbrief::toString(mdbrief::activeSimdLevel()));
  return true;
}();

}  // namespace
