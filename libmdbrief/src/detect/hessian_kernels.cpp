// The Hessian detector's loops (hessian_kernels.hpp) for every SIMD level: compiled once per
// Highway target (hwy/foreach_target.h), the active level's copy chosen at run time
// (simd_dispatch.hpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "detect/hessian_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include "detect/hessian_kernels.hpp"
#include "mdbrief/internal/simd_dispatch.hpp"

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

// One pass over the three rows: no dilated image is written and read back.
int Candidates(const float* above, const float* row, const float* below, int begin, int end, float threshold,
               int32_t* HWY_RESTRICT xs) {
  const hn::ScalableTag<float> d;
  const int n = static_cast<int>(hn::Lanes(d));
  const auto t = hn::Set(d, threshold);
  int count = 0, x = begin;
  for (; x + n <= end; x += n) {
    const auto v = hn::LoadU(d, row + x);
    const auto gate = hn::Gt(v, t);
    if (hn::AllFalse(d, gate)) continue;  // most of a textured level
    const auto side = hn::Max(hn::LoadU(d, row + x - 1), hn::LoadU(d, row + x + 1));
    const auto up = hn::Max(hn::Max(hn::LoadU(d, above + x - 1), hn::LoadU(d, above + x)), hn::LoadU(d, above + x + 1));
    const auto down = hn::Max(hn::Max(hn::LoadU(d, below + x - 1), hn::LoadU(d, below + x)), hn::LoadU(d, below + x + 1));
    const auto keep = hn::And(gate, hn::Ge(v, hn::Max(side, hn::Max(up, down))));
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
    if (!(v > threshold)) continue;
    bool top = true;
    for (int u = -1; u <= 1; ++u) top = top && v >= above[x + u] && v >= below[x + u];
    if (top && v >= row[x - 1] && v >= row[x + 1]) xs[count++] = x;
  }
  return count;
}

HessianKernels Kernels() { return {ResponseRow, Candidates}; }

}  // namespace mdbrief::hessian_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::hessian_kernels {

HWY_EXPORT(Kernels);

HessianKernels activeHessianKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels)(); }

}  // namespace mdbrief::hessian_kernels
#endif
