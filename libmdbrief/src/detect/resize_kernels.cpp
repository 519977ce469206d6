// The pyramid's bilinear reduction (resize_kernels.hpp) for every SIMD level: this file is
// compiled once per Highway target (hwy/foreach_target.h) and the active level's copy is chosen
// at run time (simd_dispatch.hpp).
//
// OpenCV 4.6's INTER_LINEAR on 8 bits (Debian's build: no IPP, no custom HAL), as measured
// against cv::resize (tests/test_resize_kernels.cpp): weights in 1/2048 from float positions; a
// horizontal pass per source row, exact in integers, H = S[sx] a0 + S[sx + 1] a1; then per
// output row, at every column, out = (mulhi(H0 / 16, b0) + mulhi(H1 / 16, b1) + 2) / 4, mulhi
// the high 16 bits of the product and each division rounded down. OpenCV's vector loop and its
// scalar tail share that form: every column of every width from 1 to 2100 matched it, none the
// exact (H0 b0 + H1 b1 + 2^21) / 2^22. H / 16 <= 32640 fits 16 bits, as it is kept here.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "detect/resize_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include <algorithm>
#include <cmath>

#include "mdbrief/internal/base/simd_dispatch.hpp"
#include "detect/border_reflect.hpp"
#include "detect/resize_kernels.hpp"

HWY_BEFORE_NAMESPACE();
namespace mdbrief::resize_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

int16_t Column(const uint8_t* src, const ColumnPlan& p, int x) {
  return static_cast<int16_t>((src[p.first[x]] * p.a0[x] + src[p.second[x]] * p.a1[x]) >> 4);
}

#if HWY_TARGET == HWY_SCALAR
void Columns(const uint8_t* src, const ColumnPlan& p, int16_t* HWY_RESTRICT out) {
  for (int x = 0; x < p.cols; ++x) out[x] = Column(src, p, x);
}
#else
// The 16-byte windows of consecutive blocks, one per 128-bit block of the vector.
template <class D>
HWY_INLINE hn::VFromD<D> LoadWindows(D d, const uint8_t* src, const int32_t* window) {
  if constexpr (hn::MaxLanes(D()) <= 16) {
    return hn::LoadU(d, src + window[0]);
  } else {
    const hn::Half<D> dh;
    return hn::Combine(d, LoadWindows(dh, src, window + hn::MaxLanes(dh) / 16), LoadWindows(dh, src, window));
  }
}

// The plan's arrays, held in registers across the row (through the plan, the compiler reloads
// them after every store).
struct Tables {
  const int32_t* window;
  const uint8_t *firstIndex, *secondIndex;
  const int16_t *high0, *low0, *high1, *low1;
  int cols;
};

// The blocks from b on, one per 128-bit block of d. Each block's pixels come from one load and
// two byte shuffles (no gather). With a = 16 high + low, H / 16 = S0 high0 + S1 high1 +
// (S0 low0 + S1 low1) / 16 exactly, and every term stays below 2^15: 16-bit lanes.
template <class D>
HWY_INLINE void Blocks(D d, const uint8_t* src, const Tables& t, int b, int16_t* HWY_RESTRICT out) {
  const hn::Repartition<uint8_t, D> d8;
  const int x = std::min(8 * b, t.cols - 8);
  const auto pixels = LoadWindows(d8, src, t.window + b);
  const auto s0 = hn::BitCast(d, hn::TableLookupBytesOr0(pixels, hn::LoadU(d8, t.firstIndex + 16 * b)));
  const auto s1 = hn::BitCast(d, hn::TableLookupBytesOr0(pixels, hn::LoadU(d8, t.secondIndex + 16 * b)));
  const auto high = hn::Add(hn::Mul(s0, hn::LoadU(d, t.high0 + x)), hn::Mul(s1, hn::LoadU(d, t.high1 + x)));
  const auto low = hn::Add(hn::Mul(s0, hn::LoadU(d, t.low0 + x)), hn::Mul(s1, hn::LoadU(d, t.low1 + x)));
  hn::StoreU(hn::Add(high, hn::ShiftRight<4>(low)), d, out + x);
}

