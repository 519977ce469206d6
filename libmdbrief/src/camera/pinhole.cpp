#include "mdbrief/camera/pinhole.hpp"

#include "camera/construction.hpp"
#include "camera/registry.hpp"
#include "camera/model_utils.hpp"

namespace mdbrief {

PinholeCamera::PinholeCamera(const CameraIntrinsics& intrinsics) : CameraWithIntrinsics(intrinsics, "pinhole") {}

bool PinholeCamera::pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const {
  if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return false;
  const cv::Vec2d m = normalise(pixel);
  bearing = detail::normalized({m[0], m[1], 1.0});
  return true;
}

bool PinholeCamera::projectRay(const cv::Vec3d& b, cv::Point2d& pixel) const {
  // Rays at or behind the image plane have no perspective image.
  if (!(b[2] > 0.0)) return false;
  pixel = denormalise(b[0] / b[2], b[1] / b[2]);
  return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

bool PinholeCamera::projectRayJacobian(const cv::Vec3d& b, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
  if (!projectRay(b, pixel)) return false;
  jacobian = detail::scaleRows(p_.fx, p_.fy, detail::perspectiveJacobian(b));
  return true;
}

bool PinholeCamera::isValid(const cv::Point2d& pixel) const { return detail::insideImage(pixel, imageSize()); }

// The model in the calibration files (camera/registry.hpp).
namespace detail {

ModelFormat pinholeModelFormat() {
  return {"pinhole", {"fx", "fy", "cx", "cy"},
          [](const std::string& source, const YamlReader& r, int width, int height) {
            return construct<PinholeCamera>(source, readIntrinsics(r, width, height));
          },
          [](const Camera& camera, YAML::Emitter& out) { emitIntrinsics(out, as<PinholeCamera>(camera).intrinsics()); },
          {std::set<std::string>{}}};  // fx fy cx cy only
}

}  // namespace detail
}  // namespace mdbrief
