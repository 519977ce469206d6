// The descriptor's sampling kernels (descriptor_kernels.hpp) for every SIMD level: compiled once
// per Highway target (hwy/foreach_target.h), the active level's copy chosen at run time
// (simd_dispatch.hpp). Integer sampling and exactly rounded placement give every level the same
// bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "describe/descriptor_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "describe/descriptor_kernels.hpp"
#include "mdbrief/internal/base/simd_dispatch.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::descriptor_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DI = hn::ScalableTag<int32_t>;

// One coordinate of the affine placement in 32-bit fixed point, with kFixedBits fractional bits of
// a sample unit (1/kSub px): integer lanes are twice as many as doubles, and a product is one
// multiplication. The offsets are integers, so the estimate is within 0.5 + 0.5 |qa| + 0.5 |qb|
// <= 16.5 fixed units of the exact value, and the double expression within 1/8 unit of it: the two
// round alike unless the estimate lies within kAmbiguous units of a rounding boundary, and those
// coordinates (one in 4000) are recomputed in double. Footprints wider than about 250 px take
// the double form throughout.
constexpr int kFixedBits = 18;
constexpr int32_t kAmbiguous = 32;
struct FixedAffine {
  int32_t whole;  // floor(c kSub)
  int32_t start;  // the rest of c kSub, plus one half, in fixed units
  int32_t a, b;   // a kSub, b kSub in fixed units
};

// Whether a coordinate with these coefficients stays inside 32-bit lanes (otherwise the double
// form places it): |start + a qa + b qb| < 2^31 and |c kSub| < 2^30.
bool FitsFixed(double c, double a, double b) {
  constexpr double unit = double{kSub} * (1 << kFixedBits);
  return std::abs(c) * kSub < 0x1p30 && (std::abs(a) + std::abs(b)) * unit * kMaxOffset < 0x1p30;
}

FixedAffine ToFixedAffine(double c, double a, double b) {
  constexpr double unit = double{kSub} * (1 << kFixedBits);
  // Any rounding to the nearest unit will do (the error bound above): floor(v + 0.5) inlines,
  // std::llround is a library call.
  const auto nearest = [](double v) { return static_cast<int32_t>(std::floor(v + 0.5)); };
  const double scaled = c * kSub, whole = std::floor(scaled);
  return {static_cast<int32_t>(whole), nearest((scaled - whole) * (1 << kFixedBits)) + (1 << (kFixedBits - 1)),
          nearest(a * unit), nearest(b * unit)};
}

// The double form: coefficients too large for the fixed point, ambiguous vectors, the tail.
void AffineCoordinateDouble(double c, double a, double b, const int32_t* qa, const int32_t* qb, int* out, int n) {
  for (int i = 0; i < n; ++i) out[i] = toFixed(c + a * qa[i] + b * qb[i]);
}

void AffinePoints(double cx, double cy, double m00, double m01, double m10, double m11, const int32_t* qa,
                  const int32_t* qb, int n, int* x, int* y) {
  const DI d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  // Fewer points than lanes (an offset box's corners): the vectors' set-up would cost more.
  if (n < lanes || !FitsFixed(cx, m00, m01) || !FitsFixed(cy, m10, m11)) {
    AffineCoordinateDouble(cx, m00, m01, qa, qb, x, n);
    AffineCoordinateDouble(cy, m10, m11, qa, qb, y, n);
    return;
  }
  const FixedAffine fx = ToFixedAffine(cx, m00, m01), fy = ToFixedAffine(cy, m10, m11);
  const auto xStart = hn::Set(d, fx.start), xa = hn::Set(d, fx.a), xb = hn::Set(d, fx.b), xWhole = hn::Set(d, fx.whole);
  const auto yStart = hn::Set(d, fy.start), ya = hn::Set(d, fy.a), yb = hn::Set(d, fy.b), yWhole = hn::Set(d, fy.whole);
  const auto shift = hn::Set(d, kAmbiguous), fraction = hn::Set(d, (1 << kFixedBits) - 1),
             near = hn::Set(d, 2 * kAmbiguous);
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto a = hn::LoadU(d, qa + i), b = hn::LoadU(d, qb + i);
    const auto vx = hn::Add(hn::Add(xStart, hn::Mul(xa, a)), hn::Mul(xb, b));
    const auto vy = hn::Add(hn::Add(yStart, hn::Mul(ya, a)), hn::Mul(yb, b));
    hn::StoreU(hn::Add(xWhole, hn::ShiftRight<kFixedBits>(vx)), d, x + i);
    hn::StoreU(hn::Add(yWhole, hn::ShiftRight<kFixedBits>(vy)), d, y + i);
    // Within kAmbiguous units of a boundary: (v + kAmbiguous) mod 2^kFixedBits < 2 kAmbiguous, for
    // x or y (the lesser of the two, both non-negative).
    const auto ambiguous =
        hn::Lt(hn::Min(hn::And(hn::Add(vx, shift), fraction), hn::And(hn::Add(vy, shift), fraction)), near);
    if (HWY_UNLIKELY(!hn::AllFalse(d, ambiguous))) {
      AffineCoordinateDouble(cx, m00, m01, qa + i, qb + i, x + i, lanes);
      AffineCoordinateDouble(cy, m10, m11, qa + i, qb + i, y + i, lanes);
    }
  }
  AffineCoordinateDouble(cx, m00, m01, qa + i, qb + i, x + i, n - i);
  AffineCoordinateDouble(cy, m10, m11, qa + i, qb + i, y + i, n - i);
}

