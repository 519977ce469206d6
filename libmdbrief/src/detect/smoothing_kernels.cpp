// The pyramid's smoothing passes (smoothing_kernels.hpp) for every SIMD level: this file is
// compiled once per Highway target (hwy/foreach_target.h) and the active level's copy is chosen
// at run time (simd_dispatch.hpp). Vectors cover whole chunks of a row; the last few columns
// take the same integer arithmetic one at a time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "detect/smoothing_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include <utility>

#include "mdbrief/internal/base/simd_dispatch.hpp"
#include "detect/smoothing_kernels.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::smoothing_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The radius (rows) and the number of terms (columns) are template parameters, so that the taps
// unroll and the row pointers and weights stay in registers (a run-time radius took twice as
// long); RowPair and Columns pick the instantiation of theirs.

// Sums stay below 2^16 (weights sum to 256, pixels <= 255): 16-bit lanes wrap never. Two rows
// at once, stored less 32768 and interleaved (see smoothing_kernels.hpp): the column pass then
// multiplies and adds two rows per instruction where the CPU has one (pmaddwd).
template <int R>
void RowPairR(const uint16_t* upper, const uint16_t* lower, int cols, const uint32_t* w,
              uint16_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint16_t> d;
  const int n = static_cast<int>(hn::Lanes(d));
  uint16_t wk[R + 1];
  for (int k = 0; k <= R; ++k) wk[k] = static_cast<uint16_t>(w[k]);
  const auto row = [&](const uint16_t* centre, int x) {
    auto sum = hn::Mul(hn::Set(d, wk[0]), hn::LoadU(d, centre + x));
    for (int k = 1; k <= R; ++k)
      sum = hn::Add(sum, hn::Mul(hn::Set(d, wk[k]), hn::Add(hn::LoadU(d, centre + x - k), hn::LoadU(d, centre + x + k))));
    return hn::Xor(sum, hn::Set(d, uint16_t{0x8000}));
  };
  int x = 0;
  for (; x + n <= cols; x += n) hn::StoreInterleaved2(row(upper, x), row(lower, x), d, out + 2 * x);
  for (; x < cols; ++x) {
    for (int half = 0; half < 2; ++half) {
      const uint16_t* centre = half ? lower : upper;
      uint16_t sum = static_cast<uint16_t>(wk[0] * centre[x]);
      for (int k = 1; k <= R; ++k) sum = static_cast<uint16_t>(sum + wk[k] * (centre[x - k] + centre[x + k]));
      out[2 * x + half] = static_cast<uint16_t>(sum ^ 0x8000u);
    }
  }
}