void Columns(const uint8_t* src, const ColumnPlan& p, int16_t* HWY_RESTRICT out) {
  const hn::ScalableTag<int16_t> d;
  const hn::CappedTag<int16_t, 8> dBlock;
  const int perVector = static_cast<int>(hn::Lanes(d)) / 8;
  const int blocks = static_cast<int>(p.window.size());
  const int32_t* run = p.run.data();
  const Tables t{p.window.data(), p.firstIndex.data(), p.secondIndex.data(), p.high0.data(),
                 p.low0.data(),   p.high1.data(),      p.low1.data(),       p.cols};
  for (int b = 0; b < blocks;) {
    if (run[b] == 0) {
      for (int x = std::min(8 * b, p.cols - 8), end = x + 8; x < end; ++x) out[x] = Column(src, p, x);
      ++b;
      continue;
    }
    const int end = b + run[b];
    for (; b + perVector <= end; b += perVector) Blocks(d, src, t, b, out);
    for (; b < end; ++b) Blocks(dBlock, src, t, b, out);  // fewer than a vector's blocks left
  }
  if (blocks == 0)
    for (int x = 0; x < p.cols; ++x) out[x] = Column(src, p, x);
}
#endif

// The products stay below 2^15 x 2^11, the sum below 2^11: no lane saturates or wraps, and
// the result is at most 255.
uint8_t Row(const int16_t* upper, const int16_t* lower, int16_t b0, int16_t b1, int x) {
  return static_cast<uint8_t>((((upper[x] * b0) >> 16) + ((lower[x] * b1) >> 16) + 2) >> 2);
}

// The last columns are the last vector's, overlapping the one before; one lane (HWY_SCALAR) is
// the scalar loop, which the compiler may vectorise for the baseline instruction set.
void Rows(const int16_t* upper, const int16_t* lower, int16_t b0, int16_t b1, int cols, uint8_t* HWY_RESTRICT out) {
  const hn::ScalableTag<int16_t> d;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const int n = static_cast<int>(hn::Lanes(d));
  if (n == 1 || cols < n) {
    for (int x = 0; x < cols; ++x) out[x] = Row(upper, lower, b0, b1, x);
    return;
  }
  const auto w0 = hn::Set(d, b0), w1 = hn::Set(d, b1), two = hn::Set(d, 2);
  for (int x = 0;; x += n) {
    x = std::min(x, cols - n);
    const auto sum = hn::Add(hn::MulHigh(hn::LoadU(d, upper + x), w0), hn::MulHigh(hn::LoadU(d, lower + x), w1));
    hn::StoreU(hn::DemoteTo(d8, hn::ShiftRight<2>(hn::Add(sum, two))), d8, out + x);
    if (x + n >= cols) break;
  }
}

uint16_t HalveColumn(const uint8_t* src, int i) {
  const uint8_t* p = src + 2 * i;
  return static_cast<uint16_t>(p[-2] + 4 * p[-1] + 6 * p[0] + 4 * p[1] + p[2]);
}

uint8_t HalveRow(const uint16_t* const* r, int x) {
  return static_cast<uint8_t>((r[0][x] + 4 * r[1][x] + 6 * r[2][x] + 4 * r[3][x] + r[4][x] + 128) >> 8);
}

#if HWY_TARGET == HWY_SCALAR
void HalveColumns(const uint8_t* src, int from, int to, uint16_t* HWY_RESTRICT out) {
  for (int i = from; i < to; ++i) out[i] = HalveColumn(src, i);
}
#else
// Two source pixels as one 16-bit lane (little-endian: the even pixel low): three loads give
// the five pixels of every output lane without a shuffle.
void HalveColumns(const uint8_t* src, int from, int to, uint16_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint16_t> d;
  const hn::Repartition<uint8_t, decltype(d)> d8;
  const int n = static_cast<int>(hn::Lanes(d));
  if (to - from < n) {
    for (int i = from; i < to; ++i) out[i] = HalveColumn(src, i);
    return;
  }
  const auto low = hn::Set(d, uint16_t{0xFF});
  const auto four = hn::Set(d, uint16_t{4}), six = hn::Set(d, uint16_t{6});
  for (int i = from;; i += n) {
    i = std::min(i, to - n);  // the last vector overlaps the one before
    const auto before = hn::BitCast(d, hn::LoadU(d8, src + 2 * i - 2));
    const auto at = hn::BitCast(d, hn::LoadU(d8, src + 2 * i));
    const auto after = hn::BitCast(d, hn::LoadU(d8, src + 2 * i + 2));
    const auto outer = hn::Add(hn::And(before, low), hn::And(after, low));
    const auto odd = hn::Add(hn::ShiftRight<8>(before), hn::ShiftRight<8>(at));
    hn::StoreU(hn::Add(hn::Add(outer, hn::Mul(odd, four)), hn::Mul(hn::And(at, low), six)), d, out + i);
    if (i + n >= to) break;
  }
}
#endif