// The four pixels around each position, from the row pairs (ImagePyramid::smoothedPairs): the 32
// bits at byte 2 x0 of pair row y0 hold I(x0, y0), I(x0, y0 + 1), I(x0 + 1, y0) and
// I(x0 + 1, y0 + 1), low byte first. One read per sample where the plain level takes two rows.
#if HWY_TARGET == HWY_AVX2 || HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL
HWY_INLINE hn::Vec<DI> Quads(const uint8_t* pairs, hn::Vec<DI> offset) {
  return hn::GatherOffset(DI(), reinterpret_cast<const int32_t*>(pairs), offset);
}
#else
// Without a gather instruction: one 32-bit read per lane inserted in the register (the loop
// unrolls to constant lanes). Highway's emulated gather goes through memory.
HWY_INLINE hn::Vec<DI> Quads(const uint8_t* pairs, hn::Vec<DI> offset) {
  const DI d;
  const hn::RebindToUnsigned<DI> du;
  // Unsigned offsets (a position inside the image has one): a lane read into a 32-bit register
  // is then an index as it stands, with no sign extension.
  HWY_ALIGN uint32_t at[hn::MaxLanes(d)];
  hn::Store(hn::BitCast(du, offset), du, at);
  auto quads = hn::Zero(du);
#pragma GCC unroll 16
  for (size_t i = 0; i < hn::MaxLanes(d); ++i) {
    uint32_t quad;
    std::memcpy(&quad, pairs + at[i], 4);
    quads = hn::InsertLane(quads, i, quad);
  }
  return hn::BitCast(d, quads);
}
#endif

// Bilinear samples of one vector of positions.
HWY_INLINE hn::Vec<DI> Bilinear(const uint8_t* pairs, int pairStep, const int* px, const int* py) {
  const DI d;
  const auto x = hn::LoadU(d, px), y = hn::LoadU(d, py);
  const auto mask = hn::Set(d, kSub - 1);
  const auto fx = hn::And(x, mask), fy = hn::And(y, mask);
  const auto offset = hn::Add(hn::Mul(hn::ShiftRight<kSubBits>(y), hn::Set(d, pairStep)),
                              hn::ShiftLeft<1>(hn::ShiftRight<kSubBits>(x)));
  const auto quads = Quads(pairs, offset);
#if HWY_TARGET == HWY_SCALAR
  // One lane holds no pair of 16-bit values: each corner on its own. A logical shift for the top
  // byte: the lanes are signed, the pixels are not.
  const hn::RebindToUnsigned<DI> du;
  const auto lo = hn::Set(d, 0xff);
  const auto p00 = hn::And(quads, lo), p10 = hn::And(hn::ShiftRight<8>(quads), lo);
  const auto p01 = hn::And(hn::ShiftRight<16>(quads), lo);
  const auto p11 = hn::BitCast(d, hn::ShiftRight<24>(hn::BitCast(du, quads)));
  // a (kSub - f) + b f = a kSub + f (b - a): one multiplication per interpolation.
  const auto top = hn::Add(hn::ShiftLeft<kSubBits>(p00), hn::Mul(fx, hn::Sub(p01, p00)));
  const auto bottom = hn::Add(hn::ShiftLeft<kSubBits>(p10), hn::Mul(fx, hn::Sub(p11, p10)));
#else
  // Bytes 0 and 2 of each lane (I(x0, y0), I(x0 + 1, y0)) as two 16-bit values, and bytes 1 and 3
  // (the row below): each row's interpolation p0 (kSub - fx) + p1 fx is then one pairwise
  // multiply-add (pmaddwd on x86) against the weights (kSub - fx, fx), exactly the integers of
  // sampleBilinear. The products and their sums stay below 2^15.
  const hn::Repartition<int16_t, DI> d16;
  const auto bytes02 = hn::Set(d, 0x00ff00ff);
  const auto upper = hn::BitCast(d16, hn::And(quads, bytes02));
  const auto lower = hn::BitCast(d16, hn::And(hn::ShiftRight<8>(quads), bytes02));
  const auto weights = hn::BitCast(d16, hn::Add(hn::Sub(hn::Set(d, kSub), fx), hn::ShiftLeft<16>(fx)));
  const auto pairwise = [&](hn::Vec<decltype(d16)> p) {
    auto sum1 = hn::Zero(d);
    const auto sum0 = hn::ReorderWidenMulAccumulate(d, p, weights, hn::Zero(d), sum1);
    return hn::RearrangeToOddPlusEven(sum0, sum1);
  };
  const auto top = pairwise(upper), bottom = pairwise(lower);
#endif
  return hn::Add(hn::ShiftLeft<kSubBits>(top), hn::Mul(fy, hn::Sub(bottom, top)));
}

