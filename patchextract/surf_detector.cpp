#include "patchextract/surf_detector.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace mdbrief::train {

namespace {

constexpr int kIntervals = 4;  // filter sizes per octave

// Sums over an integral image (CV_64F: exact for any 8-bit image below 2^45 pixels).
class BoxSums {
 public:
  explicit BoxSums(const cv::Mat& image) { cv::integral(image, sum_, CV_64F); }
  int rows() const { return sum_.rows - 1; }
  int cols() const { return sum_.cols - 1; }
  // Sum of the rows [r, r + h) x columns [c, c + w), clipped to the image.
  double box(int r, int c, int h, int w) const {
    const int r0 = std::clamp(r, 0, rows()), r1 = std::clamp(r + h, 0, rows());
    const int c0 = std::clamp(c, 0, cols()), c1 = std::clamp(c + w, 0, cols());
    if (r1 <= r0 || c1 <= c0) return 0.0;
    const double* a = sum_.ptr<double>(r0);
    const double* b = sum_.ptr<double>(r1);
    return b[c1] - b[c0] - a[c1] + a[c0];
  }

 private:
  cv::Mat sum_;
};

int filterSize(int octave, int interval) { return 3 * ((2 << octave) * (interval + 1) + 1); }

// One response layer: det(H) and the Laplacian sign on a grid with the octave's step.
struct Layer {
  int filter = 0, step = 1, rows = 0, cols = 0;
  std::vector<float> det;
  std::vector<uint8_t> laplacianPositive;
  float at(int r, int c) const { return det[r * cols + c]; }
};

Layer computeLayer(const BoxSums& s, int filter, int step) {
  Layer layer;
  layer.filter = filter;
  layer.step = step;
  layer.rows = s.rows() / step;
  layer.cols = s.cols() / step;
  layer.det.assign(static_cast<size_t>(layer.rows) * layer.cols, 0.f);
  layer.laplacianPositive.assign(layer.det.size(), 0);
  const int l = filter / 3, b = (filter - 1) / 2;
  const double norm = 1.0 / (double(filter) * filter);
  for (int gr = 0; gr < layer.rows; ++gr)
    for (int gc = 0; gc < layer.cols; ++gc) {
      const int r = gr * step, c = gc * step;
      // Full-height band minus 3x the middle lobe gives the +1 -2 +1 lobes.
      const double dxx = (s.box(r - l + 1, c - b, 2 * l - 1, filter) -
                          3 * s.box(r - l + 1, c - l / 2, 2 * l - 1, l)) * norm;
      const double dyy = (s.box(r - b, c - l + 1, filter, 2 * l - 1) -
                          3 * s.box(r - l / 2, c - l + 1, l, 2 * l - 1)) * norm;
      const double dxy = (s.box(r - l, c + 1, l, l) + s.box(r + 1, c - l, l, l) -
                          s.box(r - l, c - l, l, l) - s.box(r + 1, c + 1, l, l)) * norm;
      const size_t i = static_cast<size_t>(gr) * layer.cols + gc;
      layer.det[i] = static_cast<float>(dxx * dyy - 0.81 * dxy * dxy);
      // A bright blob has negative second derivatives.
      layer.laplacianPositive[i] = dxx + dyy < 0;
    }
  return layer;
}

// Dominant orientation (degrees, [0, 360)) from Haar responses around (x, y) at scale s.
float orientation(const BoxSums& s, double x, double y, double scale) {
  struct Sample { double angle, dx, dy; };
  std::vector<Sample> samples;
  const int haar = std::max(2, 2 * static_cast<int>(std::lround(2 * scale)));  // ~4s, even
  const int half = haar / 2;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j) {
      if (i * i + j * j >= 36) continue;
      const int r = static_cast<int>(std::lround(y + j * scale));
      const int c = static_cast<int>(std::lround(x + i * scale));
      const double w = std::exp(-(i * i + j * j) / (2 * 2.5 * 2.5));
      const double dx = s.box(r - half, c, haar, half) - s.box(r - half, c - half, haar, half);
      const double dy = s.box(r, c - half, half, haar) - s.box(r - half, c - half, half, haar);
      samples.push_back({std::atan2(dy, dx), w * dx, w * dy});
    }
  double bestNorm = -1, bestAngle = 0;
  constexpr double kWindow = CV_PI / 3;
  for (double start = -CV_PI; start < CV_PI; start += 0.15) {
    double sx = 0, sy = 0;
    for (const Sample& p : samples) {
      double d = p.angle - start;
      if (d < 0) d += 2 * CV_PI;
      if (d < kWindow) sx += p.dx, sy += p.dy;
    }
    const double n = sx * sx + sy * sy;
    if (n > bestNorm) bestNorm = n, bestAngle = std::atan2(sy, sx);
  }
  double deg = bestAngle * 180.0 / CV_PI;
  if (deg < 0) deg += 360.0;
  if (deg >= 360.0) deg -= 360.0;
  return static_cast<float>(deg);
}

}  // namespace

