#pragma once
// A random change of viewpoint of a training image, with exact pixel correspondence: the data
// from which the trainer learns which tests survive a change of view (test stability).
// - Without a camera: a homography about the image centre that tilts the scene (a rotation of
//   the camera about an in-plane axis, focal length = image width), rolls it and zooms it.
// - With a camera (fisheye): the same lens turned by a random rotation (yaw/pitch up to the
//   tilt, roll) and zoomed (the lens resampled), so structures move between the centre and
//   the rim and the distortion they see changes; a pure rotation needs no scene depth.
// Blur and sensor noise follow the warp, as a second exposure would have them.
#include <cstdint>
#include <memory>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/base/option_fields.hpp"

namespace mdbrief::train {

// Defaults chosen on the validation set (docs/training.md "Validation": milder and stronger
// changes both scored lower).
struct ViewChangeOptions {
  double maxTiltDeg = 40.0;     // out-of-plane rotation, uniform in [0, max]
  double maxRollDeg = 180.0;    // in-plane rotation, uniform in [-max, max]
  double maxZoom = 1.3;         // zoom factor log-uniform in [1/max, max]
  double maxBlurSigma = 1.0;    // Gaussian blur sigma, uniform in [0, max] pixels
  double maxNoiseSigma = 3.0;   // additive Gaussian noise sigma, uniform in [0, max] grey levels
};

// The fields of ViewChangeOptions (mdbrief/base/option_fields.hpp).
const OptionTable<ViewChangeOptions>& viewChangeOptionFields();
// Throws OptionError naming the option.
void validate(const ViewChangeOptions& options);

class ViewChange {
 public:
  virtual ~ViewChange() = default;
  // Source pixel -> view pixel; false where the point has no image in the view.
  virtual bool toView(const cv::Point2d& source, cv::Point2d& view) const = 0;
  // View pixel -> source pixel; false where the view sees nothing of the source.
  virtual bool toSource(const cv::Point2d& view, cv::Point2d& source) const = 0;
  // The camera of the view (null without a camera).
  virtual CameraPtr viewCamera() const = 0;
  virtual cv::Size viewSize() const = 0;

  // The warped, blurred and noisy view of `source` (8UC1; 0 where toSource fails). The noise
  // comes from noiseSeed, so a view is reproducible.
  cv::Mat render(const cv::Mat& source, uint64_t noiseSeed) const;
  // Square root of the area scale of toView at `source` (finite differences): how much larger
  // a structure appears in the view.
  double localZoom(const cv::Point2d& source) const;

  double blurSigma = 0, noiseSigma = 0;
};

// A random view change of an image of `size` (with `camera` at that size, or null), drawn
// from seed; the same seed gives the same change on every platform (std::mt19937, own
// uniform mapping).
std::unique_ptr<ViewChange> randomViewChange(cv::Size size, const CameraPtr& camera,
                                             const ViewChangeOptions& options, uint64_t seed);

// The lens turned by `rotation` (bearing in the view = rotation * bearing in the source), at
// the same resolution, without blur or noise: a real photo seen by a turned camera, exactly.
std::unique_ptr<ViewChange> lensRotation(const CameraPtr& camera, const cv::Matx33d& rotation);

}  // namespace mdbrief::train
