#pragma once
// BRIEF, dBRIEF and mdBRIEF extraction (paper sections "dBRIEF - Distorted BRIEF" and
// "Improving dBRIEF by On-line Mask Learning").
//
// Output layout: descriptors and masks are N x (bits / 8) CV_8U matrices, row i for keypoint i.
// Bit order: test d is bit (d % 8) of byte (d / 8), least significant bit first (as cv::ORB),
// so the first n tests of a longer set give exactly the first n/8 bytes.
// Test d is 1 when I(p1) < I(p2) on the smoothed pyramid level the keypoint's size selects.
// Mask bit d (mdBRIEF, masked BRIEF) is 1 when test d is stable: the same outcome for the test
// set rotated by 0, +maskRotationDeg and -maskRotationDeg.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/base/enum_names.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/base/option_fields.hpp"
#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief {

enum class DescriptorKind {
  Brief,    // tests rotated by the keypoint angle, no camera model
  DBrief,   // tests anchored on the undistorted keypoint, projected through the camera
  MdBrief,  // dBRIEF plus an on-line learned mask
  // BRIEF placement plus the on-line mask, no camera model (BOLD-like): with BRIEF, dBRIEF and
  // mdBRIEF it separates what the masks and what the distortion model contribute.
  MaskedBrief,
};
// The names users type, one table per enum (enum_names.hpp); parse* throw listing them.
inline constexpr EnumName<DescriptorKind> kDescriptorKindNames[] = {{DescriptorKind::Brief, "brief"},
                                                                    {DescriptorKind::DBrief, "dbrief"},
                                                                    {DescriptorKind::MdBrief, "mdbrief"},
                                                                    {DescriptorKind::MaskedBrief, "mbrief"}};
inline std::string toString(DescriptorKind kind) { return nameOf(kind, kDescriptorKindNames); }
inline DescriptorKind parseDescriptorKind(const std::string& name) {
  return parseName(name, kDescriptorKindNames, "descriptor kind");
}
// Whether the kind learns masks (mdBRIEF, masked BRIEF) and needs a camera model (dBRIEF, mdBRIEF).
inline bool hasMasks(DescriptorKind kind) { return kind == DescriptorKind::MdBrief || kind == DescriptorKind::MaskedBrief; }
inline bool usesCamera(DescriptorKind kind) { return kind == DescriptorKind::DBrief || kind == DescriptorKind::MdBrief; }

// Where the tests' orientation comes from when useOrientation is set.
enum class OrientationSource {
  // The keypoint's angle (the detector's intensity centroid, measured on a disc of the
  // distorted image), carried to the tangent plane through the Jacobian. That disc is an
  // ellipse on the plane, so the angle is not covariant with the footprint the tests use.
  Keypoint,
  // dBRIEF/mdBRIEF: re-measured per keypoint as the intensity centroid of a disc of radius
  // orientationRadius on the tangent plane, sampled through the same local map as the tests, so
  // the angle turns with the plane wherever the plane is seen in the image. compute() writes the
  // image direction of this angle back into the keypoint. BRIEF/masked BRIEF: as Keypoint.
  // Measured on keypoints without an angle too (angle -1).
  TangentPlane,
};
inline constexpr EnumName<OrientationSource> kOrientationSourceNames[] = {
    {OrientationSource::TangentPlane, "tangent-plane"}, {OrientationSource::Keypoint, "keypoint"}};
inline std::string toString(OrientationSource source) { return nameOf(source, kOrientationSourceNames); }
inline OrientationSource parseOrientationSource(const std::string& name) {
  return parseName(name, kOrientationSourceNames, "orientation source");
}

