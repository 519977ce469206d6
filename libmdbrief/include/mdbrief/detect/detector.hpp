#pragma once
// The keypoint detectors, on the shared ImagePyramid.
//
// DetectorMethod::ModOrb ("modORB" in the paper): ORB's detection scheme. Per level: FAST or
// AGAST corners, Harris-score ranking, a feature budget that decreases geometrically with the
// level (as cv::ORB), optional quadtree spreading, and the intensity-centroid orientation. Keypoints are in level-0 pixels with octave = level,
// size = patchSize * scale(level) and response = Harris score, as cv::ORB's.
//
// DetectorMethod::Hessian: scale-space blobs. On every level, the determinant of the Hessian
// at a fixed smoothing (hessianSigma level pixels), scale-normalised so that levels compare;
// maxima over space and over both neighbouring levels (so never on the first or last level,
// whose maxima may belong to a structure finer or coarser than the pyramid), refined to
// sub-pixel position and sub-level scale; the nfeatures strongest over all levels (or one
// quadtree over the image with `spread`), by the determinant weighted with the blob's scale
// (hessianScaleExponent); each kept blob's position then measured again on the input image at
// the blob's own scale (relocalise).
// size = patchSize * the refined scale, octave = the level, response = the weighted normalised
// determinant, angle = the intensity centroid.
//
// Keypoints are only returned where the descriptor's rotated 32x32 patch fits: at least
// borderMargin level pixels from the level's border and, with a camera, from the boundary
// of the camera's valid area. An explicit mask is tested at the keypoint's position only
// (cv::Feature2D's semantics).
#include <functional>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/base/enum_names.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/base/option_fields.hpp"

namespace mdbrief {

namespace detail {
class ConformalView;
}

enum class CornerDetector { Fast, Agast };
inline constexpr EnumName<CornerDetector> kCornerDetectorNames[] = {{CornerDetector::Fast, "fast"},
                                                                    {CornerDetector::Agast, "agast"}};
inline std::string toString(CornerDetector corners) { return nameOf(corners, kCornerDetectorNames); }
inline CornerDetector parseCornerDetector(const std::string& name) {
  return parseName(name, kCornerDetectorNames, "corner detector");
}

enum class DetectorMethod { ModOrb, Hessian };
inline constexpr EnumName<DetectorMethod> kDetectorMethodNames[] = {{DetectorMethod::ModOrb, "modorb"},
                                                                    {DetectorMethod::Hessian, "hessian"}};
inline std::string toString(DetectorMethod method) { return nameOf(method, kDetectorMethodNames); }
inline DetectorMethod parseDetectorMethod(const std::string& name) {
  return parseName(name, kDetectorMethodNames, "detector method");
}

struct DetectorOptions {
  // Hessian: more right two-view fits than modORB on real fisheye and perspective pairs, and
  // more repeatable across scale (docs/RESULTS.md "Real images: what a tracker keeps").
  DetectorMethod method = DetectorMethod::Hessian;
  int nfeatures = 1000;               // upper bound on the number of keypoints returned
  // Levels, scale factor and first level (cv::ORB's nlevels / scaleFactor / firstLevel; its 8,
  // 1.2 and 0 are PyramidOptions' defaults). Here a level below the input (the image enlarged
  // by the scale factor) finds the small blobs that carry most of a wide-angle frame's detail,
  // and 11 levels of 1.25 span the scale changes of wide baselines (docs/RESULTS.md "Real images:
  // what a tracker keeps"). The smoothing is the Hessian's own Gaussian (hessianSigma, 3 sigma
  // wide), so detection and description share one blur per level.
  PyramidOptions pyramid{11, 1.25, 1, 13, 2.0};
  // FAST-9/16 or AGAST OAST-9/16. FAST by default: OpenCV 4.6's AGAST has no SIMD path and
  // is the slower one here, unlike in the paper (docs/RESULTS.md "Detector").
  CornerDetector corners = CornerDetector::Fast;
  int threshold = 20;                 // FAST/AGAST intensity threshold (cv::ORB's default)
  // Used instead on a level where `threshold` finds fewer corners than the level's budget
  // (low-contrast images), as ORB-SLAM does; equal to `threshold` disables the retry.
  int fallbackThreshold = 7;
  int harrisBlockSize = 7;            // window of the Harris score (cv::ORB: 7)
  double harrisK = 0.04;              // Harris' k (cv::ORB: 0.04)
  // Spread each level's keypoints with a quadtree (one keypoint per cell, the cell with the
  // most candidates split first) instead of keeping the strongest. Off by default: it covers
  // more of the image but keeps weaker corners, and repeatability under a homography drops
  // (tests/test_detector.cpp prints both; docs/RESULTS.md "Detector").
  bool spread = false;
  // Hessian: Gaussian smoothing of the derivatives, in level pixels (chosen on the validation
  // photos: docs/RESULTS.md "Whole pipelines"), and the smallest normalised
  // determinant kept (intensities in [0, 1]).
  double hessianSigma = 2.0;
  double hessianThreshold = 1e-5;
  // Hessian: blobs compete for nfeatures by their normalised determinant times
  // scale^hessianScaleExponent (scale: input pixels per level pixel, refined), which is also
  // their response. 0 ranks by the determinant alone, which favours fine blobs; coarse blobs
  // survive blur and zoom and match more often (docs/RESULTS.md "Coarse blobs first").
  // The scale of a blob is still chosen by the determinant alone.
  double hessianScaleExponent = 1.0;
  // Hessian: locate each kept blob again on the input image, smoothed to the blob's own scale,
  // instead of on its level, which is a chain of bilinear reductions whose varying sampling phase
  // moves a blob's peak by a fraction of a level pixel (input pixels on coarse levels). On real
  // stereo pairs, the epipolar residual of keypoints from level 4 and above falls by a fifth and
  // more, and relative poses improve (docs/RESULTS.md "Keypoints located on the input").
  bool relocalise = true;
  int orientationRadius = 15;         // circular patch of the intensity centroid (cv::ORB: 15)
  int patchSize = 31;                 // keypoint size = patchSize * scale (cv::ORB: 31)
  // Minimum distance (level pixels) to the level's border and to the camera's invalid area.
  // 24 = ceil(16 * sqrt(2)) + 1: the 32x32 patch at any rotation plus one bilinear neighbour.
  int borderMargin = 24;
  // Detect on the camera's view in the stereographic projection (conformal: a structure keeps
  // its shape wherever the lens sees it) and map the keypoints back through the camera model,
  // size included. Needs a camera (ignored without one). Off by default: docs/RESULTS.md
  // "Whole pipelines" ("detection on a conformal image") has what it changes.
  bool conformal = false;
};

// The fields of DetectorOptions, the pyramid's included as "pyramid.<member>" (option_fields.hpp).
const OptionTable<DetectorOptions>& detectorOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const DetectorOptions& options);

