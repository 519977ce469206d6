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

// Row b: the lanes whose bits are set in b, in increasing order (then zeros).
struct CompactionTable {
  uint8_t lanes[256][8];
};
constexpr CompactionTable MakeCompactionTable() {
  CompactionTable t{};
  for (int b = 0; b < 256; ++b)
    for (int l = 0, k = 0; l < 8; ++l)
      if ((b >> l) & 1) t.lanes[b][k++] = static_cast<uint8_t>(l);
  return t;
}
constexpr CompactionTable kCompaction = MakeCompactionTable();

// Each row's maxima of three are computed once and serve three rows of candidates: a third of
// the comparisons of the 3x3 neighbourhood read pixel by pixel.
int Candidates(const float* row, const float* maxAbove, const float* maxRow, const float* maxBelow, int begin,
               int end, float threshold, int32_t* HWY_RESTRICT xs) {
  const hn::ScalableTag<float> d;
  // Eight lanes of the mask at a time (four at 128 bits), as the table's indices widened.
  const hn::CappedTag<int32_t, 8> di;
  const hn::Rebind<uint8_t, decltype(di)> d8;
  const int n = static_cast<int>(hn::Lanes(d)), ni = static_cast<int>(hn::Lanes(di));
  const auto t = hn::Set(d, threshold);
  int count = 0, x = begin;
  for (; x + n <= end; x += n) {
    const auto v = hn::LoadU(d, row + x);
    const auto around = hn::Max(hn::Max(hn::LoadU(d, maxAbove + x), hn::LoadU(d, maxRow + x)), hn::LoadU(d, maxBelow + x));
    const auto keep = hn::And(hn::Gt(v, t), hn::Ge(v, around));
    // The set lanes' columns stored whole from a table and the count advanced by how many, for
    // every vector: no branch, where one vector in eight or so holds a candidate and no
    // predictor knows which (Highway's CompressStore copies its own table to the stack on every
    // call with GCC 12).
    uint8_t bytes[8] = {};
    hn::StoreMaskBits(d, keep, bytes);
    for (int b = 0; b * ni < n; ++b) {
      const unsigned bits = ni == 8 ? bytes[b] : (bytes[b * ni / 8] >> (b * ni % 8)) & ((1u << ni) - 1);
      hn::StoreU(hn::Add(hn::PromoteTo(di, hn::LoadU(d8, kCompaction.lanes[bits])), hn::Set(di, x + b * ni)), di,
                 xs + count);
      count += __builtin_popcount(bits);
    }
  }
  for (; x < end; ++x) {
    const float v = row[x];
    if (v > threshold && v >= std::max(std::max(maxAbove[x], maxRow[x]), maxBelow[x])) xs[count++] = x;
  }
  return count;
}

// Five rows' sums at a time, each from one conversion of the pixels it shares with the others:
// independent sums, where one row after another would wait on each addition in turn.
void GaussianBlock5(const uint8_t* const* rows, int taps, const float* weights, float* HWY_RESTRICT out) {
  const hn::CappedTag<float, kBlockLanes> d;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const hn::Rebind<int32_t, decltype(d)> di;
  const int n = static_cast<int>(hn::Lanes(d)), width = blockReadWidth(taps);
  HWY_ALIGN float vertical[5][blockReadWidth(kMaxBlockTaps)];
  // Sum i takes row q at tap q - i, so that each sum still adds its taps in their order.
  const auto add = [&](auto sum, int t, auto pixels) {
    return t >= 0 && t < taps ? hn::Add(sum, hn::Mul(hn::Set(d, weights[t]), pixels)) : sum;
  };
  for (int c = 0; c < width; c += n) {
    auto s0 = hn::Zero(d), s1 = s0, s2 = s0, s3 = s0, s4 = s0;
    const auto pixels = [&](int q) { return hn::ConvertTo(d, hn::PromoteTo(di, hn::LoadU(d8, rows[q] + c))); };
    const auto edgeRow = [&](int q) {
      const auto p = pixels(q);
      s0 = add(s0, q, p), s1 = add(s1, q - 1, p), s2 = add(s2, q - 2, p), s3 = add(s3, q - 3, p), s4 = add(s4, q - 4, p);
    };
    // The first and last four rows, which some sums skip; in between, every sum takes each row.
    for (int q = 0; q < 4; ++q) edgeRow(q);
    for (int q = 4; q < taps; ++q) {
      const auto p = pixels(q);
      s0 = hn::Add(s0, hn::Mul(hn::Set(d, weights[q]), p)), s1 = hn::Add(s1, hn::Mul(hn::Set(d, weights[q - 1]), p));
      s2 = hn::Add(s2, hn::Mul(hn::Set(d, weights[q - 2]), p)), s3 = hn::Add(s3, hn::Mul(hn::Set(d, weights[q - 3]), p));
      s4 = hn::Add(s4, hn::Mul(hn::Set(d, weights[q - 4]), p));
    }
    for (int q = std::max(4, taps); q < taps + 4; ++q) edgeRow(q);
    hn::Store(s0, d, vertical[0] + c), hn::Store(s1, d, vertical[1] + c), hn::Store(s2, d, vertical[2] + c);
    hn::Store(s3, d, vertical[3] + c), hn::Store(s4, d, vertical[4] + c);
  }
  for (int j = 0; j < 5; j += n) {
    auto s0 = hn::Zero(d), s1 = s0, s2 = s0, s3 = s0, s4 = s0;
    for (int t = 0; t < taps; ++t) {
      const auto w = hn::Set(d, weights[t]);
      s0 = hn::Add(s0, hn::Mul(w, hn::LoadU(d, vertical[0] + j + t)));
      s1 = hn::Add(s1, hn::Mul(w, hn::LoadU(d, vertical[1] + j + t)));
      s2 = hn::Add(s2, hn::Mul(w, hn::LoadU(d, vertical[2] + j + t)));
      s3 = hn::Add(s3, hn::Mul(w, hn::LoadU(d, vertical[3] + j + t)));
      s4 = hn::Add(s4, hn::Mul(w, hn::LoadU(d, vertical[4] + j + t)));
    }
    HWY_ALIGN float sums[5][kBlockLanes];
    hn::Store(s0, d, sums[0]), hn::Store(s1, d, sums[1]), hn::Store(s2, d, sums[2]);
    hn::Store(s3, d, sums[3]), hn::Store(s4, d, sums[4]);
    for (int i = 0; i < 5; ++i)
      for (int l = 0; l < n && j + l < 5; ++l) out[5 * i + j + l] = sums[i][l];
  }
}

HessianKernels Kernels() { return {ResponseRow, RowMax3, Candidates, GaussianBlock5, HWY_TARGET}; }

}  // namespace mdbrief::hessian_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::hessian_kernels {

HessianKernels activeHessianKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

}  // namespace mdbrief::hessian_kernels
#endif
