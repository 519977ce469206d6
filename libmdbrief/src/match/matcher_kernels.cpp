// The matcher's kernels (matcher_kernels.hpp) for every SIMD level: compiled once per Highway
// target (hwy/foreach_target.h), the active level's copy chosen at run time (simd_dispatch.hpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "match/matcher_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include "mdbrief/internal/base/bit_count-inl.h"

#include <cstring>

#include "match/matcher_kernels.hpp"
#include "mdbrief/internal/base/simd_dispatch.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::matcher_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using mdbrief::HWY_NAMESPACE::Ones;  // mdbrief/internal/base/bit_count-inl.h

HWY_INLINE uint64_t LongWord(const uint32_t* p, int k) {
  uint64_t v;
  std::memcpy(&v, p + 2 * k, 8);
  return v;
}

HWY_INLINE void Keep(Nearest& n, uint32_t d, int j) {
  if (d < n.best) {  // strict: ties keep the lowest index
    n.second = n.best;
    n.best = d;
    n.index = j;
  } else if (d < n.second) {
    n.second = d;
  }
}

// The query's words as 64-bit words, read once per query.
struct LongQuery {
  uint64_t d[kMaxWords / 2], l[kMaxWords / 2];
};

template <bool Masked>
HWY_INLINE LongQuery LongWords(const QueryRow& q, int nwords) {
  LongQuery lq;
  std::memcpy(lq.d, q.d, sizeof(uint64_t) * (nwords / 2));
  if constexpr (Masked) std::memcpy(lq.l, q.l, sizeof(uint64_t) * (nwords / 2));
  return lq;
}

// Distance of the query to row-major train row j: 64-bit counts plus a 32-bit tail word for odd
// word counts.
template <bool Masked>
HWY_INLINE uint32_t RowDistance(const QueryRow& q, const LongQuery& lq, const TrainView& t, int j) {
  const int nwords = t.nwords, nlong = nwords / 2;
  const uint32_t* row = t.desc + static_cast<size_t>(j) * nwords;
  if constexpr (!Masked) {
    uint32_t d = 0;
    for (int k = 0; k < nlong; ++k) d += Ones(LongWord(row, k) ^ lq.d[k]);
    if (nwords & 1) d += Ones(row[nwords - 1] ^ q.d[nwords - 1]);
    return d;
  } else {
    const uint32_t* mask = t.mask + static_cast<size_t>(j) * nwords;
    uint32_t a = 0, c = 0;
    for (int k = 0; k < nlong; ++k) {
      const uint64_t x = LongWord(row, k) ^ lq.d[k];
      a += Ones(x & lq.l[k]);
      c += Ones(x & LongWord(mask, k));
    }
    if (nwords & 1) {
      const uint32_t x = row[nwords - 1] ^ q.d[nwords - 1];
      a += Ones(x & q.l[nwords - 1]);
      c += Ones(x & mask[nwords - 1]);
    }
    return a * q.w + c * t.weight[j];
  }
}

// One train row at a time in index order.
template <bool Masked>
Nearest RowsOf(const QueryRow& q, const TrainView& t) {
  const LongQuery lq = LongWords<Masked>(q, t.nwords);
  Nearest n;
  for (int j = 0; j < t.count; ++j) Keep(n, RowDistance<Masked>(q, lq, t, j), j);
  return n;
}

Nearest NearestTwoRows(const QueryRow& q, const TrainView& t) {
  return t.mask ? RowsOf<true>(q, t) : RowsOf<false>(q, t);
}

template <bool Masked>
void DistancesOf(const QueryRow& q, const TrainView& t, const int* rows, int count, uint32_t* out) {
  const LongQuery lq = LongWords<Masked>(q, t.nwords);
  for (int i = 0; i < count; ++i) out[i] = RowDistance<Masked>(q, lq, t, rows[i]);
}

void DistancesRows(const QueryRow& q, const TrainView& t, const int* rows, int count, uint32_t* out) {
  if (t.mask) {
    DistancesOf<true>(q, t, rows, count, out);
  } else {
    DistancesOf<false>(q, t, rows, count, out);
  }
}

#if HWY_TARGET == HWY_SCALAR
MatcherKernels Kernels() { return {NearestTwoRows, 1, NearestTwoRows, DistancesRows, HWY_TARGET}; }
#else

using DU = hn::ScalableTag<uint32_t>;

