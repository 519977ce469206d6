#include "scenes/photo_camera.hpp"

#include <memory>

#include "mdbrief/camera/pinhole.hpp"

namespace mdbrief {

CameraPtr photoCamera(cv::Size size) {
  CameraIntrinsics k;
  k.width = size.width;
  k.height = size.height;
  k.fx = k.fy = size.width;
  k.cx = (size.width - 1) / 2.0;
  k.cy = (size.height - 1) / 2.0;
  return std::make_shared<PinholeCamera>(k);
}

}  // namespace mdbrief
