#pragma once
// Samples the 32x32 training patch of a keypoint the way the runtime descriptor places its
// tests, so the trainer's candidate tests see the pixels the descriptor will compare:
// - the keypoint's scale picks the pyramid level: step = size / 31 level-0 pixels per patch
//   pixel (ORB's patch size 31 at octave 0), level = the nearest 1.2^k, and on that level's
//   smoothed image (Gaussian 7x7, sigma 2, as ImagePyramid) the step is size / 31 / 1.2^k.
//   For ORB keypoints (size = 31 * 1.2^octave) that is the octave's level with step 1, exactly
//   the runtime's integer offsets;
// - the orientation rotates the offsets as the runtime does: (x, y) -> R(angle) (x, y);
// - with a camera (the paper's fisheye variant), the offsets are laid on the tangent plane
//   Pi_lambda at the undistorted keypoint, rotated by the keypoint angle carried onto the plane,
//   scaled by the step and projected through the camera (DistortionForm::Paper);
// - patch pixel (i, j) has offset (i - 16, j - 16) (test_set.hpp); values are bilinear
//   interpolations, rounded.
#include <cstdint>

#include <opencv2/core.hpp>

#include "mdbrief/camera.hpp"
#include "mdbrief/image_pyramid.hpp"

namespace mdbrief::train {

// Keypoint size of ORB's level 0 (cv::ORB's patchSize): defines step 1.
inline constexpr double kReferenceKeypointSize = 31.0;

// The pyramid level a keypoint of this size is sampled on: the one whose scale is nearest.
int samplingLevel(const ImagePyramid& pyramid, double keypointSize);

// True when samplePatch would succeed; needs no smoothed levels (cheap pre-selection).
bool patchFits(const ImagePyramid& pyramid, const cv::KeyPoint& keypoint, const Camera* camera);

// Fills out[32 * 32] (row-major). False, out unspecified, when a sample falls outside the
// level image (with its bilinear neighbour) or, with a camera, outside the camera's valid area
// or the projection fails. The pyramid's smoothed levels must be prepared.
bool samplePatch(const ImagePyramid& pyramid, const cv::KeyPoint& keypoint, const Camera* camera,
                 uint8_t* out);

}  // namespace mdbrief::train
