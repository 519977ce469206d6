#include "patchextract/patch_sampler.hpp"

#include <algorithm>
#include <cmath>

#include "mdbrief/tangent_plane.hpp"
#include "mdbrief/test_set.hpp"

namespace mdbrief::train {

namespace {

// Rays this far from the axis make Pi_lambda degenerate; the runtime's default limit.
constexpr double kMaxIncidenceDeg = 80.0;

bool bilinear(const cv::Mat& img, double x, double y, uint8_t& value) {
  if (!(x >= 0 && y >= 0 && x < img.cols - 1 && y < img.rows - 1)) return false;  // + neighbour
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const uint8_t* r0 = img.ptr<uint8_t>(y0) + x0;
  const uint8_t* r1 = r0 + img.step[0];
  const double v = (r0[0] * (1 - fx) + r0[1] * fx) * (1 - fy) + (r1[0] * (1 - fx) + r1[1] * fx) * fy;
  value = static_cast<uint8_t>(std::lround(v));
  return true;
}

}  // namespace

int samplingLevel(const ImagePyramid& pyramid, double keypointSize) {
  // The level whose scale is nearest (in log) to the keypoint's; scanning the levels also
  // covers pyramids with an upsampled firstLevel.
  const double target = std::log(std::max(keypointSize, 1e-6) / kReferenceKeypointSize);
  int best = 0;
  for (int k = 1; k < pyramid.levels(); ++k)
    if (std::abs(std::log(pyramid.scale(k)) - target) <
        std::abs(std::log(pyramid.scale(best)) - target) - 1e-9)
      best = k;
  return best;
}

namespace {

// Calls visit(index, x, y) with the level coordinates of every patch pixel, row-major; stops
// and returns false as soon as visit does or a sample cannot be placed.
template <class Visit>
bool forEachSample(const ImagePyramid& pyramid, const cv::KeyPoint& kp, const Camera* camera,
                   int level, Visit visit) {
  if (!std::isfinite(kp.pt.x) || !std::isfinite(kp.pt.y) || !(kp.size > 0)) return false;
  const double scale = pyramid.scale(level);
  const double step0 = kp.size / kReferenceKeypointSize;  // level-0 pixels per patch pixel
  if (!camera) {
    const double a = (kp.angle >= 0 ? kp.angle : 0.0) * CV_PI / 180.0;
    const double c = std::cos(a) * step0 / scale, s = std::sin(a) * step0 / scale;
    const double cx = kp.pt.x / scale, cy = kp.pt.y / scale;
    for (int j = 0; j < kPatchSize; ++j)
      for (int i = 0; i < kPatchSize; ++i) {
        const double qx = i - kPatchHalf, qy = j - kPatchHalf;
        if (!visit(j * kPatchSize + i, cx + c * qx - s * qy, cy + s * qx + c * qy)) return false;
      }
    return true;
  }
  const auto frame = tangentPlaneAt(*camera, cv::Point2d(kp.pt.x, kp.pt.y), kMaxIncidenceDeg);
  if (!frame) return false;
  const double a =
      (kp.angle >= 0 ? imageAngleToPlaneAngle(frame->jacobian, kp.angle) : 0.0) * CV_PI / 180.0;
  // Plane units per patch pixel: the test set is added on Pi_lambda scaled like the image step.
  const double c = std::cos(a) * step0, s = std::sin(a) * step0;
  for (int j = 0; j < kPatchSize; ++j)
    for (int i = 0; i < kPatchSize; ++i) {
      const double qx = i - kPatchHalf, qy = j - kPatchHalf;
      const cv::Point2d plane(frame->anchor.x + c * qx - s * qy, frame->anchor.y + s * qx + c * qy);
      cv::Point2d px;
      if (!planeToPixel(*camera, frame->lambda, plane, px) || !camera->isValid(px)) return false;
      if (!visit(j * kPatchSize + i, px.x / scale, px.y / scale)) return false;
    }
  return true;
}

bool insideForBilinear(const cv::Size& size, double x, double y) {
  return x >= 0 && y >= 0 && x < size.width - 1 && y < size.height - 1;
}

}  // namespace

bool patchFits(const ImagePyramid& pyramid, const cv::KeyPoint& kp, const Camera* camera) {
  const int level = samplingLevel(pyramid, kp.size);
  const cv::Size size = pyramid.image(level).size();
  return forEachSample(pyramid, kp, camera, level, [&](int, double x, double y) {
    return insideForBilinear(size, x, y);
  });
}

bool samplePatch(const ImagePyramid& pyramid, const cv::KeyPoint& kp, const Camera* camera,
                 uint8_t* out) {
  const int level = samplingLevel(pyramid, kp.size);
  const cv::Mat& img = pyramid.smoothed(level);
  return forEachSample(pyramid, kp, camera, level, [&](int index, double x, double y) {
    return bilinear(img, x, y, out[index]);
  });
}

}  // namespace mdbrief::train
