// The pyramid's smoothing passes (smoothing_kernels.hpp) for every SIMD level: this file is
// compiled once per Highway target (hwy/foreach_target.h) and the active level's copy is chosen
// at run time (simd_dispatch.hpp). Vectors cover whole chunks of a row; the last few columns
// take the same integer arithmetic one at a time.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "detect/smoothing_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include <utility>

#include "mdbrief/internal/simd_dispatch.hpp"
#include "detect/smoothing_kernels.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::smoothing_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The radius is a template parameter, so that the taps unroll and the row pointers and weights
// stay in registers (a run-time radius took twice as long); Rows and Columns pick the
// instantiation of theirs.

// Sums stay below 2^16 (weights sum to 256, pixels <= 255): 16-bit lanes wrap never.
template <int R>
void RowsR(const uint16_t* centre, int cols, const uint32_t* w, uint16_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint16_t> d;
  const int n = static_cast<int>(hn::Lanes(d));
  uint16_t wk[R + 1];
  for (int k = 0; k <= R; ++k) wk[k] = static_cast<uint16_t>(w[k]);
  int x = 0;
  for (; x + n <= cols; x += n) {
    auto sum = hn::Mul(hn::Set(d, wk[0]), hn::LoadU(d, centre + x));
    for (int k = 1; k <= R; ++k)
      sum = hn::Add(sum, hn::Mul(hn::Set(d, wk[k]), hn::Add(hn::LoadU(d, centre + x - k), hn::LoadU(d, centre + x + k))));
    hn::StoreU(sum, d, out + x);
  }
  for (; x < cols; ++x) {
    uint16_t sum = static_cast<uint16_t>(wk[0] * centre[x]);
    for (int k = 1; k <= R; ++k) sum = static_cast<uint16_t>(sum + wk[k] * (centre[x - k] + centre[x + k]));
    out[x] = sum;
  }
}

// Sums below 65280 x 65536 + 2^15 < 2^32 in 32-bit lanes; the rounded value (<= 65280) then
// fits signed lanes, which narrow to bytes and convert to floats.
template <int R>
void ColumnsR(const uint16_t* const* rows, int cols, const uint32_t* w, uint8_t* HWY_RESTRICT bytes,
              float* HWY_RESTRICT floats) {
  const hn::ScalableTag<uint32_t> d;
  const hn::Rebind<uint16_t, decltype(d)> d16;
  const hn::Rebind<int32_t, decltype(d)> di;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const hn::Rebind<float, decltype(d)> df;
  const int n = static_cast<int>(hn::Lanes(d));
  const uint16_t* r[2 * R + 1];
  uint32_t wk[R + 1];
  for (int k = 0; k <= 2 * R; ++k) r[k] = rows[k];
  for (int k = 0; k <= R; ++k) wk[k] = w[k];
  const auto load = [&](const uint16_t* row, int x) { return hn::PromoteTo(d, hn::LoadU(d16, row + x)); };
  const float toUnit = 1.f / (256.f * 255.f);
  int x = 0;
  for (; x + n <= cols; x += n) {
    auto sum = hn::Mul(hn::Set(d, wk[0]), load(r[R], x));
    for (int k = 1; k <= R; ++k)
      sum = hn::Add(sum, hn::Mul(hn::Set(d, wk[k]), hn::Add(load(r[R - k], x), load(r[R + k], x))));
    const auto fixed = hn::BitCast(di, hn::ShiftRight<16>(hn::Add(sum, hn::Set(d, 1u << 15))));
    hn::StoreU(hn::DemoteTo(d8, hn::ShiftRight<8>(hn::Add(fixed, hn::Set(di, 128)))), d8, bytes + x);
    if (floats) hn::StoreU(hn::Mul(hn::ConvertTo(df, fixed), hn::Set(df, toUnit)), df, floats + x);
  }
  for (; x < cols; ++x) {
    uint32_t sum = wk[0] * r[R][x];
    for (int k = 1; k <= R; ++k) sum += wk[k] * (uint32_t{r[R - k][x]} + r[R + k][x]);
    const uint32_t fixed = (sum + (1u << 15)) >> 16;
    bytes[x] = static_cast<uint8_t>((fixed + 128u) >> 8);
    if (floats) floats[x] = static_cast<float>(static_cast<int>(fixed)) * toUnit;
  }
}

template <int... R>
void RowsOf(const uint16_t* centre, int cols, const uint32_t* w, int radius, uint16_t* out,
            std::integer_sequence<int, R...>) {
  using Row = void (*)(const uint16_t*, int, const uint32_t*, uint16_t*);
  static constexpr Row forRadius[] = {RowsR<R>...};
  forRadius[radius](centre, cols, w, out);
}

template <int... R>
void ColumnsOf(const uint16_t* const* rows, int cols, const uint32_t* w, int radius, uint8_t* bytes, float* floats,
               std::integer_sequence<int, R...>) {
  using Columns = void (*)(const uint16_t* const*, int, const uint32_t*, uint8_t*, float*);
  static constexpr Columns forRadius[] = {ColumnsR<R>...};
  forRadius[radius](rows, cols, w, bytes, floats);
}

void Rows(const uint16_t* centre, int cols, const uint32_t* w, int radius, uint16_t* out) {
  RowsOf(centre, cols, w, radius, out, std::make_integer_sequence<int, kMaxRadius + 1>());
}

void Columns(const uint16_t* const* rows, int cols, const uint32_t* w, int radius, uint8_t* bytes, float* floats) {
  ColumnsOf(rows, cols, w, radius, bytes, floats, std::make_integer_sequence<int, kMaxRadius + 1>());
}

void PairRows(const uint8_t* upper, const uint8_t* lower, int cols, uint8_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint8_t> d;
  const int n = static_cast<int>(hn::Lanes(d));
  int x = 0;
  for (; x + n <= cols; x += n) hn::StoreInterleaved2(hn::LoadU(d, upper + x), hn::LoadU(d, lower + x), d, out + 2 * x);
  for (; x < cols; ++x) out[2 * x] = upper[x], out[2 * x + 1] = lower[x];
}

SmoothingKernels Kernels() { return {Rows, Columns, PairRows}; }

}  // namespace mdbrief::smoothing_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::smoothing_kernels {

HWY_EXPORT(Kernels);

SmoothingKernels activeSmoothingKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels)(); }

}  // namespace mdbrief::smoothing_kernels
#endif
