// AVX2 forms of the descriptor's sampling kernels (descriptor_kernels.hpp), compiled with -mavx2
// and without FMA, so every product is rounded as in the portable form.
#include <immintrin.h>

#include "descriptor_kernels.hpp"

namespace mdbrief::descriptor_kernels {
namespace {

// GCC 12 does not vectorise the double -> int conversion, so it is written out.
void affineCoordinate(double c, double a, double b, const double* qa, const double* qb, int* out, int n) {
  int i = 0;
  const __m256d vc = _mm256_set1_pd(c), va = _mm256_set1_pd(a), vb = _mm256_set1_pd(b);
  const __m256d scale = _mm256_set1_pd(kSub), half = _mm256_set1_pd(0.5);
  for (; i + 4 <= n; i += 4) {
    const __m256d v = _mm256_add_pd(_mm256_add_pd(vc, _mm256_mul_pd(va, _mm256_loadu_pd(qa + i))),
                                    _mm256_mul_pd(vb, _mm256_loadu_pd(qb + i)));
    const __m256d f = _mm256_floor_pd(_mm256_add_pd(_mm256_mul_pd(v, scale), half));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm256_cvttpd_epi32(f));
  }
  for (; i < n; ++i) out[i] = toFixed(c + a * qa[i] + b * qb[i]);
}

// Eight bilinear samples at once with 32-bit gathers, staying inside the image buffer:
// the top row is read at x0 (pixels x0, x0 + 1 in the low bytes; the two bytes past them are
// at worst the start of row y0 + 1, which exists since allInside() keeps y0 + 1 <= height - 1);
// the bottom row, possibly the last one, is read at x0 - 2 (pixels in the high bytes; x0 - 2
// is at worst the end of row y0 >= 0).
inline __m256i bilinear8(const uint8_t* data, __m256i step, const int* px, const int* py) {
  const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(px));
  const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(py));
  const __m256i mask = _mm256_set1_epi32(kSub - 1), one = _mm256_set1_epi32(kSub), lo = _mm256_set1_epi32(0xff);
  const __m256i fx = _mm256_and_si256(x, mask), fy = _mm256_and_si256(y, mask);
  const __m256i idx = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srai_epi32(y, kSubBits), step),
                                       _mm256_srai_epi32(x, kSubBits));
  const __m256i w0 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(data), idx, 1);
  const __m256i w1 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(data),
                                            _mm256_add_epi32(idx, _mm256_sub_epi32(step, _mm256_set1_epi32(2))), 1);
  const __m256i gx = _mm256_sub_epi32(one, fx);
  const __m256i top = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_and_si256(w0, lo), gx),
                                       _mm256_mullo_epi32(_mm256_and_si256(_mm256_srli_epi32(w0, 8), lo), fx));
  const __m256i bottom = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_and_si256(_mm256_srli_epi32(w1, 16), lo), gx),
                                          _mm256_mullo_epi32(_mm256_srli_epi32(w1, 24), fx));
  return _mm256_add_epi32(_mm256_mullo_epi32(top, _mm256_sub_epi32(one, fy)), _mm256_mullo_epi32(bottom, fy));
}

// v1 < v2 per lane, lane d -> bit d of the byte.
void packBitsBilinear(const uint8_t* data, size_t step, const int* x, const int* y, int nTests, uint8_t* out) {
  const __m256i vstep = _mm256_set1_epi32(static_cast<int>(step));
  for (int d = 0; d < nTests; d += 8) {
    const __m256i v1 = bilinear8(data, vstep, x + d, y + d);
    const __m256i v2 = bilinear8(data, vstep, x + nTests + d, y + nTests + d);
    out[d / 8] = static_cast<uint8_t>(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(v2, v1))));
  }
}

// Per lane at most 89 samples (radius 15, step 1) of 255 * 32^2 * 15: far inside int32.
void centroidMoments(const uint8_t* data, size_t step, const int* x, const int* y, const int* u, const int* v,
                     int n, long long& m10, long long& m01) {
  const __m256i vstep = _mm256_set1_epi32(static_cast<int>(step));
  __m256i a10 = _mm256_setzero_si256(), a01 = _mm256_setzero_si256();
  for (int i = 0; i < n; i += 8) {
    const __m256i val = bilinear8(data, vstep, x + i, y + i);
    a10 = _mm256_add_epi32(a10, _mm256_mullo_epi32(val, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(u + i))));
    a01 = _mm256_add_epi32(a01, _mm256_mullo_epi32(val, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i))));
  }
  alignas(32) int l10[8], l01[8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(l10), a10);
  _mm256_store_si256(reinterpret_cast<__m256i*>(l01), a01);
  m10 = m01 = 0;
  for (int k = 0; k < 8; ++k) m10 += l10[k], m01 += l01[k];
}

}  // namespace

SamplingKernels avx2SamplingKernels() {
  return {affineCoordinate, packBitsBilinear, allInsideImage, centroidMoments};
}

}  // namespace mdbrief::descriptor_kernels
