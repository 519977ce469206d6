// AVX-512 BW test-response kernels (test_response_kernels.hpp), compiled with -mavx512f
// -mavx512bw -mavx512vpopcntdq -mpopcnt.
#include <immintrin.h>

#include "trainer/test_response_kernels.hpp"

namespace mdbrief::train::kernels {
namespace {

uint64_t lessMask(const uint8_t* a, const uint8_t* b) {
  return _mm512_cmplt_epu8_mask(_mm512_loadu_si512(a), _mm512_loadu_si512(b));
}

}  // namespace

ResponseKernels avx512ResponseKernels() { return responseKernelsWith<lessMask>(); }

}  // namespace mdbrief::train::kernels
