#pragma once
// Building a camera out of a calibration's parameters, for every reader of calibrations (the
// file formats, the Python constructor): the constructors' std::invalid_argument becomes a
// std::runtime_error naming the source, and the camera must be a plausible lens.
#include <memory>
#include <stdexcept>
#include <string>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/ocam.hpp"

namespace mdbrief::detail {

// A calibration can parse and still be no lens: checked along 16 rays from the principal point
// to the image border, over the pixels the model calls valid, the angle to the optical axis
// must grow with the distance (the distortion is monotonic over the field of view), every
// pixel must unproject and project back within 0.01 px (the inverse converges), and the image
// must span at least half a degree. Throws std::runtime_error naming the source, the
// parameters and the failing pixel.
void requirePlausible(const Camera& camera, const std::string& source);

template <class CameraType, class Params>
std::shared_ptr<Camera> construct(const std::string& source, const Params& params) {
  std::shared_ptr<Camera> camera;
  try {
    camera = std::make_shared<CameraType>(params);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
  requirePlausible(*camera, source);
  return camera;
}

// a0 > 0 means z points forward (fisheye-calib-adapter); OCamCalib's convention is a0 < 0.
std::shared_ptr<Camera> makeOcam(const std::string& source, OcamParams p);

}  // namespace mdbrief::detail
