// The descriptor's sampling kernels (descriptor_kernels.hpp) for every SIMD level: compiled once
// per Highway target (hwy/foreach_target.h), the active level's copy chosen at run time
// (simd_dispatch.hpp). Integer sampling and exactly rounded placement give every level the same
// bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "describe/descriptor_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include "describe/descriptor_kernels.hpp"
#include "mdbrief/internal/simd_dispatch.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::descriptor_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DI = hn::ScalableTag<int32_t>;

// The same rounded operations as toFixed(c + a * qa + b * qb): scaling c, a and b by kSub (a
// power of two) scales every product and sum exactly, and floor() of an integral value
// converts exactly.
void AffineCoordinate(double c, double a, double b, const double* qa, const double* qb, int* out, int n) {
  const hn::ScalableTag<double> d;
  const hn::Rebind<int32_t, decltype(d)> di;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const auto vc = hn::Set(d, c * kSub), va = hn::Set(d, a * kSub), vb = hn::Set(d, b * kSub), half = hn::Set(d, 0.5);
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto v = hn::Add(hn::Add(vc, hn::Mul(va, hn::LoadU(d, qa + i))), hn::Mul(vb, hn::LoadU(d, qb + i)));
    hn::StoreU(hn::DemoteTo(di, hn::Floor(hn::Add(v, half))), di, out + i);
  }
  for (; i < n; ++i) out[i] = toFixed(c + a * qa[i] + b * qb[i]);
}

// Bilinear samples of one vector of positions, with two 32-bit reads per sample that stay inside
// the image buffer: the top row is read at x0 (pixels x0, x0 + 1 in the low bytes; the two
// bytes past them are at worst the start of row y0 + 1, which exists since allInside() keeps
// y0 + 1 <= height - 1); the bottom row, possibly the last one, is read at x0 - 2 (pixels in the
// high bytes; x0 - 2 is at worst the end of row y0 >= 0).
HWY_INLINE hn::Vec<DI> Bilinear(const uint8_t* data, int step, const int* px, const int* py) {
  const DI d;
  const auto x = hn::LoadU(d, px), y = hn::LoadU(d, py);
  const auto mask = hn::Set(d, kSub - 1), lo = hn::Set(d, 0xff);
  const auto fx = hn::And(x, mask), fy = hn::And(y, mask);
  const auto offset = hn::Add(hn::Mul(hn::ShiftRight<kSubBits>(y), hn::Set(d, step)), hn::ShiftRight<kSubBits>(x));
  const auto* base = reinterpret_cast<const int32_t*>(data);
  const auto w0 = hn::GatherOffset(d, base, offset);
  const auto w1 = hn::GatherOffset(d, base, hn::Add(offset, hn::Set(d, step - 2)));
  // Logical shifts of the high bytes: the lanes are signed, the pixels are not.
  const hn::RebindToUnsigned<DI> du;
  const auto w1u = hn::BitCast(du, w1);
  const auto p00 = hn::And(w0, lo), p01 = hn::And(hn::ShiftRight<8>(w0), lo);
  const auto p10 = hn::And(hn::BitCast(d, hn::ShiftRight<16>(w1u)), lo), p11 = hn::BitCast(d, hn::ShiftRight<24>(w1u));
  // a (kSub - f) + b f = a kSub + f (b - a) in integers: sampleBilinear's value with one
  // multiplication per interpolation instead of two.
  const auto top = hn::Add(hn::ShiftLeft<kSubBits>(p00), hn::Mul(fx, hn::Sub(p01, p00)));
  const auto bottom = hn::Add(hn::ShiftLeft<kSubBits>(p10), hn::Mul(fx, hn::Sub(p11, p10)));
  return hn::Add(hn::ShiftLeft<kSubBits>(top), hn::Mul(fy, hn::Sub(bottom, top)));
}

// Test d's bit is sample 1 < sample 2, bit d % 8 of byte d / 8. The mask bits of successive
// vectors gather in a 64-bit word written out byte by byte (the lanes divide 64, and nTests is a
// multiple of 32).
void PackBitsBilinear(const uint8_t* data, size_t step, const int* x, const int* y, int nTests, uint8_t* out) {
  const DI d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const int s = static_cast<int>(step);
  uint64_t word = 0;
  int gathered = 0;
  for (int t = 0; t < nTests; t += lanes) {
    uint8_t bits[8] = {};
    hn::StoreMaskBits(d, hn::Lt(Bilinear(data, s, x + t, y + t), Bilinear(data, s, x + nTests + t, y + nTests + t)),
                      bits);
    for (int b = 0; 8 * b < lanes; ++b) word |= uint64_t{bits[b]} << (gathered + 8 * b);
    gathered += lanes;
    if (gathered == 64 || t + lanes == nTests) {
      uint8_t* bytes = out + (t + lanes - gathered) / 8;
      for (int b = 0; 8 * b < gathered; ++b) bytes[b] = static_cast<uint8_t>(word >> (8 * b));
      word = 0;
      gathered = 0;
    }
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
void CentroidMoments(const uint8_t* data, size_t step, const int* x, const int* y, const int* u, const int* v,
                     int n, long long& m10, long long& m01) {
  const DI d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const int s = static_cast<int>(step);
  m10 = m01 = 0;
  int i = 0;
  while (i + lanes <= n) {
    auto a10 = hn::Zero(d), a01 = hn::Zero(d);
    for (int steps = 0; steps < 256 && i + lanes <= n; ++steps, i += lanes) {
      const auto val = Bilinear(data, s, x + i, y + i);
      a10 = hn::Add(a10, hn::Mul(val, hn::LoadU(d, u + i)));
      a01 = hn::Add(a01, hn::Mul(val, hn::LoadU(d, v + i)));
    }
    HWY_ALIGN int32_t l10[hn::MaxLanes(d)], l01[hn::MaxLanes(d)];
    hn::Store(a10, d, l10);
    hn::Store(a01, d, l01);
    for (int k = 0; k < lanes; ++k) m10 += l10[k], m01 += l01[k];
  }
  for (; i < n; ++i) {
    const long long val = sampleBilinear(data, step, x[i], y[i]);
    m10 += val * u[i];
    m01 += val * v[i];
  }
}

SamplingKernels Kernels() { return {AffineCoordinate, PackBitsBilinear, AllInside, CentroidMoments}; }

}  // namespace mdbrief::descriptor_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::descriptor_kernels {

HWY_EXPORT(Kernels);

SamplingKernels activeSamplingKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels)(); }

}  // namespace mdbrief::descriptor_kernels
#endif
