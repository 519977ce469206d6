#pragma once
// Where BRIEF, dBRIEF and mdBRIEF sample one keypoint: the pyramid level and footprint from its
// size, the orientation (the keypoint's angle or re-measured on the tangent plane), the map of
// offsets to level coordinates (BRIEF, the Affine form) or their projection through the camera
// (the Paper form), and the checks that drop a keypoint. compute(), comparisonPositions() and the
// training patches (mdbrief/internal/describe/patch_sampling.hpp) all place through placeChecked().
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "describe/descriptor_kernels.hpp"
#include "mdbrief/camera/camera.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief::placement {

// Points of the offset frame (comparison_set.hpp), integers, structure of arrays.
struct Offsets {
  Offsets() = default;
  // Throws std::invalid_argument for an offset beyond descriptor_kernels::kMaxOffset.
  Offsets(std::vector<int32_t> x, std::vector<int32_t> y);
  std::vector<int32_t> x, y;
  // The corners of the points' bounding box. An affine placement, rounded as the kernels round
  // it, is monotonic in each offset coordinate, so when the corners land inside the level every
  // point does: four points decide the bounds check of almost every keypoint.
  std::array<int32_t, 4> boxX{}, boxY{};
};

// Where a keypoint is sampled: the pyramid level whose scale is nearest (in log) to the
// footprint's, and the footprint relative to that level (1 when it is the level's own).
struct Support {
  int level = -1;  // -1: the size is not finite or the footprint is under one pixel
  double fraction = 1.0;
};

// The tests' 31-pixel diameter spans supportScale * size input pixels.
Support supportOf(float size, double supportScale, const std::vector<double>& scales);
std::vector<double> pyramidScales(const PyramidOptions& options);
std::vector<double> pyramidScales(const ImagePyramid& pyramid);

// The disc of the intensity centroid that re-measures the orientation on the tangent plane
// (DescriptorOptions::orientationRadius); no samples when `options` do not re-measure it.
struct Disc {
  Offsets offsets;
  std::vector<int> u, v;
};
Disc orientationDisc(const DescriptorOptions& options);
// Whether compute() replaces the keypoint's angle with its own measurement.
bool measuresOrientation(const DescriptorOptions& options);

// Quantised level coordinates (descriptor_kernels.hpp) of every rotation of n offsets:
// rotation r's points at [r * n, (r + 1) * n) of x and y; disc buffers for the orientation.
struct PlacedPoints {
  PlacedPoints(size_t offsets, size_t discSamples)
      : x(3 * offsets), y(3 * offsets), discX(discSamples), discY(discSamples) {}
  std::vector<int> x, y, discX, discY;
};

// Places every rotation of `offsets` for `kp` on `pairs` (ImagePyramid::smoothedPairs of the
// level of `support`, placed in the input by `grid`): rotation 0, then (masked kinds)
// +maskRotationDeg and -maskRotationDeg.
// Returns the number of placements, 0 when the keypoint cannot be described: a point that
// cannot be projected, leaves the level or, with a camera, the valid area (the corners of the
// 32x32 offset square are checked there). imageAngle receives the image direction (degrees) of
// a re-measured orientation, else -1. `camera` may be null only for kinds without one.
int placeChecked(const DescriptorOptions& options, const Camera* camera, const Offsets& offsets, const Disc& disc,
                 const descriptor_kernels::SamplingKernels& kernels, const cv::KeyPoint& kp, const cv::Mat& pairs,
                 const LevelGrid& grid, const Support& support, PlacedPoints& points, float& imageAngle);

}  // namespace mdbrief::placement