// Each term's lane is we r'_even + wo r'_odd, with r' = r - 32768 in [-32768, 32512] and
// we, wo <= 32767 summing to at most 65536 over all terms: every partial sum lies in
// [-2^31, 2^31), so the signed 32-bit lanes never wrap, and adding back 32768 x the weights'
// sum (modulo 2^32) gives the unsigned sum below 65280 x 65536 + 2^15 < 2^32 exactly. The
// rounded value (<= 65280) then fits signed lanes, which narrow to bytes and convert to floats.
template <int T>
void ColumnsT(const uint16_t* const* pairs, const uint32_t* weights, int cols, uint8_t* HWY_RESTRICT bytes,
              float* HWY_RESTRICT floats) {
  const int16_t* p[T];
  uint32_t offset = 1u << 15;  // the rounding, plus 32768 x every weight (below)
  for (int t = 0; t < T; ++t) {
    p[t] = reinterpret_cast<const int16_t*>(pairs[t]);
    offset += 32768u * ((weights[t] & 0xffffu) + (weights[t] >> 16));
  }
  int x = 0;
#if HWY_TARGET != HWY_SCALAR  // one lane cannot hold a pair: the scalar loop below does it all
  const hn::ScalableTag<int32_t> d;
  const hn::Repartition<int16_t, decltype(d)> d16;
  const hn::Rebind<uint32_t, decltype(d)> du;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const hn::Rebind<float, decltype(d)> df;
  const int n = static_cast<int>(hn::Lanes(d));
  hn::Vec<decltype(d16)> wv[T];
  for (int t = 0; t < T; ++t) wv[t] = hn::BitCast(d16, hn::Set(du, weights[t]));
  for (; x + n <= cols; x += n) {
    auto sum0 = hn::Zero(d), sum1 = hn::Zero(d);
    for (int t = 0; t < T; ++t) sum0 = hn::ReorderWidenMulAccumulate(d, hn::LoadU(d16, p[t] + 2 * x), wv[t], sum0, sum1);
    const auto sum = hn::Add(hn::BitCast(du, hn::RearrangeToOddPlusEven(sum0, sum1)), hn::Set(du, offset));
    const auto fixed = hn::BitCast(d, hn::ShiftRight<16>(sum));
    hn::StoreU(hn::DemoteTo(d8, hn::ShiftRight<8>(hn::Add(fixed, hn::Set(d, 128)))), d8, bytes + x);
    if (floats) hn::StoreU(hn::Mul(hn::ConvertTo(df, fixed), hn::Set(df, kFixedToUnit)), df, floats + x);
  }
#endif
  for (; x < cols; ++x) {
    int32_t acc = 0;
    for (int t = 0; t < T; ++t)
      acc += static_cast<int32_t>(weights[t] & 0xffffu) * p[t][2 * x] + static_cast<int32_t>(weights[t] >> 16) * p[t][2 * x + 1];
    const uint32_t fixed = (static_cast<uint32_t>(acc) + offset) >> 16;
    bytes[x] = static_cast<uint8_t>((fixed + 128u) >> 8);
    if (floats) floats[x] = static_cast<float>(static_cast<int>(fixed)) * kFixedToUnit;
  }
}

template <int... R>
void RowPairOf(const uint16_t* upper, const uint16_t* lower, int cols, const uint32_t* w, int radius, uint16_t* out,
               std::integer_sequence<int, R...>) {
  using RowPair = void (*)(const uint16_t*, const uint16_t*, int, const uint32_t*, uint16_t*);
  static constexpr RowPair forRadius[] = {RowPairR<R>...};
  forRadius[radius](upper, lower, cols, w, out);
}

template <int... T>
void ColumnsOf(const uint16_t* const* pairs, const uint32_t* weights, int terms, int cols, uint8_t* bytes,
               float* floats, std::integer_sequence<int, T...>) {
  using Columns = void (*)(const uint16_t* const*, const uint32_t*, int, uint8_t*, float*);
  static constexpr Columns forTerms[] = {ColumnsT<T + 1>...};
  forTerms[terms - 1](pairs, weights, cols, bytes, floats);
}

void RowPair(const uint16_t* upper, const uint16_t* lower, int cols, const uint32_t* w, int radius, uint16_t* out) {
  RowPairOf(upper, lower, cols, w, radius, out, std::make_integer_sequence<int, kMaxRadius + 1>());
}

void Columns(const uint16_t* const* pairs, const uint32_t* weights, int terms, int cols, uint8_t* bytes,
             float* floats) {
  ColumnsOf(pairs, weights, terms, cols, bytes, floats, std::make_integer_sequence<int, kMaxTerms>());
}

void Widen(const uint8_t* in, int n, uint16_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint16_t> d;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const int lanes = static_cast<int>(hn::Lanes(d));
  int x = 0;
  for (; x + lanes <= n; x += lanes) hn::StoreU(hn::PromoteTo(d, hn::LoadU(d8, in + x)), d, out + x);
  for (; x < n; ++x) out[x] = in[x];
}

void PairRows(const uint8_t* upper, const uint8_t* lower, int cols, uint8_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint8_t> d;
  const int n = static_cast<int>(hn::Lanes(d));
  int x = 0;
  for (; x + n <= cols; x += n) hn::StoreInterleaved2(hn::LoadU(d, upper + x), hn::LoadU(d, lower + x), d, out + 2 * x);
  for (; x < cols; ++x) out[2 * x] = upper[x], out[2 * x + 1] = lower[x];
}