// How dBRIEF maps the test set into the image (the planes: mdbrief/camera/tangent_plane.hpp).
enum class DistortionForm {
  // The paper's eq. 8-11 literally: tests added on its plane Pi_lambda (z = lambda) at the
  // undistorted keypoint (scaled by the octave's scale), every test point projected through the
  // camera. Not rotation invariant off the optical axis (the plane adds perspective stretch), and
  // it degenerates towards 90 degrees: use maxIncidenceDeg 80 with it (the `paper` preset does).
  Paper,
  // The tests on the plane tangent to the viewing sphere at the keypoint's ray, mapped by the
  // local Jacobian of plane -> pixel normalised to unit determinant: the footprint's shape
  // (rotation, anisotropy) comes from the camera, its size from the detector (whose scale
  // already reflects the compressed appearance near the rim). Holds at any incidence.
  Affine,
};
inline constexpr EnumName<DistortionForm> kDistortionFormNames[] = {{DistortionForm::Affine, "affine"},
                                                                    {DistortionForm::Paper, "paper"}};
inline std::string toString(DistortionForm form) { return nameOf(form, kDistortionFormNames); }
inline DistortionForm parseDistortionForm(const std::string& name) {
  return parseName(name, kDistortionFormNames, "distortion form");
}

enum class Sampling { Bilinear, Nearest };
inline constexpr EnumName<Sampling> kSamplingNames[] = {{Sampling::Bilinear, "bilinear"}, {Sampling::Nearest, "nearest"}};
inline std::string toString(Sampling sampling) { return nameOf(sampling, kSamplingNames); }
inline Sampling parseSampling(const std::string& name) { return parseName(name, kSamplingNames, "sampling"); }

struct DescriptorOptions {
  DescriptorKind kind = DescriptorKind::MdBrief;
  int bits = 256;                   // 32..512 in steps of 32: the first `bits` tests of the set
  // Registry name or path to a JSON test set; empty = the registry's default, the learned set
  // chosen by held-out measurement (docs/RESULTS.md "Learned vs random test sets").
  std::string pattern;
  bool useOrientation = true;       // rotate the tests by the keypoint angle
  // TangentPlane: higher recognition and precision-recall than the detector's angle (the -kp
  // rows of docs/RESULTS.md, sections "Precision-recall" and
  // "Detected keypoints, tilted and rolled poses (decides the defaults)").
  OrientationSource orientation = OrientationSource::TangentPlane;
  // TangentPlane: disc radius, 4..15, in test-offset units (level pixels without distortion;
  // cv::ORB's 15). At most 15 so the disc stays inside the 32x32 footprint that is checked.
  int orientationRadius = 15;
  // Affine: higher recognition than Paper with detected keypoints and an order of magnitude
  // faster (docs/RESULTS.md, sections "Description speed" and
  // "Detected keypoints, tilted and rolled poses (decides the defaults)").
  DistortionForm form = DistortionForm::Affine;
  Sampling sampling = Sampling::Bilinear;
  // mdBRIEF: the two extra rotations are +/- this angle, which must cover the orientation error
  // of the detector. 20 degrees: the best of the angles compared in docs/RESULTS.md, section
  // "Detected keypoints, tilted and rolled poses (decides the defaults)".
  double maskRotationDeg = 20.0;
  // dBRIEF/mdBRIEF: keypoints whose ray is further than this from the optical axis are dropped.
  // 180 = none: the Affine form's plane holds at any incidence, and keypoints beyond 80 degrees
  // add matches on the wide lenses (docs/RESULTS.md "Real images: what a tracker keeps").
  double maxIncidenceDeg = 180.0;
  // The footprint follows the keypoint's size continuously: the tests' 31-pixel diameter
  // (cv::ORB's patch) spans supportScale * size level-0 pixels, sampled on the pyramid level
  // whose scale is nearest, at the remaining fractional scale on that level. 1 = cv::ORB's
  // convention (size = patch diameter), so ORB and modORB keypoints (size = 31 * scale of their
  // octave) give exactly the descriptors of an octave-based placement, and 1 is also where
  // they match best. Detectors whose size measures a blob rather than a patch (cv::AKAZE,
  // cv::SIFT) want a larger factor: the measured one per detector is in docs/RESULTS.md
  // "Descriptor footprint for other detectors".
  double supportScale = 1.0;
};

