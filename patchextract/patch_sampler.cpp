#include "patchextract/patch_sampler.hpp"

#include "mdbrief/internal/describe/patch_sampling.hpp"
#include "scenes/photo_camera.hpp"

namespace mdbrief::train {

bool samplePatch(const DescriptorOptions& placement, const Camera* calibration, const ImagePyramid& pyramid,
                 const cv::KeyPoint& keypoint, uint8_t* out, float& angle) {
  if (calibration || !usesCamera(placement.kind))
    return internal::samplePatch(placement, calibration, pyramid, keypoint, out, angle);
  const CameraPtr photo = photoCamera(pyramid.inputSize());
  return internal::samplePatch(placement, photo.get(), pyramid, keypoint, out, angle);
}

}  // namespace mdbrief::train