void HalveRows(const uint16_t* const* r, int cols, uint8_t* HWY_RESTRICT out) {
  const hn::ScalableTag<uint16_t> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::Rebind<uint8_t, decltype(d)> d8;
  const int n = static_cast<int>(hn::Lanes(d));
  if (n == 1 || cols < n) {
    for (int x = 0; x < cols; ++x) out[x] = HalveRow(r, x);
    return;
  }
  const auto four = hn::Set(d, uint16_t{4}), six = hn::Set(d, uint16_t{6}), half = hn::Set(d, uint16_t{128});
  for (int x = 0;; x += n) {
    x = std::min(x, cols - n);
    const auto outer = hn::Add(hn::LoadU(d, r[0] + x), hn::LoadU(d, r[4] + x));
    const auto inner = hn::Add(hn::LoadU(d, r[1] + x), hn::LoadU(d, r[3] + x));
    const auto sum = hn::Add(hn::Add(outer, half), hn::Add(hn::Mul(inner, four), hn::Mul(hn::LoadU(d, r[2] + x), six)));
    // At most 255 after the shift: positive as a signed lane, which DemoteTo narrows.
    hn::StoreU(hn::DemoteTo(d8, hn::BitCast(di, hn::ShiftRight<8>(sum))), d8, out + x);
    if (x + n >= cols) break;
  }
}

ResizeKernels Kernels() { return {Columns, Rows, HalveColumns, HalveRows, HWY_TARGET}; }

}  // namespace mdbrief::resize_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mdbrief::resize_kernels {

ResizeKernels activeResizeKernels() { return MDBRIEF_ACTIVE_KERNELS(Kernels); }

namespace {

// OpenCV's source position and weights of output pixel i, in its float arithmetic: the first
// source pixel, its weight and the second's, each rounded to nearest, ties to even (cvRound).
struct Tap {
  int first;
  int16_t w0, w1;
};
Tap tap(int i, double scale) {
  float f = static_cast<float>((i + 0.5) * scale - 0.5);
  // floor (cvFloor): an enlargement's first position lies before the first pixel.
  const int first = static_cast<int>(f) - (f < static_cast<float>(static_cast<int>(f)));
  f -= static_cast<float>(first);
  // v in [0, 1]. Adding and taking away 2^23 rounds v x 2048 to a whole number as the FPU
  // rounds, to nearest, ties to even (cvRound's): inline and without a branch, where
  // std::lrint is a library call.
  const auto weight = [](float v) {
    constexpr float kWhole = 8388608.f;
    return static_cast<int16_t>((v * kWeightOne + kWhole) - kWhole);
  };
  return {first, weight(1.f - f), weight(f)};
}

// OpenCV's scale: the inverse of the size ratio.
double scaleOf(int src, int dst) { return 1. / (static_cast<double>(dst) / src); }

ColumnPlan columnPlan(int srcCols, int cols) {
  ColumnPlan p;
  p.srcCols = srcCols, p.cols = cols;
  p.first.resize(cols), p.second.resize(cols), p.a0.resize(cols), p.a1.resize(cols);
  p.high0.resize(cols), p.low0.resize(cols), p.high1.resize(cols), p.low1.resize(cols);
  const double scale = scaleOf(srcCols, cols);
  for (int x = 0; x < cols; ++x) {
    Tap t = tap(x, scale);
    // Before the first column or past the last, one pixel whole (OpenCV's clamping of the
    // position; of an enlargement's first columns too).
    if (t.first < 0) t = {0, kWeightOne, 0};
    if (t.first >= srcCols - 1) t = {srcCols - 1, kWeightOne, 0};
    p.first[x] = t.first, p.second[x] = std::min(t.first + 1, srcCols - 1), p.a0[x] = t.w0, p.a1[x] = t.w1;
    p.high0[x] = static_cast<int16_t>(t.w0 >> 4), p.low0[x] = static_cast<int16_t>(t.w0 & 15);
    p.high1[x] = static_cast<int16_t>(t.w1 >> 4), p.low1[x] = static_cast<int16_t>(t.w1 & 15);
  }
  // Blocks of 8 columns; when 8 does not divide cols, a last block of the last 8 columns.
  const int aligned = cols / 8, blocks = cols < 8 ? 0 : (cols + 7) / 8;
  p.window.resize(blocks), p.run.resize(blocks), p.firstIndex.resize(16 * blocks), p.secondIndex.resize(16 * blocks);
  for (int b = blocks - 1; b >= 0; --b) {
    const int x = std::min(8 * b, cols - 8);
    // The window ends at the row's end at the latest (the pixels are in the row).
    const int window = std::min(p.first[x], srcCols - 16);
    const bool fits = window >= 0 && p.second[x + 7] - window <= 15;
    // Runs of consecutive columns only: the last block overlaps the one before.
    p.run[b] = !fits ? 0 : b + 1 < aligned ? p.run[b + 1] + 1 : 1;
    if (!fits) continue;
    p.window[b] = window;
    for (int i = 0; i < 8; ++i) {
      // The pixel widened to 16 bits: a zero (index 0x80) for its high byte.
      p.firstIndex[16 * b + 2 * i] = static_cast<uint8_t>(p.first[x + i] - window);
      p.secondIndex[16 * b + 2 * i] = static_cast<uint8_t>(p.second[x + i] - window);
      p.firstIndex[16 * b + 2 * i + 1] = p.secondIndex[16 * b + 2 * i + 1] = 0x80;
    }
  }
  return p;
}

// The plans of the last sizes resized on this thread, newest last: a tracker's frames share
// their sizes, and each level's plan cost about a third of its columns pass.
constexpr size_t kCachedPlans = 32;  // PyramidOptions' most levels
const ColumnPlan& cachedColumnPlan(int srcCols, int cols) {
  thread_local std::vector<ColumnPlan> plans;
  for (const ColumnPlan& p : plans)
    if (p.srcCols == srcCols && p.cols == cols) return p;
  if (plans.size() == kCachedPlans) plans.erase(plans.begin());
  plans.push_back(columnPlan(srcCols, cols));
  return plans.back();
}

}  // namespace