// Lanes are the block's columns, 8 of them (5 kept) in 16-bit lanes for the row pass, whose sums
// stay below 2^16, and in 32-bit lanes for the column pass, whose sums stay below 2^32 (255 x
// 256 x 65536 + 2^15). The radius is a template parameter, as in RowPairR.
template <int R>
void Block5R(const uint8_t* const* rows, const uint32_t* w, const uint32_t* columnWeights, uint32_t* HWY_RESTRICT out) {
  constexpr int kLanes = 8;
  const hn::CappedTag<uint16_t, kLanes> d16;
  const hn::Rebind<uint8_t, decltype(d16)> d8;
  const hn::CappedTag<uint32_t, kLanes> d32;
  const hn::Rebind<uint16_t, decltype(d32)> d16for32;
  const int n16 = static_cast<int>(hn::Lanes(d16)), n32 = static_cast<int>(hn::Lanes(d32));
  uint16_t wk[R + 1];
  for (int k = 0; k <= R; ++k) wk[k] = static_cast<uint16_t>(w[k]);
  HWY_ALIGN uint16_t smoothedRows[2 * R + 5][kLanes];
  for (int t = 0; t < 2 * R + 5; ++t) {
    const uint8_t* centre = rows[t] + R;
    for (int j = 0; j < 5; j += n16) {
      auto sum = hn::Mul(hn::Set(d16, wk[0]), hn::PromoteTo(d16, hn::LoadU(d8, centre + j)));
      for (int k = 1; k <= R; ++k)
        sum = hn::Add(sum, hn::Mul(hn::Set(d16, wk[k]), hn::Add(hn::PromoteTo(d16, hn::LoadU(d8, centre + j - k)),
                                                               hn::PromoteTo(d16, hn::LoadU(d8, centre + j + k)))));
      hn::Store(sum, d16, &smoothedRows[t][j]);
    }
  }
  const auto row = [&](int t, int j) { return hn::PromoteTo(d32, hn::Load(d16for32, &smoothedRows[t][j])); };
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; j += n32) {
      auto sum = hn::Mul(hn::Set(d32, columnWeights[0]), row(i + R, j));
      for (int k = 1; k <= R; ++k)
        sum = hn::Add(sum, hn::Mul(hn::Set(d32, columnWeights[k]), hn::Add(row(i + R - k, j), row(i + R + k, j))));
      HWY_ALIGN uint32_t lanes[kLanes];
      hn::Store(hn::ShiftRight<16>(hn::Add(sum, hn::Set(d32, 1u << 15))), d32, lanes);
      for (int l = 0; l < n32 && j + l < 5; ++l) out[5 * i + j + l] = lanes[l];
    }
  }
}

template <int... R>
void Block5Of(const uint8_t* const* rows, int radius, const uint32_t* w, const uint32_t* columnWeights, uint32_t* out,
              std::integer_sequence<int, R...>) {
  using Block = void (*)(const uint8_t* const*, const uint32_t*, const uint32_t*, uint32_t*);
  static constexpr Block forRadius[] = {Block5R<R>...};
  forRadius[radius](rows, w, columnWeights, out);
}

void Block5(const uint8_t* const* rows, int radius, const uint32_t* w, const uint32_t* columnWeights, uint32_t* out) {
  Block5Of(rows, radius, w, columnWeights, out, std::make_integer_sequence<int, kMaxRadius + 1>());
}

SmoothingKernels Kernels() { return {Widen, RowPair, Columns, PairRows, Block5, HWY_TARGET}; }

}  // namespace mdbrief::smoothing_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::smoothing_kernels {

SmoothingKernels activeSmoothingKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

}  // namespace mdbrief::smoothing_kernels
#endif
