#pragma once
// The 32x32 patch of a keypoint as the descriptor reads it, for the trainer's patches
// (patchextract/): pixel (i, j) holds the value compute() samples for a test point at offset
// (i - 16, j - 16) of the rotation-0 placement (comparison_set.hpp). The placement is compute()'s own
// code: level and footprint from the size, orientation (re-measured on the tangent plane when
// compute() re-measures it), Affine or Paper form, the same fixed-point positions on the same
// smoothed level, and the same checks; the bilinear value is rounded to 8 bits. So a test is 1
// on the patch exactly when compute() gives 1, except where rounding makes the two values equal.
#include <cstdint>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief::internal {

// cv::ORB's patch size: a keypoint of this size at scale 1 is described with step 1
// (DescriptorOptions::supportScale).
inline constexpr double kReferenceKeypointSize = 31.0;

// Fills out[32 * 32] (row-major) and sets angle to the keypoint's angle as compute() leaves it
// (the re-measured one when compute() re-measures it). False, out unspecified, when compute()
// would drop the keypoint or a patch pixel cannot be sampled (the patch covers every offset of
// the 32x32 square, a test set only some of them). Only the placement fields of `options`
// matter (kind, form, orientation, orientationRadius, useOrientation, maxIncidenceDeg,
// supportScale, sampling); a masked kind's rotated views are placed and checked, not sampled.
// camera may be null only for kinds without a camera. Throws std::invalid_argument for invalid options or a missing camera.
bool samplePatch(const DescriptorOptions& options, const Camera* camera, const ImagePyramid& pyramid,
                 const cv::KeyPoint& keypoint, uint8_t* out, float& angle);

}  // namespace mdbrief::internal