// Lane l of the block kernel sees trains l, l + L, l + 2L, ... in increasing order and keeps its
// own two nearest (strict < keeps the lowest index among ties); merging the lanes afterwards
// gives the same result as one scan in index order.
Nearest MergeLanes(const uint32_t* best1, const uint32_t* best2, const int32_t* index1, int lanes) {
  int win = -1;
  for (int l = 0; l < lanes; ++l) {
    if (index1[l] < 0) continue;
    if (win < 0 || best1[l] < best1[win] || (best1[l] == best1[win] && index1[l] < index1[win])) win = l;
  }
  Nearest r;
  if (win < 0) return r;
  r.best = best1[win];
  r.index = index1[win];
  r.second = best2[win];
  for (int l = 0; l < lanes; ++l)
    if (l != win && best1[l] < r.second) r.second = best1[l];
  return r;
}

// The four byte counts of each 32-bit lane summed (each at most 8 x 16 words = 128).
HWY_INLINE hn::Vec<DU> SumBytes(hn::Vec<hn::Repartition<uint8_t, DU>> counts) {
  const DU d;
  const hn::Repartition<uint16_t, DU> d16;
  const auto pairs = hn::BitCast(d16, counts);
  const auto halves = hn::BitCast(d, hn::Add(hn::And(pairs, hn::Set(d16, 0x00FF)), hn::ShiftRight<8>(pairs)));
  return hn::Add(hn::And(halves, hn::Set(d, 0xFFFFu)), hn::ShiftRight<16>(halves));
}

// One block of L train descriptors per step, the query's words broadcast; bits are counted per
// byte and summed per lane once per block.
template <bool Masked>
Nearest BlocksOf(const QueryRow& q, const TrainView& t) {
  const DU d;
  const hn::Repartition<uint8_t, DU> d8;
  const hn::RebindToSigned<DU> di;
  const int lanes = static_cast<int>(hn::Lanes(d)), nwords = t.nwords;
  const int blocks = (t.count + lanes - 1) / lanes;
  auto best1 = hn::Set(d, kNone), best2 = best1;
  auto index1 = hn::Set(di, -1), lane = hn::Iota(di, 0);
  const auto step = hn::Set(di, lanes);
  const auto qw = hn::Set(d, q.w);
  const uint32_t* D = t.desc;
  const uint32_t* L = t.mask;
  for (int b = 0; b < blocks; ++b, D += nwords * lanes) {
    auto a = hn::Zero(d8), c = hn::Zero(d8);
    for (int k = 0; k < nwords; ++k) {
      const auto x = hn::Xor(hn::LoadU(d, D + k * lanes), hn::Set(d, q.d[k]));
      if constexpr (Masked) {
        a = hn::Add(a, hn::PopulationCount(hn::BitCast(d8, hn::And(x, hn::Set(d, q.l[k])))));
        c = hn::Add(c, hn::PopulationCount(hn::BitCast(d8, hn::And(x, hn::LoadU(d, L + k * lanes)))));
      } else {
        a = hn::Add(a, hn::PopulationCount(hn::BitCast(d8, x)));
      }
    }
    auto dist = SumBytes(a);
    if constexpr (Masked) {
      dist = hn::Add(hn::Mul(dist, qw), hn::Mul(SumBytes(c), hn::LoadU(d, t.weight + static_cast<size_t>(b) * lanes)));
      L += nwords * lanes;
    }
    if (b == blocks - 1) dist = hn::IfThenElse(hn::FirstN(d, t.count - b * lanes), dist, hn::Set(d, kNone));
    const auto closer = hn::Lt(dist, best1);
    best2 = hn::IfThenElse(closer, best1, hn::IfThenElse(hn::Lt(dist, best2), dist, best2));
    best1 = hn::IfThenElse(closer, dist, best1);
    index1 = hn::IfThenElse(hn::RebindMask(di, closer), lane, index1);
    lane = hn::Add(lane, step);
  }
  HWY_ALIGN uint32_t b1[hn::MaxLanes(d)], b2[hn::MaxLanes(d)];
  HWY_ALIGN int32_t i1[hn::MaxLanes(d)];
  hn::Store(best1, d, b1);
  hn::Store(best2, d, b2);
  hn::Store(index1, di, i1);
  return MergeLanes(b1, b2, i1, lanes);
}

Nearest NearestTwoBlocks(const QueryRow& q, const TrainView& t) {
  return t.mask ? BlocksOf<true>(q, t) : BlocksOf<false>(q, t);
}

MatcherKernels Kernels() {
  return {NearestTwoBlocks, static_cast<int>(hn::Lanes(DU())), NearestTwoRows, DistancesRows, HWY_TARGET};
}
#endif

}  // namespace mdbrief::matcher_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::matcher_kernels {

MatcherKernels activeMatcherKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

}  // namespace mdbrief::matcher_kernels
#endif
