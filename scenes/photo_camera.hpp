#pragma once
// The camera assumed for an undistorted photo without a calibration (the Oxford sequences, the
// opencv-doc photos): a pinhole with focal length = image width (about 53 degrees across) and
// the principal point in the middle. Only the descriptor's footprint depends on it.
#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief {

CameraPtr photoCamera(cv::Size size);

}  // namespace mdbrief