std::vector<cv::KeyPoint> detectSurf(const cv::Mat& image, const SurfOptions& options) {
  if (image.empty() || image.type() != CV_8UC1)
    throw std::invalid_argument("detectSurf: need a non-empty 8UC1 image");
  const BoxSums sums(image);
  std::vector<cv::KeyPoint> keypoints;
  for (int o = 0; o < options.octaves; ++o) {
    const int step = 1 << o;
    std::array<Layer, kIntervals> layers;
    for (int i = 0; i < kIntervals; ++i) layers[i] = computeLayer(sums, filterSize(o, i), step);
    const int rows = layers[0].rows, cols = layers[0].cols;
    for (int i = 1; i + 1 < kIntervals; ++i) {
      const Layer &lo = layers[i - 1], &mid = layers[i], &hi = layers[i + 1];
      // The largest filter of the triple must fit in the image around the point.
      const int margin = (hi.filter / 2) / step + 1;
      for (int r = margin; r < rows - margin; ++r)
        for (int c = margin; c < cols - margin; ++c) {
          const float v = mid.at(r, c);
          if (v <= options.hessianThreshold) continue;
          bool isMax = true;
          for (int dr = -1; dr <= 1 && isMax; ++dr)
            for (int dc = -1; dc <= 1 && isMax; ++dc)
              isMax = v > lo.at(r + dr, c + dc) && v > hi.at(r + dr, c + dc) &&
                      (dr == 0 && dc == 0 ? true : v > mid.at(r + dr, c + dc));
          if (!isMax) continue;
          // Quadratic fit: offset = -H^-1 g in (column, row, layer) units.
          const double dx = (mid.at(r, c + 1) - mid.at(r, c - 1)) / 2;
          const double dy = (mid.at(r + 1, c) - mid.at(r - 1, c)) / 2;
          const double ds = (hi.at(r, c) - lo.at(r, c)) / 2;
          const double dxx = mid.at(r, c + 1) + mid.at(r, c - 1) - 2 * v;
          const double dyy = mid.at(r + 1, c) + mid.at(r - 1, c) - 2 * v;
          const double dss = hi.at(r, c) + lo.at(r, c) - 2 * v;
          const double dxy = (mid.at(r + 1, c + 1) - mid.at(r + 1, c - 1) -
                              mid.at(r - 1, c + 1) + mid.at(r - 1, c - 1)) / 4;
          const double dxs = (hi.at(r, c + 1) - hi.at(r, c - 1) - lo.at(r, c + 1) +
                              lo.at(r, c - 1)) / 4;
          const double dys = (hi.at(r + 1, c) - hi.at(r - 1, c) - lo.at(r + 1, c) +
                              lo.at(r - 1, c)) / 4;
          const cv::Matx33d H(dxx, dxy, dxs, dxy, dyy, dys, dxs, dys, dss);
          cv::Vec3d off;
          if (!cv::solve(H, cv::Vec3d(-dx, -dy, -ds), off, cv::DECOMP_LU)) continue;
          if (std::abs(off[0]) >= 0.5 || std::abs(off[1]) >= 0.5 || std::abs(off[2]) >= 0.5)
            continue;
          const double x = (c + off[0]) * step, y = (r + off[1]) * step;
          const double filter = mid.filter + off[2] * (mid.filter - lo.filter);
          const double scale = 1.2 * filter / 9.0;
          cv::KeyPoint kp(cv::Point2f(float(x), float(y)), float(20 * scale), -1.f, v, o,
                          mid.laplacianPositive[r * cols + c]);
          keypoints.push_back(kp);
        }
    }
  }
  std::sort(keypoints.begin(), keypoints.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
    if (a.response != b.response) return a.response > b.response;
    if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
    return a.pt.x < b.pt.x;
  });
  if (options.maxKeypoints > 0 && static_cast<int>(keypoints.size()) > options.maxKeypoints)
    keypoints.resize(options.maxKeypoints);
  if (!options.upright)
    for (auto& kp : keypoints) kp.angle = orientation(sums, kp.pt.x, kp.pt.y, kp.size / 20.0);
  return keypoints;
}

}  // namespace mdbrief::train
