#include "mdbrief/camera/intrinsics.hpp"

#include "camera/model_utils.hpp"

namespace mdbrief {

void validateIntrinsics(const CameraIntrinsics& k, const std::string& model) {
  detail::requirePositive(model, "width", k.width);
  detail::requirePositive(model, "height", k.height);
  detail::requirePositive(model, "fx", k.fx);
  detail::requirePositive(model, "fy", k.fy);
  detail::requireFinite(model, "cx", k.cx);
  detail::requireFinite(model, "cy", k.cy);
}

CameraIntrinsics resizeIntrinsics(const CameraIntrinsics& k, cv::Size newSize) {
  const cv::Vec2d s = detail::resizeScale(k.size(), newSize, "intrinsics");
  CameraIntrinsics r = k;
  r.width = newSize.width;
  r.height = newSize.height;
  r.fx = k.fx * s[0];
  r.fy = k.fy * s[1];
  r.cx = detail::resizeCoordinate(k.cx, s[0]);
  r.cy = detail::resizeCoordinate(k.cy, s[1]);
  return r;
}

}  // namespace mdbrief
