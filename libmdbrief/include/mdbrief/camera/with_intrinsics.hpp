#pragma once
// What every perspective-family camera model (pinhole, radial, Kannala-Brandt, double sphere,
// UCM/EUCM, radial-tangential, omni) shares, written once: parameters that hold the linear part
// (CameraIntrinsics), the image size it gives, the linear map between pixels and normalised
// coordinates, the tangent-plane scale, and resized(), which rescales the linear part and keeps
// the rest. A model derives from CameraWithIntrinsics<Model, ModelParams>, is constructible from
// ModelParams, and writes its model name and projection.
#include <memory>
#include <string>
#include <type_traits>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/intrinsics.hpp"

namespace mdbrief {

template <class Model, class Params>
class CameraWithIntrinsics : public Camera {
 public:
  const Params& params() const { return p_; }
  const CameraIntrinsics& intrinsics() const { return linearPart(p_); }

  cv::Size imageSize() const override { return intrinsics().size(); }
  // (fx + fy) / 2: the mean focal length, so non-square pixels get the average footprint.
  double tangentPlaneScale() const override { return 0.5 * (intrinsics().fx + intrinsics().fy); }
  std::shared_ptr<Camera> resized(cv::Size newSize) const override {
    return std::make_shared<Model>(resizedParams(newSize));
  }

 protected:
  // Throws std::invalid_argument "<model>: ..." for bad intrinsics (validateIntrinsics).
  CameraWithIntrinsics(const Params& params, const std::string& model) : p_(params) {
    validateIntrinsics(intrinsics(), model);
  }

  // The parameters of the image resampled to newSize: the linear part rescaled, the rest kept.
  Params resizedParams(cv::Size newSize) const {
    Params r = p_;
    linearPart(r) = resizeIntrinsics(intrinsics(), newSize);
    return r;
  }

  // ((u - cx) / fx, (v - cy) / fy): the pixel on the normalised plane, before undistortion.
  cv::Vec2d normalise(const cv::Point2d& pixel) const {
    const CameraIntrinsics& k = intrinsics();
    return {(pixel.x - k.cx) / k.fx, (pixel.y - k.cy) / k.fy};
  }
  // (fx x + cx, fy y + cy): the inverse of normalise.
  cv::Point2d denormalise(double x, double y) const {
    const CameraIntrinsics& k = intrinsics();
    return {k.fx * x + k.cx, k.fy * y + k.cy};
  }

  Params p_;

 private:
  // The pinhole camera's parameters are the linear part itself; the others hold it as `intrinsics`.
  template <class P>
  static auto& linearPart(P& params) {
    if constexpr (std::is_same_v<std::remove_const_t<P>, CameraIntrinsics>)
      return params;
    else
      return params.intrinsics;
  }
};

}  // namespace mdbrief