// The fields of DescriptorOptions (option_fields.hpp).
const OptionTable<DescriptorOptions>& descriptorOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const DescriptorOptions& options);

class DescriptorExtractor {
 public:
  // camera may be null only for DescriptorKind::Brief and MaskedBrief.
  explicit DescriptorExtractor(CameraPtr camera, DescriptorOptions options = {});
  // With an explicit test set (options.pattern is ignored); its first options.bits tests are used.
  DescriptorExtractor(CameraPtr camera, DescriptorOptions options, const ComparisonSet& tests);

  // Samples on the levels of `pyramid` (the detector's, when detection and description share it).
  // Keypoints: level-0 pixels, angle in degrees (cv::KeyPoint's convention, -1 = none), size
  // as DescriptorOptions::supportScale describes (octave is not read). Keypoints whose size is
  // not finite, or whose footprint (supportScale * size) is under one input pixel, are dropped:
  // their tests would all compare the same interpolated value. Keypoints whose tests cannot all
  // be sampled inside the image and the camera's valid area are removed from `keypoints` (as
  // cv::Feature2D::compute does), so rows stay aligned. descriptors and masks may be cv::noArray(); masks is filled only for
  // MdBrief and MaskedBrief (otherwise released).
  // With OrientationSource::TangentPlane (dBRIEF/mdBRIEF) the kept keypoints' angle becomes
  // the re-measured one.
  void compute(const ImagePyramid& pyramid, std::vector<cv::KeyPoint>& keypoints, cv::OutputArray descriptors,
               cv::OutputArray masks = cv::noArray()) const;
  // Same, building the levels the keypoints need of a pyramid of `image` with `pyramid`'s options.
  void compute(const cv::Mat& image, std::vector<cv::KeyPoint>& keypoints, cv::OutputArray descriptors,
               cv::OutputArray masks = cv::noArray(), const PyramidOptions& pyramid = {}) const;

  // The depth (at least 1) of a pyramid with `pyramid`'s options that holds every level compute()
  // samples these keypoints on (each keypoint's level follows its size, not its octave).
  int levelsFor(const std::vector<cv::KeyPoint>& keypoints, const PyramidOptions& pyramid) const;

  int descriptorBytes() const { return options_.bits / 8; }
  // True when compute() replaces the keypoints' angles with its own measurement (dBRIEF and
  // mdBRIEF with OrientationSource::TangentPlane): the detector's angles are then not needed.
  bool measuresOrientation() const;
  const DescriptorOptions& options() const { return options_; }
  const ComparisonSet& comparisonSet() const { return tests_; }
  const CameraPtr& camera() const { return camera_; }

  // The image positions (level-0 pixels) of the test points of one keypoint on `pyramid`, for
  // drawing: element d is (p1, p2) of test d for rotation 0, placed and checked as compute()
  // does (the same code), so empty exactly when compute() would drop the keypoint. An angle
  // that compute() re-measures is re-measured here too; otherwise keypoint.angle is used.
  std::vector<std::pair<cv::Point2f, cv::Point2f>> comparisonPositions(const ImagePyramid& pyramid,
                                                                       const cv::KeyPoint& keypoint) const;

  // The names of 0.2, deprecated (a BRIEF test is now called a comparison).
  [[deprecated("renamed comparisonSet")]] const ComparisonSet& testSet() const { return comparisonSet(); }
  [[deprecated("renamed comparisonPositions")]] std::vector<std::pair<cv::Point2f, cv::Point2f>> testPositions(
      const ImagePyramid& pyramid, const cv::KeyPoint& keypoint) const {
    return comparisonPositions(pyramid, keypoint);
  }

 private:
  CameraPtr camera_;
  DescriptorOptions options_;
  ComparisonSet tests_;
};

}  // namespace mdbrief
