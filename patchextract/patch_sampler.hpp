#pragma once
// Training patches, sampled by the runtime descriptor's own placement
// (mdbrief/internal/describe/patch_sampling.hpp), so the trainer's candidate tests see the pixels the
// descriptor compares: patch pixel (i, j) is what compute() reads for a test point at offset
// (i - 16, j - 16) (comparison_set.hpp). An image without a calibration is described through the
// camera the evaluation assumes for photos (scenes/photo_camera.hpp), as dBRIEF and mdBRIEF
// describe the Oxford sequences.
#include <cstdint>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief::train {

// Fills out[32 * 32] (row-major) and angle (the keypoint's angle as compute() leaves it) for the
// descriptor options `placement`. calibration: the image's camera, or null for the photo camera
// of the pyramid's input size. False, out unspecified, when compute() would drop the keypoint or
// a patch pixel leaves the level or the camera's valid area.
bool samplePatch(const DescriptorOptions& placement, const Camera* calibration, const ImagePyramid& pyramid,
                 const cv::KeyPoint& keypoint, uint8_t* out, float& angle);

}  // namespace mdbrief::train
