#include "detect/harris.hpp"

#include <stdexcept>

namespace mdbrief::detail {

namespace {

// The window size as a compile-time constant lets the compiler unroll and vectorise the
// loops; harrisResponse dispatches the sizes validate(DetectorOptions) allows (3..15, odd).
template <int B>
float harrisResponseFixed(const cv::Mat& image, int x, int y, double k) {
  constexpr int r = B / 2;
  // Sobel is separable: per row of the window plus one row above and below, the horizontal
  // [1 2 1] smoothing and [-1 0 1] difference; the vertical pass then combines three rows.
  int smooth[B + 2][B], diff[B + 2][B];
  for (int i = 0; i < B + 2; ++i) {
    const uchar* p = image.ptr<uchar>(y - r - 1 + i) + x - r;
    for (int j = 0; j < B; ++j) {
      smooth[i][j] = p[j - 1] + 2 * p[j] + p[j + 1];
      diff[i][j] = p[j + 1] - p[j - 1];
    }
  }
  // |g| <= 4 * 255, so a product is < 2^20 and a sum over at most 15 x 15 pixels < 2^28.
  int sxx = 0, syy = 0, sxy = 0;
  for (int i = 1; i <= B; ++i) {
    for (int j = 0; j < B; ++j) {
      const int gx = diff[i - 1][j] + 2 * diff[i][j] + diff[i + 1][j];
      const int gy = smooth[i + 1][j] - smooth[i - 1][j];
      sxx += gx * gx;
      syy += gy * gy;
      sxy += gx * gy;
    }
  }
  const double norm = 1.0 / (1020.0 * 1020.0 * B * B);
  const double a = sxx * norm, b = syy * norm, c = sxy * norm;
  return static_cast<float>(a * b - c * c - k * (a + b) * (a + b));
}

}  // namespace

float harrisResponse(const cv::Mat& image, int x, int y, int blockSize, double k) {
  switch (blockSize) {
    case 3: return harrisResponseFixed<3>(image, x, y, k);
    case 5: return harrisResponseFixed<5>(image, x, y, k);
    case 7: return harrisResponseFixed<7>(image, x, y, k);
    case 9: return harrisResponseFixed<9>(image, x, y, k);
    case 11: return harrisResponseFixed<11>(image, x, y, k);
    case 13: return harrisResponseFixed<13>(image, x, y, k);
    case 15: return harrisResponseFixed<15>(image, x, y, k);
    default: throw std::invalid_argument("harrisResponse: blockSize must be odd in [3, 15]");
  }
}

}  // namespace mdbrief::detail
