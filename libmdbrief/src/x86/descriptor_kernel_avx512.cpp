// AVX-512 forms of the descriptor's placement and test kernels (descriptor_kernels.hpp), compiled
// with -mavx512f and without FMA; the bounds check and the centroid stay the AVX2 ones.
#include <immintrin.h>

#include "descriptor_kernels.hpp"

namespace mdbrief::descriptor_kernels {
namespace {

// GCC 12's plain forms of the shifts, the gather and the conversion start from an undefined
// register and warn about it (-Wmaybe-uninitialized); the masked forms with every lane set are
// the same instructions.
constexpr __mmask16 kAll = 0xffff;
inline __m512i sra(__m512i v, unsigned n) { return _mm512_maskz_srai_epi32(kAll, v, n); }
inline __m512i srl(__m512i v, unsigned n) { return _mm512_maskz_srli_epi32(kAll, v, n); }
inline __m512i gather(const uint8_t* data, __m512i idx) {
  return _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), kAll, idx, data, 1);
}

// Eight points per step. The same rounded operations as toFixed(c + a * qa + b * qb): scaling c,
// a and b by kSub (a power of two) scales every product and sum exactly, and the conversion
// rounding towards minus infinity is floor() and truncation in one instruction.
void affineCoordinate(double c, double a, double b, const double* qa, const double* qb, int* out, int n) {
  int i = 0;
  const __m512d vc = _mm512_set1_pd(c * kSub), va = _mm512_set1_pd(a * kSub), vb = _mm512_set1_pd(b * kSub);
  const __m512d half = _mm512_set1_pd(0.5);
  for (; i + 8 <= n; i += 8) {
    const __m512d v = _mm512_add_pd(_mm512_add_pd(vc, _mm512_mul_pd(va, _mm512_loadu_pd(qa + i))),
                                    _mm512_mul_pd(vb, _mm512_loadu_pd(qb + i)));
    const __m256i q = _mm512_maskz_cvt_roundpd_epi32(static_cast<__mmask8>(kAll), _mm512_add_pd(v, half),
                                                     _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + i), q);
  }
  for (; i < n; ++i) out[i] = toFixed(c + a * qa[i] + b * qb[i]);
}

// Sixteen bilinear samples at once, read as descriptor_kernel_avx2.cpp's bilinear8 reads them
// (two 32-bit gathers per sample that stay inside the image buffer).
inline __m512i bilinear16(const uint8_t* data, __m512i step, const int* px, const int* py) {
  const __m512i x = _mm512_loadu_si512(px), y = _mm512_loadu_si512(py);
  const __m512i mask = _mm512_set1_epi32(kSub - 1), one = _mm512_set1_epi32(kSub), lo = _mm512_set1_epi32(0xff);
  const __m512i fx = _mm512_and_si512(x, mask), fy = _mm512_and_si512(y, mask);
  const __m512i idx = _mm512_add_epi32(_mm512_mullo_epi32(sra(y, kSubBits), step), sra(x, kSubBits));
  const __m512i w0 = gather(data, idx);
  const __m512i w1 = gather(data, _mm512_add_epi32(idx, _mm512_sub_epi32(step, _mm512_set1_epi32(2))));
  const __m512i gx = _mm512_sub_epi32(one, fx);
  const __m512i top = _mm512_add_epi32(_mm512_mullo_epi32(_mm512_and_si512(w0, lo), gx),
                                       _mm512_mullo_epi32(_mm512_and_si512(srl(w0, 8), lo), fx));
  const __m512i bottom = _mm512_add_epi32(_mm512_mullo_epi32(_mm512_and_si512(srl(w1, 16), lo), gx),
                                          _mm512_mullo_epi32(srl(w1, 24), fx));
  return _mm512_add_epi32(_mm512_mullo_epi32(top, _mm512_sub_epi32(one, fy)), _mm512_mullo_epi32(bottom, fy));
}

// v1 < v2 per lane, lane d -> bit d of two bytes.
void packBitsBilinear(const uint8_t* data, size_t step, const int* x, const int* y, int nTests, uint8_t* out) {
  const __m512i vstep = _mm512_set1_epi32(static_cast<int>(step));
  for (int d = 0; d < nTests; d += 16) {
    const __m512i v1 = bilinear16(data, vstep, x + d, y + d);
    const __m512i v2 = bilinear16(data, vstep, x + nTests + d, y + nTests + d);
    const __mmask16 bits = _mm512_cmpgt_epi32_mask(v2, v1);
    out[d / 8] = static_cast<uint8_t>(bits);
    out[d / 8 + 1] = static_cast<uint8_t>(bits >> 8);
  }
}

}  // namespace

SamplingKernels avx512SamplingKernels() {
  SamplingKernels k = avx2SamplingKernels();
  k.affineCoordinate = affineCoordinate;
  k.packBitsBilinear = packBitsBilinear;
  return k;
}

}  // namespace mdbrief::descriptor_kernels
