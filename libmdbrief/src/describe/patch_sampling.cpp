#include "mdbrief/internal/describe/patch_sampling.hpp"

#include <stdexcept>
#include <utility>
#include <vector>

#include "mdbrief/describe/comparison_set.hpp"
#include "describe/comparison_placement.hpp"

namespace mdbrief::internal {
namespace {

using namespace descriptor_kernels;
using namespace placement;

// Every offset of the patch, row-major: (i - 16, j - 16) for pixel (i, j).
Offsets patchGrid() {
  std::vector<int32_t> x, y;
  for (int j = 0; j < kPatchSize; ++j)
    for (int i = 0; i < kPatchSize; ++i) {
      x.push_back(i - kPatchHalf);
      y.push_back(j - kPatchHalf);
    }
  return {std::move(x), std::move(y)};
}

// The bilinear weights sum to kSub^2: rounded to the nearest grey level.
uint8_t bilinearGrey(const cv::Mat& img, int x, int y) {
  return static_cast<uint8_t>((sampleBilinear(img.data, img.step[0], x, y) + kSub * kSub / 2) >> (2 * kSubBits));
}

}  // namespace

bool samplePatch(const DescriptorOptions& options, const Camera* camera, const ImagePyramid& pyramid,
                 const cv::KeyPoint& keypoint, uint8_t* out, float& angle) {
  validate(options);
  if (!camera && usesCamera(options.kind)) throw std::invalid_argument("dBRIEF and mdBRIEF need a camera model");
  // The patch is the rotation-0 view. A masked kind also places the rotated views: compute()
  // drops a keypoint when one of them leaves the image or the valid area, so the sampler does too.
  const DescriptorOptions& o = options;
  const Support support = supportOf(keypoint.size, o.supportScale, pyramidScales(pyramid));
  if (support.level < 0) return false;
  static const Offsets grid = patchGrid();
  const Disc disc = orientationDisc(o);
  PlacedPoints points(grid.x.size(), disc.u.size());
  const cv::Mat& img = pyramid.smoothed(support.level);
  float imageAngle;
  if (placeChecked(o, camera, grid, disc, activeSamplingKernels(), keypoint, pyramid.smoothedPairs(support.level),
                   pyramid.grid(support.level), support, points, imageAngle) == 0)
    return false;
  for (size_t i = 0; i < grid.x.size(); ++i)
    out[i] = o.sampling == Sampling::Nearest
                 ? static_cast<uint8_t>(sampleNearest(img.data, img.step[0], points.x[i], points.y[i]))
                 : bilinearGrey(img, points.x[i], points.y[i]);
  angle = measuresOrientation(o) ? imageAngle : keypoint.angle;
  return true;
}

}  // namespace mdbrief::internal
