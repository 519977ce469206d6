// Benchmarks run at the level named by MDBRIEF_SIMD_LEVEL (portable, avx2, avx512; default: the
// highest the CPU supports), so one build measures every kernel. The level in use is printed
// in the benchmark context.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "mdbrief/simd_level.hpp"

namespace {

const bool kLevelChosen = [] {
  if (const char* env = std::getenv("MDBRIEF_SIMD_LEVEL"); env && *env) {
    try {
      mdbrief::limitSimdLevel(mdbrief::parseSimdLevel(env));
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "MDBRIEF_SIMD_LEVEL: %s\n", e.what());
      std::exit(2);
    }
  }
  benchmark::AddCustomContext("mdbrief_simd_level", mdbrief::toString(mdbrief::activeSimdLevel()));
  return true;
}();

}  // namespace
