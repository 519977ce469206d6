#pragma once
// The camera interface every model implements. Conventions, shared by all models:
// - pixel coordinates (u, v): u = column, v = row, origin at the centre of the top-left
//   pixel (OpenCV's convention, so cv::KeyPoint::pt can be passed unchanged);
// - bearings are unit 3-vectors in the camera frame: x right, y down, z along the optical axis;
// - all models work at the calibration's resolution, imageSize().
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief {

class Camera {
 public:
  virtual ~Camera() = default;

  // Short model identifier as used in the project's YAML ("pinhole", "ocam", ...).
  virtual std::string modelName() const = 0;
  virtual cv::Size imageSize() const = 0;

  // Pixel -> unit bearing. Returns false (bearing untouched) where the model has no inverse,
  // e.g. outside the lens' field of view.
  virtual bool pixelToBearing(const cv::Point2d& pixel, cv::Vec3d& bearing) const = 0;
  // Bearing (any non-zero length) -> pixel. Returns false where the model cannot project the
  // ray (behind a perspective camera, beyond the fisheye's field of view). The pixel may lie
  // outside the image; isValid() tells whether it is usable. The ray's length is free over all
  // of double's range, subnormals included: a ray whose largest component lies outside
  // [2^-400, 2^400], where the models' squares of the components would overflow or underflow,
  // is scaled by a power of two (exact) to a largest component in [0.5, 1) before the model
  // sees it; every other ray reaches the model unchanged. A zero ray, or one with a NaN
  // component, gives false. A ray with an infinite component reaches the model as it is and
  // gives false, except (finite, finite, +inf), which gives the principal point in the pinhole,
  // radial, radtan and Kannala-Brandt models and, for some parameters, UCM / EUCM and double
  // sphere.
  bool bearingToPixel(const cv::Vec3d& bearing, cv::Point2d& pixel) const {
    return inScaleBand(bearing) ? projectRay(bearing, pixel) : projectScaledRay(bearing, pixel);
  }
  // bearingToPixel with its derivative d pixel / d bearing (2x3) at `bearing`, in closed form:
  // the tangent plane's Jacobian at every keypoint (tangent_plane.hpp) without iterating the
  // inverse model. The same pixel and the same false cases as bearingToPixel. A scaled ray's
  // derivative is scaled back by the same power of two (the pixel is of degree 0 in the ray, so
  // its derivative is of degree -1): only where d pixel / d bearing itself exceeds double's
  // range (a subnormal ray) are its entries infinite.
  bool bearingToPixelJacobian(const cv::Vec3d& bearing, cv::Point2d& pixel, cv::Matx23d& jacobian) const {
    return inScaleBand(bearing) ? projectRayJacobian(bearing, pixel, jacobian)
                                : projectScaledRayJacobian(bearing, pixel, jacobian);
  }

  // True when the pixel is inside the image and inside the lens' usable area (image circle,
  // field of view). Descriptors never sample where this is false.
  virtual bool isValid(const cv::Point2d& pixel) const = 0;

  // Scale lambda of the tangent plane used by dBRIEF (the paper's Pi_lambda): the focal
  // length for perspective models, |a0| for OCamCalib. Tests added on Pi_lambda therefore have
  // about the size, in pixels, they have at the image centre.
  virtual double tangentPlaneScale() const = 0;

  // The same lens at another image resolution (a uniform resample of the image).
  virtual std::shared_ptr<Camera> resized(cv::Size newSize) const = 0;

 protected:
  // The model's projection, which bearingToPixel and bearingToPixelJacobian call: `ray` has its
  // largest component in [2^-400, 2^400] or an infinite one, never a NaN. Over that band the
  // squares of the largest component stay finite and normal, and the result must not depend on
  // the ray's length.
  virtual bool projectRay(const cv::Vec3d& ray, cv::Point2d& pixel) const = 0;
  virtual bool projectRayJacobian(const cv::Vec3d& ray, cv::Point2d& pixel, cv::Matx23d& jacobian) const = 0;

 private:
  // True when the largest |component| is in [2^-400, 2^400] (false for a NaN): the ray the
  // model is given unchanged, which keeps ordinary rays bit for bit as they were. Compared as
  // bit patterns, which order as the magnitudes (a NaN above infinity), in one comparison.
  static bool inScaleBand(const cv::Vec3d& b) {
    constexpr std::uint64_t kLow = std::uint64_t{1023 - 400} << 52, kHigh = std::uint64_t{1023 + 400} << 52;
    const auto magnitude = [](double v) {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof bits);
      return bits & ~(std::uint64_t{1} << 63);
    };
    return std::max({magnitude(b[0]), magnitude(b[1]), magnitude(b[2])}) - kLow <= kHigh - kLow;
  }
  // The rays outside the band (camera/camera.cpp).
  bool projectScaledRay(const cv::Vec3d& bearing, cv::Point2d& pixel) const;
  bool projectScaledRayJacobian(const cv::Vec3d& bearing, cv::Point2d& pixel, cv::Matx23d& jacobian) const;
};

using CameraPtr = std::shared_ptr<const Camera>;

}  // namespace mdbrief
