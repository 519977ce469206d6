#include "detector_harris.hpp"

namespace mdbrief::detail {

float harrisResponse(const cv::Mat& image, int x, int y, int blockSize, double k) {
  const int r = blockSize / 2;
  const auto step = static_cast<std::ptrdiff_t>(image.step1());
  // Sums of at most 15 x 15 products of Sobel values (|g| <= 4 * 255) fit in 64 bits easily.
  long long sxx = 0, syy = 0, sxy = 0;
  for (int dy = -r; dy <= r; ++dy) {
    const uchar* row = image.ptr<uchar>(y + dy) + x;
    for (int dx = -r; dx <= r; ++dx) {
      const uchar* p = row + dx;
      const int gx = (p[1 - step] + 2 * p[1] + p[1 + step]) - (p[-1 - step] + 2 * p[-1] + p[-1 + step]);
      const int gy = (p[step - 1] + 2 * p[step] + p[step + 1]) - (p[-step - 1] + 2 * p[-step] + p[-step + 1]);
      sxx += gx * gx;
      syy += gy * gy;
      sxy += gx * gy;
    }
  }
  const double norm = 1.0 / (1020.0 * 1020.0 * blockSize * blockSize);
  const double a = sxx * norm, b = syy * norm, c = sxy * norm;
  return static_cast<float>(a * b - c * c - k * (a + b) * (a + b));
}

}  // namespace mdbrief::detail
