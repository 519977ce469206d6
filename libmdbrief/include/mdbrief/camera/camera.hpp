#pragma once
// The camera interface every model implements. Conventions, shared by all models:
// - pixel coordinates (u, v): u = column, v = row, origin at the centre of the top-left
//   pixel (OpenCV's convention, so cv::KeyPoint::pt can be passed unchanged);
// - bearings are unit 3-vectors in the camera frame: x right, y down, z along the optical axis;
// - all models work at the calibration's resolution, imageSize().
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
  // outside the image; isValid() tells whether it is usable. Lengths whose squared components
  // overflow or underflow (above about 1e154, below about 1e-154) may give false, never a
  // non-finite pixel: scale such rays towards 1 first, as the Python binding does.
  virtual bool bearingToPixel(const cv::Vec3d& bearing, cv::Point2d& pixel) const = 0;
  // bearingToPixel with its derivative d pixel / d bearing (2x3) at `bearing`, in closed form:
  // the tangent plane's Jacobian at every keypoint (tangent_plane.hpp) without iterating the
  // inverse model. The same pixel and the same false cases as bearingToPixel.
  virtual bool bearingToPixelJacobian(const cv::Vec3d& bearing, cv::Point2d& pixel, cv::Matx23d& jacobian) const = 0;

  // True when the pixel is inside the image and inside the lens' usable area (image circle,
  // field of view). Descriptors never sample where this is false.
  virtual bool isValid(const cv::Point2d& pixel) const = 0;

  // Scale lambda of the tangent plane used by dBRIEF (the paper's Pi_lambda): the focal
  // length for perspective models, |a0| for OCamCalib. Tests added on Pi_lambda therefore have
  // about the size, in pixels, they have at the image centre.
  virtual double tangentPlaneScale() const = 0;

  // The same lens at another image resolution (a uniform resample of the image).
  virtual std::shared_ptr<Camera> resized(cv::Size newSize) const = 0;
};

using CameraPtr = std::shared_ptr<const Camera>;

}  // namespace mdbrief
