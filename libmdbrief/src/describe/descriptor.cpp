#include "mdbrief/describe/descriptor.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

#include "describe/descriptor_kernels.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "describe/comparison_placement.hpp"

namespace mdbrief {
namespace {

using namespace descriptor_kernels;
using namespace placement;

// Nearest-pixel tests (DescriptorOptions::sampling), no default's hot loop: plain C++.
void packBitsNearest(const uint8_t* data, size_t step, const int* x, const int* y, int nTests, uint8_t* out) {
  for (int byte = 0; byte < nTests / 8; ++byte) {
    unsigned v = 0;
    for (int b = 0; b < 8; ++b) {
      const int d = byte * 8 + b;
      v |= static_cast<unsigned>(sampleNearest(data, step, x[d], y[d]) <
                                 sampleNearest(data, step, x[nTests + d], y[nTests + d]))
           << b;
    }
    out[byte] = static_cast<uint8_t>(v);
  }
}

// Bits of one placement: x, y hold the first points of the tests, then their second points.
// img is the smoothed level, pairs its row pairs.
void sampleDescriptor(const cv::Mat& img, const cv::Mat& pairs, const int* x, const int* y, int nTests,
                      Sampling sampling, const SamplingKernels& kernels, uchar* out) {
  if (sampling == Sampling::Nearest) return packBitsNearest(img.data, img.step[0], x, y, nTests, out);
  kernels.packBitsBilinear(pairs.data, pairs.step[0], x, y, nTests, out);
}

// The tests' first points, then their second points.
Offsets offsetsOf(const ComparisonSet& tests) {
  const size_t n = tests.tests.size();
  std::vector<int32_t> x(2 * n), y(2 * n);
  for (size_t d = 0; d < n; ++d) {
    const ComparisonPair& t = tests.tests[d];
    x[d] = t.x1, y[d] = t.y1, x[n + d] = t.x2, y[n + d] = t.y2;
  }
  return {std::move(x), std::move(y)};
}

}  // namespace

DescriptorExtractor::DescriptorExtractor(CameraPtr camera, DescriptorOptions options)
    : DescriptorExtractor(camera, options,
                          resolveComparisonSet(options.pattern.empty() ? defaultComparisonSetName() : options.pattern)) {}

DescriptorExtractor::DescriptorExtractor(CameraPtr camera, DescriptorOptions options, const ComparisonSet& tests)
    : camera_(std::move(camera)), options_(std::move(options)) {
  validate(options_);
  if (!camera_ && usesCamera(options_.kind)) throw std::invalid_argument("dBRIEF and mdBRIEF need a camera model");
  if (static_cast<int>(tests.tests.size()) < options_.bits)
    throw std::invalid_argument("test set '" + tests.name + "' has " + std::to_string(tests.tests.size()) +
                                " tests, fewer than bits=" + std::to_string(options_.bits));
  tests_ = tests.first(options_.bits);
}

bool DescriptorExtractor::measuresOrientation() const { return placement::measuresOrientation(options_); }

void DescriptorExtractor::compute(const ImagePyramid& pyramid, std::vector<cv::KeyPoint>& keypoints,
                                  cv::OutputArray descriptors, cv::OutputArray masks) const {
  const int n = static_cast<int>(keypoints.size());
  const int bytes = descriptorBytes();
  const int nTests = options_.bits;
  const bool wantMasks = hasMasks(options_.kind);
  // Each keypoint's level and footprint from its size; octave is not read.
  std::vector<Support> supports(n);
  const std::vector<double> scales = pyramidScales(pyramid);
  std::vector<char> used(scales.size(), 0);
  for (int i = 0; i < n; ++i) {
    supports[i] = supportOf(keypoints[i].size, options_.supportScale, scales);
    if (supports[i].level >= 0) used[supports[i].level] = 1;
  }
  std::vector<int> usedLevels;
  for (size_t k = 0; k < used.size(); ++k)
    if (used[k]) usedLevels.push_back(static_cast<int>(k));
  // The levels the keypoints use, each once, in parallel ahead of parallel sampling; not the
  // others (the Hessian detector leaves its finest level unsmoothed).
  tbb::parallel_for(size_t{0}, usedLevels.size(), [&](size_t i) { pyramid.smoothedPairs(usedLevels[i]); });

  cv::Mat desc(n, bytes, CV_8U, cv::Scalar(0)), mask(wantMasks ? n : 0, bytes, CV_8U, cv::Scalar(0));
  std::vector<uchar> ok(n, 0);
  std::vector<float> angles(n, -1.f);
  const Camera* camera = camera_.get();
  const Offsets offsets = offsetsOf(tests_);
  const bool measure = measuresOrientation();
  const Disc disc = orientationDisc(options_);
  const SamplingKernels kernels = activeSamplingKernels();

  tbb::parallel_for(tbb::blocked_range<int>(0, n, 16), [&](const tbb::blocked_range<int>& range) {
    PlacedPoints points(offsets.x.size(), disc.u.size());
    std::array<uchar, 64> bits[3];
    for (int i = range.begin(); i != range.end(); ++i) {
      const Support& support = supports[i];
      if (support.level < 0) continue;  // no usable size
      const cv::Mat& img = pyramid.smoothed(support.level);
      const cv::Mat& pairs = pyramid.smoothedPairs(support.level);
      const int count = placeChecked(options_, camera, offsets, disc, kernels, keypoints[i], pairs,
                                     pyramid.grid(support.level), support, points, angles[i]);
      if (count == 0) continue;
      for (int r = 0; r < count; ++r)
        sampleDescriptor(img, pairs, &points.x[2 * nTests * r], &points.y[2 * nTests * r], nTests,
                         options_.sampling, kernels, bits[r].data());
      std::copy_n(bits[0].data(), bytes, desc.ptr<uchar>(i));
      if (wantMasks) {
        uchar* m = mask.ptr<uchar>(i);
        for (int b = 0; b < bytes; ++b)
          m[b] = static_cast<uchar>(~((bits[0][b] ^ bits[1][b]) | (bits[0][b] ^ bits[2][b])));
      }
      ok[i] = 1;
    }
  });

  // Drop the keypoints that could not be described, keeping rows aligned with keypoints.
  int kept = 0;
  for (int i = 0; i < n; ++i) {
    if (!ok[i]) continue;
    if (measure) keypoints[i].angle = angles[i];
    if (kept != i) {
      keypoints[kept] = keypoints[i];
      // Row pointers: the cv::Mat row headers showed in the profile.
      std::copy_n(desc.ptr<uchar>(i), bytes, desc.ptr<uchar>(kept));
      if (wantMasks) std::copy_n(mask.ptr<uchar>(i), bytes, mask.ptr<uchar>(kept));
    }
    ++kept;
  }
  keypoints.resize(kept);
  if (descriptors.needed()) descriptors.assign(desc.rowRange(0, kept).clone());
  if (masks.needed()) {
    if (wantMasks)
      masks.assign(mask.rowRange(0, kept).clone());
    else
      masks.release();
  }
}

void DescriptorExtractor::compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints,
                                  cv::OutputArray descriptors, cv::OutputArray masks,
                                  const PyramidOptions& pyramidOptions) const {
  const ImagePyramid pyramid(image, pyramidOptions, levelsFor(keypoints, pyramidOptions));
  compute(pyramid, keypoints, descriptors, masks);
}

