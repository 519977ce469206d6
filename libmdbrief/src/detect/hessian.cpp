#include "detect/hessian.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include "detect/gaussian_smoothing.hpp"
#include "detect/hessian_kernels.hpp"

namespace mdbrief::detail {

cv::Mat gaussianSmoothed(const cv::Mat& level, double sigma) {
  // Truncated at 3 sigma: OpenCV's default for float images reaches 4 sigma, a third more taps
  // for weights below 0.3 % of the total. The pyramid's own smoothing, at this detector's sigma.
  const int taps = 2 * static_cast<int>(std::ceil(3.0 * sigma)) + 1;
  return gaussianSmoothing(level, taps, sigma, true).floats;
}

cv::Mat hessianResponse(const cv::Mat& smooth, double sigma) {
  // Central second differences and det * sigma^4 in one pass (hessian_kernels.hpp). Borders
  // reflect as BORDER_REFLECT_101: the maxima of the neighbouring levels read them.
  const int rows = smooth.rows, cols = smooth.cols;
  const float scale = static_cast<float>(sigma * sigma * sigma * sigma);
  const hessian_kernels::HessianKernels kernels = hessian_kernels::activeHessianKernels();
  cv::Mat response(rows, cols, CV_32F);
  const auto reflect = [](int i, int n) { return n == 1 ? 0 : i < 0 ? -i : i >= n ? 2 * n - 2 - i : i; };
  for (int y = 0; y < rows; ++y) {
    const float* a = smooth.ptr<float>(reflect(y - 1, rows));
    const float* b = smooth.ptr<float>(y);
    const float* c = smooth.ptr<float>(reflect(y + 1, rows));
    float* out = response.ptr<float>(y);
    // The two border columns as the kernel does the others, with reflected neighbours.
    const auto at = [&](int x) {
      const int l = reflect(x - 1, cols), r = reflect(x + 1, cols);
      const float dxx = (b[l] + b[r]) - 2.f * b[x];
      const float dyy = (a[x] + c[x]) - 2.f * b[x];
      const float dxy = ((c[r] - c[l]) - (a[r] - a[l])) * 0.25f;
      return (dxx * dyy - dxy * dxy) * scale;
    };
    out[0] = at(0);
    kernels.responseRow(a, b, c, cols, scale, out);
    if (cols > 1) out[cols - 1] = at(cols - 1);
  }
  return response;
}

bool strongerBlob(const Blob& a, const Blob& b) {
  if (a.response != b.response) return a.response > b.response;
  return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
}

namespace {

// Whether `value` exceeds every response of `r` in the 3x3 neighbourhood of pixel (cx, cy) (NaN
// responses aside), and if so their largest in `largest` (-inf when that pixel is outside the
// level or on its border). Most candidates fail on a neighbouring level, and stop at the first
// response as large.
bool exceedsNeighbourhood(const cv::Mat& r, int cx, int cy, float value, float& largest) {
  largest = -INFINITY;
  if (cx < 1 || cy < 1 || cx >= r.cols - 1 || cy >= r.rows - 1) return value > largest;
  for (int v = -1; v <= 1; ++v) {
    const float* row = r.ptr<float>(cy + v);
    for (int u = -1; u <= 1; ++u) {
      if (row[cx + u] >= value) return false;
      largest = std::max(largest, row[cx + u]);
    }
  }
  return value > largest;
}

// The pixel of level `to` nearest to each column and each row of level `from`, through the
// input image (the axes map independently): computed once per level pair instead of per
// candidate.
struct PixelMap {
  std::vector<int> column, row;
};
PixelMap pixelMap(const LevelGrid& from, const LevelGrid& to, int cols, int rows) {
  PixelMap m{std::vector<int>(cols), std::vector<int>(rows)};
  for (int x = 0; x < cols; ++x) m.column[x] = static_cast<int>(std::lround(to.toLevel(from.toInput(cv::Point2d(x, 0))).x));
  for (int y = 0; y < rows; ++y) m.row[y] = static_cast<int>(std::lround(to.toLevel(from.toInput(cv::Point2d(0, y))).y));
  return m;
}

// Vertex of the parabola through (-1, a), (0, b), (1, c), clamped to [-0.5, 0.5].
float parabolaOffset(float a, float b, float c) {
  const float curvature = a - 2.f * b + c;
  if (!(curvature < 0.f)) return 0.f;
  return std::clamp(0.5f * (a - c) / curvature, -0.5f, 0.5f);
}

// The vertex of the quadratic through the 3x3 neighbourhood (its cross term included), when the
// surface is a cap whose vertex lies within half a pixel; otherwise the two parabolas alone.
void subPixelOffset(const float* above, const float* row, const float* below, float& dx, float& dy) {
  const float gx = 0.5f * (row[1] - row[-1]), gy = 0.5f * (below[0] - above[0]);
  const float hxx = row[-1] - 2.f * row[0] + row[1], hyy = above[0] - 2.f * row[0] + below[0];
  const float hxy = 0.25f * ((below[1] - below[-1]) - (above[1] - above[-1]));
  const float det = hxx * hyy - hxy * hxy;
  if (hxx < 0.f && det > 0.f) {
    const float ox = -(hyy * gx - hxy * gy) / det, oy = -(hxx * gy - hxy * gx) / det;
    if (std::abs(ox) <= 0.5f && std::abs(oy) <= 0.5f) {
      dx = ox;
      dy = oy;
      return;
    }
  }
  dx = parabolaOffset(row[-1], row[0], row[1]);
  dy = parabolaOffset(above[0], row[0], below[0]);
}

}  // namespace

namespace {

// The maxima of level k (0 < k < levels - 1), in scan order.
std::vector<Blob> levelMaxima(const std::vector<cv::Mat>& responses, const std::vector<LevelGrid>& grids, int k,
                              float threshold, int margin, const std::function<bool(int, int, int)>& allowed) {
  std::vector<Blob> blobs;
  const cv::Mat& r = responses[k];
  if (r.cols <= 2 * margin || r.rows <= 2 * margin) return blobs;
  // The pixels above the threshold that are maxima of their 3x3 neighbourhood, a row at a time.
  const hessian_kernels::HessianKernels kernels = hessian_kernels::activeHessianKernels();
  const PixelMap finerPixel = pixelMap(grids[k], grids[k - 1], r.cols, r.rows);
  const PixelMap coarserPixel = pixelMap(grids[k], grids[k + 1], r.cols, r.rows);
  std::vector<int32_t> xs(r.cols);
  for (int y = margin; y < r.rows - margin; ++y) {
    const float* above = r.ptr<float>(y - 1);
    const float* row = r.ptr<float>(y);
    const float* below = r.ptr<float>(y + 1);
    const int found = kernels.candidates(above, row, below, margin, r.cols - margin, threshold, xs.data());
    for (int i = 0; i < found; ++i) {
      const int x = xs[i];
      const float value = row[x];
      // Plateaus: keep the first pixel in scan order only.
      if (row[x - 1] == value || above[x - 1] == value || above[x] == value || above[x + 1] == value) continue;
      // Same point on the neighbouring levels.
      float finer, coarser;
      if (!exceedsNeighbourhood(responses[k - 1], finerPixel.column[x], finerPixel.row[y], value, finer) ||
          !exceedsNeighbourhood(responses[k + 1], coarserPixel.column[x], coarserPixel.row[y], value, coarser))
        continue;
      if (!allowed(k, x, y)) continue;
      Blob b;
      b.level = k;
      b.x = x;
      b.y = y;
      b.response = value;
      subPixelOffset(above + x, row + x, below + x, b.dx, b.dy);
      b.dlevel = parabolaOffset(finer, value, coarser);
      blobs.push_back(b);
    }
  }
  return blobs;
}

}  // namespace

std::vector<Blob> hessianMaxima(const std::vector<cv::Mat>& responses, const std::vector<LevelGrid>& grids,
                                float threshold, int margin,
                                const std::function<bool(int, int, int)>& allowed) {
  const int levels = static_cast<int>(responses.size());
  // Only the inner levels: a maximum on the first or last level may be one of a finer or
  // coarser structure, whose scale the pyramid cannot tell (measured: docs/RESULTS.md
  // "Whole pipelines (issue 10)"). Levels in parallel, concatenated in level order.
  std::vector<std::vector<Blob>> perLevel(std::max(levels, 0));
  if (levels >= 3)
    tbb::parallel_for(1, levels - 1,
                      [&](int k) { perLevel[k] = levelMaxima(responses, grids, k, threshold, margin, allowed); });
  std::vector<Blob> blobs;
  for (const auto& level : perLevel) blobs.insert(blobs.end(), level.begin(), level.end());
  return blobs;
}

}  // namespace mdbrief::detail