// Features per level, as cv::ORB distributes them: level k gets a share proportional to
// (1 / scaleFactor)^k, the last level the remainder, so the shares add up to nfeatures.
std::vector<int> featuresPerLevel(int nfeatures, int levels, double scaleFactor);

// 255 where camera.isValid(pixel), 0 elsewhere, for an image of `size` (the camera is resized
// when size differs from its calibration size). Throws std::invalid_argument on an empty size.
cv::Mat validAreaMask(const Camera& camera, cv::Size size);

class Detector {
 public:
  // With a camera, keypoints keep borderMargin level pixels away from its invalid area, and
  // images must have the camera's imageSize().
  explicit Detector(CameraPtr camera = nullptr, DetectorOptions options = {});

  // The pyramid must have been built with options().pyramid's levels and scale factor.
  // mask: empty, or CV_8UC1 of the level-0 size, nonzero = allowed. Output sorted by
  // response (descending), then y, then x, then octave. Throws std::invalid_argument on a
  // mismatching pyramid, mask or image size.
  // measureAngles = false leaves every angle at -1: for a descriptor that measures its own
  // (dBRIEF/mdBRIEF on the tangent plane), which saves the intensity centroid of each keypoint.
  std::vector<cv::KeyPoint> detect(const ImagePyramid& pyramid, const cv::Mat& mask = {},
                                   bool measureAngles = true) const;
  // Builds the pyramid (8UC1/8UC3/8UC4 input) and detects on it. Both overloads keep no
  // state between calls: one Detector may be used from several threads.
  std::vector<cv::KeyPoint> detect(const cv::Mat& image, const cv::Mat& mask = {}) const;

  const DetectorOptions& options() const { return options_; }
  const CameraPtr& camera() const { return camera_; }

 private:
  // Whether a candidate at level pixel (x, y) of `level` keeps its margin from the invalid area.
  using Allowed = std::function<bool(int level, int x, int y)>;
  // The `budget` strongest (corners: per level, as cv::ORB shares it out) of those `allowed`
  // and whose keypoint position the mask (empty, or as detect()'s) allows.
  std::vector<cv::KeyPoint> detectCorners(const ImagePyramid& pyramid, const Allowed& allowed, const cv::Mat& mask,
                                          int budget, bool measureAngles) const;
  std::vector<cv::KeyPoint> detectBlobs(const ImagePyramid& pyramid, const Allowed& allowed, const cv::Mat& mask,
                                        int budget, bool measureAngles) const;

  DetectorOptions options_;
  CameraPtr camera_;
  // The pixels of a level at least borderMargin level pixels from the nearest invalid pixel, as
  // runs [begin, end) along each row: a lookup stays in the cache, where an image of distances
  // missed it for most candidates.
  struct MarginRuns {
    std::vector<int> rowStart;    // rows + 1 offsets into runs
    std::vector<cv::Vec2i> runs;
    bool contains(int x, int y) const;
  };
  static std::vector<MarginRuns> keepingMargin(const cv::Mat& validMask, const PyramidOptions& pyramid, int margin);
  // Per level, with a camera.
  std::vector<MarginRuns> keepsMargin_;
  // With options.conformal and a camera: the view detected on, and its pixels as above.
  std::shared_ptr<const detail::ConformalView> conformal_;
  std::vector<MarginRuns> conformalKeepsMargin_;

  std::vector<cv::KeyPoint> detectConformal(const ImagePyramid& pyramid, const cv::Mat& mask,
                                            bool measureAngles) const;
};

}  // namespace mdbrief