int DescriptorExtractor::levelsFor(const std::vector<cv::KeyPoint>& keypoints, const PyramidOptions& pyramid) const {
  validate(pyramid);  // pyramidScales() needs at least one level
  int levels = 1;
  const std::vector<double> scales = pyramidScales(pyramid);
  for (const auto& kp : keypoints) levels = std::max(levels, supportOf(kp.size, options_.supportScale, scales).level + 1);
  return levels;
}

std::vector<std::pair<cv::Point2f, cv::Point2f>> DescriptorExtractor::comparisonPositions(
    const ImagePyramid& pyramid, const cv::KeyPoint& keypoint) const {
  const Support support = supportOf(keypoint.size, options_.supportScale, pyramidScales(pyramid));
  if (support.level < 0) return {};
  const Disc disc = orientationDisc(options_);
  const LevelGrid grid = pyramid.grid(support.level);
  const int nTests = options_.bits;
  const Offsets offsets = offsetsOf(tests_);
  PlacedPoints points(offsets.x.size(), disc.u.size());
  float imageAngle;
  if (placeChecked(options_, camera_.get(), offsets, disc, activeSamplingKernels(), keypoint,
                   pyramid.smoothedPairs(support.level), grid, support, points, imageAngle) == 0)
    return {};
  std::vector<std::pair<cv::Point2f, cv::Point2f>> out(nTests);
  const auto input = [&](int i) { return cv::Point2f(grid.toInput(cv::Point2d(points.x[i], points.y[i]) / kSub)); };
  for (int d = 0; d < nTests; ++d) out[d] = {input(d), input(nTests + d)};
  return out;
}

}  // namespace mdbrief
