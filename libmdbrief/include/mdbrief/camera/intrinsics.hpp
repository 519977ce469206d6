#pragma once
// Image size and the linear part (focal lengths, principal point) shared by every
// perspective-family camera model (pinhole, radial, Kannala-Brandt, double sphere, UCM/EUCM,
// radial-tangential, omni: camera/with_intrinsics.hpp). Pixel conventions as in camera.hpp
// (u = column, v = row).
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief {

struct CameraIntrinsics {
  int width = 0;    // image width in pixels, > 0
  int height = 0;   // image height in pixels, > 0
  double fx = 0.0;  // focal length along u (columns) in pixels, > 0
  double fy = 0.0;  // focal length along v (rows) in pixels, > 0
  double cx = 0.0;  // principal point column, finite
  double cy = 0.0;  // principal point row, finite

  cv::Size size() const { return {width, height}; }
};

// Throws std::invalid_argument "<model>: <parameter> ..." for a non-positive size or focal
// length or a non-finite value.
void validateIntrinsics(const CameraIntrinsics& intrinsics, const std::string& model);

// The intrinsics after resampling the image to newSize the way cv::resize does: pixel centres
// map as u' = (u + 0.5) * sx - 0.5 with sx = newWidth / width (same along v). Throws
// std::invalid_argument for a non-positive newSize.
CameraIntrinsics resizeIntrinsics(const CameraIntrinsics& intrinsics, cv::Size newSize);

}  // namespace mdbrief