// Test d's bit is sample 1 < sample 2, bit d % 8 of byte d / 8: a vector of 8 or more lanes
// stores its mask bits as whole bytes, and 8 / lanes narrower vectors make one byte (their lanes
// divide 8, and nTests is a multiple of 32).
void PackBitsBilinear(const uint8_t* pairs, size_t pairStep, const int* x, const int* y, int nTests, uint8_t* out) {
  const DI d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const int s = static_cast<int>(pairStep);
  const auto less = [&](int t) {
    return hn::Lt(Bilinear(pairs, s, x + t, y + t), Bilinear(pairs, s, x + nTests + t, y + nTests + t));
  };
  if (lanes % 8 == 0) {
    for (int t = 0; t < nTests; t += lanes) hn::StoreMaskBits(d, less(t), out + t / 8);
    return;
  }
  for (int t = 0; t < nTests; t += 8) {
    unsigned byte = 0;
    for (int k = 0; k < 8; k += lanes) {
      uint8_t bits[8] = {};
      hn::StoreMaskBits(d, less(t + k), bits);
      byte |= unsigned{bits[0]} << k;
    }
    out[t / 8] = static_cast<uint8_t>(byte);
  }
}

bool AllInside(const int* x, const int* y, int n, int width, int height) {
  const DI d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  if (n < lanes) return allInsideImage(x, y, n, width, height);
  auto minX = hn::LoadU(d, x), maxX = minX, minY = hn::LoadU(d, y), maxY = minY;
  const auto take = [&](int i) {
    const auto vx = hn::LoadU(d, x + i), vy = hn::LoadU(d, y + i);
    minX = hn::Min(minX, vx), maxX = hn::Max(maxX, vx), minY = hn::Min(minY, vy), maxY = hn::Max(maxY, vy);
  };
  int i = lanes;
  for (; i + lanes <= n; i += lanes) take(i);
  if (i < n) take(n - lanes);  // overlaps the previous vector: min and max do not mind
  return hn::GetLane(hn::MinOfLanes(d, minX)) >= 0 && hn::GetLane(hn::MinOfLanes(d, minY)) >= 0 &&
         hn::GetLane(hn::MaxOfLanes(d, maxX)) < (width - 1) * kSub &&
         hn::GetLane(hn::MaxOfLanes(d, maxY)) < (height - 1) * kSub;
}

// Each product is at most 255 * 32^2 * 15 (radius 15); 32-bit lanes take 256 vectors of them
// before they move to 64-bit sums, so even one lane (the portable level) never overflows.
void CentroidMoments(const uint8_t* pairs, size_t pairStep, const int* x, const int* y, const int* u, const int* v,
                     int n, long long& m10, long long& m01) {
  const DI d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const int s = static_cast<int>(pairStep);
  m10 = m01 = 0;
  int i = 0;
  while (i + lanes <= n) {
    auto a10 = hn::Zero(d), a01 = hn::Zero(d);
    for (int steps = 0; steps < 256 && i + lanes <= n; ++steps, i += lanes) {
      const auto val = Bilinear(pairs, s, x + i, y + i);
      a10 = hn::Add(a10, hn::Mul(val, hn::LoadU(d, u + i)));
      a01 = hn::Add(a01, hn::Mul(val, hn::LoadU(d, v + i)));
    }
    HWY_ALIGN int32_t l10[hn::MaxLanes(d)], l01[hn::MaxLanes(d)];
    hn::Store(a10, d, l10);
    hn::Store(a01, d, l01);
    for (int k = 0; k < lanes; ++k) m10 += l10[k], m01 += l01[k];
  }
  for (; i < n; ++i) {
    const long long val = sampleBilinearPairs(pairs, pairStep, x[i], y[i]);
    m10 += val * u[i];
    m01 += val * v[i];
  }
}

SamplingKernels Kernels() { return {AffinePoints, PackBitsBilinear, AllInside, CentroidMoments, HWY_TARGET}; }

}  // namespace mdbrief::descriptor_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::descriptor_kernels {

SamplingKernels activeSamplingKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

}  // namespace mdbrief::descriptor_kernels
#endif
