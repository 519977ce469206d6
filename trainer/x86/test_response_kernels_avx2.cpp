// AVX2 + POPCNT test-response kernels (test_response_kernels.hpp), compiled with -mavx2 -mpopcnt.
#include <immintrin.h>

#include "trainer/test_response_kernels.hpp"

namespace mdbrief::train::kernels {
namespace {

// a < b (unsigned) is max(a, b) != a: two 32-lane compares.
uint64_t lessMask(const uint8_t* a, const uint8_t* b) {
  uint64_t m = 0;
  for (int half = 0; half < 2; ++half) {
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(a + 32 * half));
    const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + 32 * half));
    const uint32_t notLess = static_cast<uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_max_epu8(x, y), x)));
    m |= static_cast<uint64_t>(~notLess) << (32 * half);
  }
  return m;
}

}  // namespace

ResponseKernels avx2ResponseKernels() { return responseKernelsWith<lessMask>(); }

}  // namespace mdbrief::train::kernels
