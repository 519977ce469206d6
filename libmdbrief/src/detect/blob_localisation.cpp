#include "detect/blob_localisation.hpp"

#include <algorithm>
#include <cmath>

#include "detect/border_reflect.hpp"
#include "detect/hessian_kernels.hpp"

namespace mdbrief::detail {

namespace {

// Beyond a few pixels' walk the maximum is another blob's.
constexpr int kMaxSteps = 3;
constexpr int kMaxRadius = 24;  // ceil(3 max(kHalvedFromSigma, sqrt(kMaxSigma^2 - 1) / 2))
static_assert(2 * kMaxRadius + 1 <= hessian_kernels::kMaxBlockTaps);
constexpr int kMaxWidth = 5 + 2 * kMaxRadius;
constexpr int kMaxReadable = hessian_kernels::blockReadWidth(2 * kMaxRadius + 1);

// A Gaussian's taps, 3 sigma on either side, summing to 1. exp(-i^2 / (2 sigma^2)) by the
// recurrence g(i) = g(i - 1) q^(2i - 1), q = exp(-1 / (2 sigma^2)): one exponential instead of one
// per tap.
struct Taps {
  int radius = 0;
  float weight[2 * kMaxRadius + 1];
};
Taps gaussianTaps(double sigma) {
  Taps t;
  t.radius = static_cast<int>(std::ceil(3.0 * sigma));
  CV_Assert(t.radius <= kMaxRadius);
  double half[kMaxRadius + 1];
  const double q = std::exp(-0.5 / (sigma * sigma));
  double g = 1.0, factor = q, total = 1.0;
  half[0] = 1.0;
  for (int i = 1; i <= t.radius; ++i) {
    g *= factor;
    factor *= q * q;
    half[i] = g;
    total += 2 * g;
  }
  for (int i = 0; i <= t.radius; ++i)
    t.weight[t.radius - i] = t.weight[t.radius + i] = static_cast<float>(half[i] / total);
  return t;
}

// The smoothed image at the 5x5 pixels around (cx, cy), row-major (hessian_kernels.hpp's
// gaussianBlock5: each sum in the order of its taps, so every SIMD level gives the same bits).
void smoothedBlock(const hessian_kernels::HessianKernels& kernels, const cv::Mat& image, int cx, int cy, const Taps& taps,
                   float out[25]) {
  const int radius = taps.radius, width = 5 + 2 * radius, readable = hessian_kernels::blockReadWidth(2 * radius + 1);
  // The image's rows where the kernel's reads lie in them (only the first `width` columns count:
  // the rest are read and their sums dropped), reflected copies otherwise.
  const uint8_t* rows[kMaxWidth];
  uint8_t copies[kMaxWidth][kMaxReadable];
  const int left = cx - 2 - radius, top = cy - 2 - radius;
  const bool inside = left >= 0 && left + readable <= image.cols;
  const bool rowsInside = top >= 0 && top + width <= image.rows;
  for (int r = 0; r < width; ++r) {
    const uint8_t* pixels = image.ptr<uint8_t>(rowsInside ? top + r : reflect101(top + r, image.rows));
    if (inside) {
      rows[r] = pixels + left;
      continue;
    }
    for (int c = 0; c < width; ++c) copies[r][c] = pixels[reflect101(left + c, image.cols)];
    std::fill(copies[r] + width, copies[r] + readable, uint8_t{0});
    rows[r] = copies[r];
  }
  kernels.gaussianBlock5(rows, 2 * radius + 1, taps.weight, out);
}

// det(Hessian) at (u, v) of the 5x5 block, by central differences (hessian.cpp's response).
float determinant(const float s[25], int u, int v) {
  const float* a = s + 5 * (v - 1);
  const float* b = s + 5 * v;
  const float* c = s + 5 * (v + 1);
  const float dxx = (b[u - 1] + b[u + 1]) - 2.f * b[u];
  const float dyy = (a[u] + c[u]) - 2.f * b[u];
  const float dxy = ((c[u + 1] - c[u - 1]) - (a[u + 1] - a[u - 1])) * 0.25f;
  return dxx * dyy - dxy * dxy;
}

std::optional<cv::Point2d> locate(const cv::Mat& image, const cv::Point2d& start, double sigma, double maxDistance) {
  const hessian_kernels::HessianKernels kernels = hessian_kernels::activeHessianKernels();
  const Taps taps = gaussianTaps(sigma);
  int x = static_cast<int>(std::lround(start.x)), y = static_cast<int>(std::lround(start.y));
  for (int step = 0; step <= kMaxSteps; ++step) {
    if (x < 0 || y < 0 || x >= image.cols || y >= image.rows) return std::nullopt;
    float s[25], r[9];
    smoothedBlock(kernels, image, x, y, taps, s);
    for (int v = 0; v < 3; ++v)
      for (int u = 0; u < 3; ++u) r[3 * v + u] = determinant(s, u + 1, v + 1);
    // The quadratic through the 3x3 responses (hessian.cpp's subPixelOffset, without its fallback:
    // a response that is no cap here means the blob is not where its level put it).
    const double gx = 0.5 * (r[5] - r[3]), gy = 0.5 * (r[7] - r[1]);
    const double hxx = r[3] - 2.0 * r[4] + r[5], hyy = r[1] - 2.0 * r[4] + r[7];
    const double hxy = 0.25 * ((r[8] - r[6]) - (r[2] - r[0]));
    const double det = hxx * hyy - hxy * hxy;
    if (!(hxx < 0 && det > 0)) return std::nullopt;
    const double ox = -(hyy * gx - hxy * gy) / det, oy = -(hxx * gy - hxy * gx) / det;
    if (std::abs(ox) <= 0.5 && std::abs(oy) <= 0.5) {
      const cv::Point2d found(x + ox, y + oy);
      if (!(cv::norm(found - start) <= maxDistance)) return std::nullopt;
      return found;
    }
    if (std::abs(ox) > 0.5) x += ox > 0 ? 1 : -1;
    if (std::abs(oy) > 0.5) y += oy > 0 ? 1 : -1;
  }
  return std::nullopt;
}

}  // namespace

std::optional<cv::Point2d> relocaliseBlob(const cv::Mat& input8u, const cv::Mat& half8u, const cv::Point2d& start,
                                          double sigma, double maxDistance) {
  CV_Assert(input8u.type() == CV_8UC1 && !input8u.empty() && sigma > 0 && sigma <= kMaxSigma);
  if (sigma <= kHalvedFromSigma) return locate(input8u, start, sigma, maxDistance);
  CV_Assert(half8u.type() == CV_8UC1 && half8u.cols == (input8u.cols + 1) / 2 && half8u.rows == (input8u.rows + 1) / 2);
  // pyrDown's pixel x is the input's pixel 2x; its kernel took 1 input pixel^2 of the variance.
  const auto found = locate(half8u, start / 2, std::sqrt(sigma * sigma - 1.0) / 2, maxDistance / 2);
  if (!found) return std::nullopt;
  return *found * 2;
}

}  // namespace mdbrief::detail
