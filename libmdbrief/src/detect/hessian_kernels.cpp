// The Hessian detector's loops (hessian_kernels.hpp) for every SIMD level: compiled once per
// Highway target (hwy/foreach_target.h), the active level's copy chosen at run time
// (simd_dispatch.hpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "detect/hessian_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include <algorithm>

#include "detect/hessian_kernels.hpp"
#include "mdbrief/internal/base/simd_dispatch.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::hessian_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void ResponseRow(const float* a, const float* b, const float* c, int cols, float scale, float* HWY_RESTRICT out) {
  const hn::ScalableTag<float> d;
  const int n = static_cast<int>(hn::Lanes(d));
  const auto two = hn::Set(d, 2.f), quarter = hn::Set(d, 0.25f), s = hn::Set(d, scale);
  int x = 1;
  for (; x + n <= cols - 1; x += n) {
    const auto bx = hn::LoadU(d, b + x), twiceB = hn::Mul(two, bx);
    const auto dxx = hn::Sub(hn::Add(hn::LoadU(d, b + x - 1), hn::LoadU(d, b + x + 1)), twiceB);
    const auto dyy = hn::Sub(hn::Add(hn::LoadU(d, a + x), hn::LoadU(d, c + x)), twiceB);
    const auto dxy = hn::Mul(hn::Sub(hn::Sub(hn::LoadU(d, c + x + 1), hn::LoadU(d, c + x - 1)),
                                     hn::Sub(hn::LoadU(d, a + x + 1), hn::LoadU(d, a + x - 1))),
                             quarter);
    hn::StoreU(hn::Mul(hn::Sub(hn::Mul(dxx, dyy), hn::Mul(dxy, dxy)), s), d, out + x);
  }
  for (; x + 1 < cols; ++x) {
    const float dxx = (b[x - 1] + b[x + 1]) - 2.f * b[x];
    const float dyy = (a[x] + c[x]) - 2.f * b[x];
    const float dxy = ((c[x + 1] - c[x - 1]) - (a[x + 1] - a[x - 1])) * 0.25f;
    out[x] = (dxx * dyy - dxy * dxy) * scale;
  }
}

void RowMax3(const float* row, int cols, float* HWY_RESTRICT out) {
  const hn::ScalableTag<float> d;
  const int n = static_cast<int>(hn::Lanes(d));
  int x = 1;
  for (; x + n <= cols - 1; x += n)
    hn::StoreU(hn::Max(hn::Max(hn::LoadU(d, row + x - 1), hn::LoadU(d, row + x)), hn::LoadU(d, row + x + 1)), d,
               out + x);
  for (; x + 1 < cols; ++x) out[x] = std::max(std::max(row[x - 1], row[x]), row[x + 1]);
}

// Each row's maxima of three are computed once and serve three rows of candidates: a third of
// the comparisons of the 3x3 neighbourhood read pixel by pixel.
int Candidates(const float* row, const float* maxAbove, const float* maxRow, const float* maxBelow, int begin,
               int end, float threshold, int32_t* HWY_RESTRICT xs) {
  const hn::ScalableTag<float> d;
  const int n = static_cast<int>(hn::Lanes(d));
  const auto t = hn::Set(d, threshold);
  int count = 0, x = begin;
  for (; x + n <= end; x += n) {
    const auto v = hn::LoadU(d, row + x);
    const auto around = hn::Max(hn::Max(hn::LoadU(d, maxAbove + x), hn::LoadU(d, maxRow + x)), hn::LoadU(d, maxBelow + x));
    const auto keep = hn::And(hn::Gt(v, t), hn::Ge(v, around));
    if (hn::AllFalse(d, keep)) continue;
    // The few set lanes one by one: Highway's CompressStore copies its table to the stack on
    // every call (GCC 12), which took most of this loop's time.
    uint8_t bytes[8] = {};
    hn::StoreMaskBits(d, keep, bytes);
    uint64_t bits = 0;
    for (int b = 0; 8 * b < n; ++b) bits |= uint64_t{bytes[b]} << (8 * b);
    for (; bits; bits &= bits - 1) xs[count++] = x + __builtin_ctzll(bits);
  }
  for (; x < end; ++x) {
    const float v = row[x];
    if (v > threshold && v >= std::max(std::max(maxAbove[x], maxRow[x]), maxBelow[x])) xs[count++] = x;
  }
  return count;
}

void WeightedRows(const uint8_t* const* rows, int taps, const float* weights, int width, float* HWY_RESTRICT out) {
  const hn::ScalableTag<float> d;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const hn::Rebind<int32_t, decltype(d)> di;
  const int n = static_cast<int>(hn::Lanes(d));
  int c = 0;
  for (; c + n <= width; c += n) {
    auto sum = hn::Zero(d);
    for (int t = 0; t < taps; ++t) {
      const auto pixels = hn::ConvertTo(d, hn::PromoteTo(di, hn::LoadU(d8, rows[t] + c)));
      sum = hn::Add(sum, hn::Mul(hn::Set(d, weights[t]), pixels));
    }
    hn::StoreU(sum, d, out + c);
  }
  for (; c < width; ++c) {
    float sum = 0.f;
    for (int t = 0; t < taps; ++t) sum += weights[t] * static_cast<float>(rows[t][c]);
    out[c] = sum;
  }
}

void WeightedRow(const float* row, int taps, const float* weights, int width, float* HWY_RESTRICT out) {
  const hn::ScalableTag<float> d;
  const int n = static_cast<int>(hn::Lanes(d));
  int c = 0;
  for (; c + n <= width; c += n) {
    auto sum = hn::Zero(d);
    for (int t = 0; t < taps; ++t) sum = hn::Add(sum, hn::Mul(hn::Set(d, weights[t]), hn::LoadU(d, row + c + t)));
    hn::StoreU(sum, d, out + c);
  }
  for (; c < width; ++c) {
    float sum = 0.f;
    for (int t = 0; t < taps; ++t) sum += weights[t] * row[c + t];
    out[c] = sum;
  }
}

HessianKernels Kernels() { return {ResponseRow, RowMax3, Candidates, WeightedRows, WeightedRow, HWY_TARGET}; }

}  // namespace mdbrief::hessian_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::hessian_kernels {

HessianKernels activeHessianKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

}  // namespace mdbrief::hessian_kernels
#endif
