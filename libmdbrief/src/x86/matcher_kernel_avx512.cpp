// The matcher's AVX-512 VPOPCNTDQ kernel (compiled with -mavx512f -mavx512bw -mavx512vpopcntdq):
// 16 train descriptors per step, query words broadcast, the per-lane two nearest kept in
// registers.
#include <immintrin.h>

#include "matcher_kernels.hpp"

namespace mdbrief::matcher_kernels {
namespace {

constexpr int kLanes = kAvx512Lanes;

// Lane l of the kernel sees trains l, l + 16, l + 32, ... in increasing order and keeps its
// own two nearest (strict < keeps the lowest index among ties). Merging the lanes afterwards
// gives the same result as one scan in index order.
Nearest mergeLanes(const uint32_t* best1, const uint32_t* best2, const int32_t* index1) {
  int win = -1;
  for (int l = 0; l < kLanes; ++l) {
    if (index1[l] < 0) continue;
    if (win < 0 || best1[l] < best1[win] || (best1[l] == best1[win] && index1[l] < index1[win])) {
      win = l;
    }
  }
  Nearest r;
  if (win < 0) return r;
  r.best = best1[win];
  r.index = index1[win];
  r.second = best2[win];
  for (int l = 0; l < kLanes; ++l) {
    if (l != win && best1[l] < r.second) r.second = best1[l];
  }
  return r;
}

template <bool Masked>
Nearest nearestTwo(const QueryRow& q, const TrainView& t) {
  const int nwords = t.nwords;
  const int blocks = (t.count + kLanes - 1) / kLanes;
  __m512i best1 = _mm512_set1_epi32(-1);
  __m512i best2 = _mm512_set1_epi32(-1);
  __m512i index1 = _mm512_set1_epi32(-1);
  __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512i step = _mm512_set1_epi32(kLanes);
  const __m512i none = _mm512_set1_epi32(-1);
  const __m512i qw = _mm512_set1_epi32(static_cast<int>(q.w));
  const int tail = t.count - (blocks - 1) * kLanes;
  const __mmask16 tailValid = static_cast<__mmask16>((1u << tail) - 1);
  const uint32_t* D = t.desc;
  const uint32_t* L = t.mask;
  for (int b = 0; b < blocks; ++b) {
    __m512i d;
    if constexpr (!Masked) {
      __m512i acc = _mm512_setzero_si512();
      for (int k = 0; k < nwords; ++k) {
        const __m512i x = _mm512_xor_si512(_mm512_loadu_si512(D + k * kLanes),
                                           _mm512_set1_epi32(static_cast<int>(q.d[k])));
        acc = _mm512_add_epi32(acc, _mm512_popcnt_epi32(x));
      }
      d = acc;
    } else {
      __m512i a = _mm512_setzero_si512();
      __m512i c = _mm512_setzero_si512();
      for (int k = 0; k < nwords; ++k) {
        const __m512i x = _mm512_xor_si512(_mm512_loadu_si512(D + k * kLanes),
                                           _mm512_set1_epi32(static_cast<int>(q.d[k])));
        a = _mm512_add_epi32(a, _mm512_popcnt_epi32(
                                    _mm512_and_si512(x, _mm512_set1_epi32(static_cast<int>(q.l[k])))));
        c = _mm512_add_epi32(c, _mm512_popcnt_epi32(
                                    _mm512_and_si512(x, _mm512_loadu_si512(L + k * kLanes))));
      }
      const __m512i tw = _mm512_loadu_si512(t.weight + static_cast<size_t>(b) * kLanes);
      d = _mm512_add_epi32(_mm512_mullo_epi32(a, qw), _mm512_mullo_epi32(c, tw));
      L += nwords * kLanes;
    }
    D += nwords * kLanes;
    if (b == blocks - 1) d = _mm512_mask_mov_epi32(none, tailValid, d);
    // Masked moves rather than _mm512_min_epu32, which trips GCC 12's -Wmaybe-uninitialized.
    const __mmask16 closer = _mm512_cmplt_epu32_mask(d, best1);
    const __mmask16 closerThanSecond = _mm512_cmplt_epu32_mask(d, best2);
    best2 = _mm512_mask_mov_epi32(_mm512_mask_mov_epi32(best2, closerThanSecond, d), closer, best1);
    best1 = _mm512_mask_mov_epi32(best1, closer, d);
    index1 = _mm512_mask_mov_epi32(index1, closer, lane);
    lane = _mm512_add_epi32(lane, step);
  }
  alignas(64) uint32_t b1[kLanes], b2[kLanes];
  alignas(64) int32_t i1[kLanes];
  _mm512_store_si512(b1, best1);
  _mm512_store_si512(b2, best2);
  _mm512_store_si512(i1, index1);
  return mergeLanes(b1, b2, i1);
}

}  // namespace

Nearest nearestTwoAvx512(const QueryRow& q, const TrainView& t) {
  return t.mask ? nearestTwo<true>(q, t) : nearestTwo<false>(q, t);
}

}  // namespace mdbrief::matcher_kernels