void resizeLinear(const uint8_t* src, size_t srcStride, int srcCols, int srcRows, uint8_t* dst, size_t dstStride,
                  int dstCols, int dstRows) {
  const ResizeKernels k = activeResizeKernels();
  const ColumnPlan& plan = cachedColumnPlan(srcCols, dstCols);
  // Two rows of the horizontal pass: consecutive output rows share source rows, each computed
  // once.
  std::vector<int16_t> ring(2 * static_cast<size_t>(dstCols));
  int held[2] = {-1, -1};
  const auto horizontal = [&](int row, int keep) -> const int16_t* {
    for (int s = 0; s < 2; ++s)
      if (held[s] == row) return ring.data() + s * static_cast<size_t>(dstCols);
    const int s = held[0] == keep ? 1 : 0;
    int16_t* out = ring.data() + s * static_cast<size_t>(dstCols);
    k.columns(src + row * srcStride, plan, out);
    held[s] = row;
    return out;
  };
  const double scale = scaleOf(srcRows, dstRows);
  for (int y = 0; y < dstRows; ++y) {
    // A row above the first or below the last is that row, its weight kept (OpenCV's clamping
    // of rows, unlike its columns').
    const Tap t = tap(y, scale);
    const int r0 = std::clamp(t.first, 0, srcRows - 1), r1 = std::clamp(t.first + 1, 0, srcRows - 1);
    const int16_t* upper = horizontal(r0, r1);
    const int16_t* lower = horizontal(r1, r0);
    k.rows(upper, lower, t.w0, t.w1, dstCols, dst + y * dstStride);
  }
}

void halveImage(const uint8_t* src, size_t srcStride, int srcCols, int srcRows, uint8_t* dst, size_t dstStride) {
  const ResizeKernels k = activeResizeKernels();
  const int cols = (srcCols + 1) / 2, rows = (srcRows + 1) / 2;
  // The columns whose five pixels, and the kernel's reads up to 2 i + 3, lie in the row; the
  // others reflected.
  const int inner = std::max(1, (srcCols - 2) / 2);
  const auto horizontal = [&](const uint8_t* row, uint16_t* out) {
    const auto pixel = [&](int c) { return row[detail::reflect101(c, srcCols)]; };
    const auto reflected = [&](int i) {
      out[i] = static_cast<uint16_t>(pixel(2 * i - 2) + 4 * pixel(2 * i - 1) + 6 * pixel(2 * i) +
                                     4 * pixel(2 * i + 1) + pixel(2 * i + 2));
    };
    reflected(0);
    if (inner > 1) k.halveColumns(row, 1, inner, out);
    for (int i = inner; i < cols; ++i) reflected(i);
  };
  // Five horizontal rows, source row s in slot s mod 5: the rows an output row reads lie within
  // five consecutive ones, so in distinct slots, and the next output row keeps three of them.
  std::vector<uint16_t> ring(5 * static_cast<size_t>(cols));
  int held[5] = {-1, -1, -1, -1, -1};
  for (int y = 0; y < rows; ++y) {
    const uint16_t* r[5];
    for (int j = 0; j < 5; ++j) {
      const int s = detail::reflect101(2 * y - 2 + j, srcRows), slot = s % 5;
      uint16_t* row = ring.data() + slot * static_cast<size_t>(cols);
      if (held[slot] != s) {
        horizontal(src + s * srcStride, row);
        held[slot] = s;
      }
      r[j] = row;
    }
    k.halveRows(r, cols, dst + y * dstStride);
  }
}

}  // namespace mdbrief::resize_kernels
#endif
