// A scene the guide's examples run on without any data: a textured image at the camera's size
// and the same image with the lens rolled about its optical axis (for a radially symmetric lens an
// exact image rotation about the principal point, so every match's true position is known).
#pragma once

#include <opencv2/imgproc.hpp>

namespace guide {

// Random blobs, bars and discs, blurred a little as a lens would; the same picture every run.
inline cv::Mat texturedImage(cv::Size size, uint64_t seed = 7) {
  cv::RNG rng(seed);
  cv::Mat image(size, CV_8UC1, cv::Scalar(128));
  for (int i = 0; i < 900; ++i) {
    const cv::Point centre(rng.uniform(0, size.width), rng.uniform(0, size.height));
    const int radius = rng.uniform(2, 14);
    const cv::Scalar shade(rng.uniform(0, 256));
    if (i % 3 == 0) {
      cv::circle(image, centre, radius, shade, cv::FILLED, cv::LINE_AA);
    } else {
      const cv::Point corner(centre.x + rng.uniform(-20, 21), centre.y + rng.uniform(-20, 21));
      cv::rectangle(image, centre, corner, shade, cv::FILLED, cv::LINE_AA);
    }
  }
  cv::GaussianBlur(image, image, cv::Size(0, 0), 1.0);
  return image;
}

// The image turned by `degrees` about `centre`, and the map that carries a pixel of the first
// image to its true position in the turned one.
inline cv::Mat rolled(const cv::Mat& image, cv::Point2f centre, double degrees, cv::Matx23d& map) {
  map = cv::getRotationMatrix2D(centre, degrees, 1.0);
  cv::Mat out;
  cv::warpAffine(image, out, cv::Mat(map), image.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  return out;
}

}  // namespace guide
