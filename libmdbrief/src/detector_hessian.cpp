#include "detector_hessian.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include <opencv2/imgproc.hpp>

namespace mdbrief::detail {

cv::Mat hessianResponse(const cv::Mat& level, double sigma) {
  cv::Mat smooth;
  level.convertTo(smooth, CV_32F, 1.0 / 255.0);
  cv::GaussianBlur(smooth, smooth, cv::Size(), sigma, sigma, cv::BORDER_REFLECT_101);
  // Central second differences; the border rows are never maxima (margin > 1).
  cv::Mat dxx, dyy, dxy;
  const cv::Mat second = (cv::Mat_<float>(1, 3) << 1.f, -2.f, 1.f);
  const cv::Mat first = (cv::Mat_<float>(1, 3) << -0.5f, 0.f, 0.5f);
  const cv::Mat one = (cv::Mat_<float>(1, 1) << 1.f);
  cv::sepFilter2D(smooth, dxx, CV_32F, second, one, cv::Point(-1, -1), 0, cv::BORDER_REFLECT_101);
  cv::sepFilter2D(smooth, dyy, CV_32F, one, second, cv::Point(-1, -1), 0, cv::BORDER_REFLECT_101);
  cv::sepFilter2D(smooth, dxy, CV_32F, first, first, cv::Point(-1, -1), 0, cv::BORDER_REFLECT_101);
  cv::Mat response;
  cv::multiply(dxx, dyy, response);
  cv::multiply(dxy, dxy, dxy);
  cv::subtract(response, dxy, response);
  const double s2 = sigma * sigma;
  response *= s2 * s2;
  return response;
}

bool strongerBlob(const Blob& a, const Blob& b) {
  if (a.response != b.response) return a.response > b.response;
  return std::tie(a.level, a.y, a.x) < std::tie(b.level, b.y, b.x);
}

namespace {

// Largest response of `r` in the 3x3 neighbourhood of the nearest pixel to (x, y); -inf when
// that pixel is outside the level.
float neighbourhoodMax(const cv::Mat& r, double x, double y) {
  const int cx = static_cast<int>(std::lround(x)), cy = static_cast<int>(std::lround(y));
  if (cx < 1 || cy < 1 || cx >= r.cols - 1 || cy >= r.rows - 1) return -INFINITY;
  float best = -INFINITY;
  for (int v = -1; v <= 1; ++v) {
    const float* row = r.ptr<float>(cy + v);
    for (int u = -1; u <= 1; ++u) best = std::max(best, row[cx + u]);
  }
  return best;
}

// Vertex of the parabola through (-1, a), (0, b), (1, c), clamped to [-0.5, 0.5].
float parabolaOffset(float a, float b, float c) {
  const float curvature = a - 2.f * b + c;
  if (!(curvature < 0.f)) return 0.f;
  return std::clamp(0.5f * (a - c) / curvature, -0.5f, 0.5f);
}

}  // namespace

std::vector<Blob> hessianMaxima(const std::vector<cv::Mat>& responses, const std::vector<double>& scales,
                                float threshold, int margin,
                                const std::function<bool(int, int, int)>& allowed) {
  std::vector<Blob> blobs;
  const int levels = static_cast<int>(responses.size());
  // Only the inner levels: a maximum on the first or last level may be one of a finer or
  // coarser structure, whose scale the pyramid cannot tell (measured: docs/RESULTS.md
  // "Whole pipelines").
  for (int k = 1; k + 1 < levels; ++k) {
    const cv::Mat& r = responses[k];
    if (r.cols <= 2 * margin || r.rows <= 2 * margin) continue;
    cv::Mat dilated;
    cv::dilate(r, dilated, cv::Mat());
    for (int y = margin; y < r.rows - margin; ++y) {
      const float* row = r.ptr<float>(y);
      const float* top = dilated.ptr<float>(y);
      for (int x = margin; x < r.cols - margin; ++x) {
        const float value = row[x];
        if (!(value > threshold) || value < top[x]) continue;
        // Plateaus: keep the first pixel in scan order only.
        if (row[x - 1] == value || r.at<float>(y - 1, x - 1) == value || r.at<float>(y - 1, x) == value ||
            r.at<float>(y - 1, x + 1) == value)
          continue;
        // Same point on the neighbouring levels (level pixels scale by scales[k] / scales[j]).
        const float below = neighbourhoodMax(responses[k - 1], x * scales[k] / scales[k - 1], y * scales[k] / scales[k - 1]);
        const float above = neighbourhoodMax(responses[k + 1], x * scales[k] / scales[k + 1], y * scales[k] / scales[k + 1]);
        if (!(value > below) || !(value > above)) continue;
        if (!allowed(k, x, y)) continue;
        Blob b;
        b.level = k;
        b.x = x;
        b.y = y;
        b.response = value;
        b.dx = parabolaOffset(row[x - 1], value, row[x + 1]);
        b.dy = parabolaOffset(r.at<float>(y - 1, x), value, r.at<float>(y + 1, x));
        b.dlevel = parabolaOffset(below, value, above);
        blobs.push_back(b);
      }
    }
  }
  return blobs;
}

}  // namespace mdbrief::detail
