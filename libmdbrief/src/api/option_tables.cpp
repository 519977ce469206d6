// The field tables of the runtime options (option_fields.hpp) and the validate() functions they
// define. Ranges hold what the code supports; a bound that is a choice says why.
#include <algorithm>
#include <cmath>

#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/match/guided_matcher.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/match/matcher.hpp"
#include "mdbrief/base/option_fields.hpp"

namespace mdbrief {

using R = FieldRange;

const OptionTable<PyramidOptions>& pyramidOptionFields() {
  using O = PyramidOptions;
  static const OptionTable<O> table = {
      integerField<O>("levels", "", "levels", "--levels", "number of pyramid levels", R::closed(1, 32),
                      [](auto& o) -> auto& { return o.levels; }),
      // At most 2 (an octave per level): beyond it a keypoint's scale falls far between levels.
      realField<O>("scaleFactor", "", "scale_factor", "--scale-factor", "scale ratio of neighbouring levels",
                   R::openLow(1, 2), [](auto& o) -> auto& { return o.scaleFactor; }),
      // Level 0 enlarges the input scale_factor^first_level times per side, bounded so that it holds
      // at most 16 times the input's pixels: --levels 32 --scale-factor 2 --first-level 10 asked
      // for 378 GB (issue 29).
      integerField<O>("firstLevel", "", "first_level", "--first-level",
                      "level holding the input image; the levels below it are enlarged, level 0 by "
                      "scale_factor^first_level, at most 4 times per side",
                      std::function<FieldRange(const O&)>([](const O& o) {
                        const int byLevels = std::max(0, std::min(o.levels, 32) - 1);
                        if (!(o.scaleFactor > 1)) return R::closed(0, byLevels);
                        const double byEnlargement = std::floor(std::log(4.0) / std::log(o.scaleFactor) + 1e-9);
                        return R::closed(0, std::min(byLevels, static_cast<int>(std::min(byEnlargement, 32.0))));
                      }),
                      [](auto& o) -> auto& { return o.firstLevel; }),
      // At most the 31-pixel patch: a wider kernel averages pixels no test compares, and its cost
      // grows with its area (99999 ran for minutes).
      integerField<O>("smoothingKernel", "", "smoothing_kernel", "--smoothing-kernel",
                      "Gaussian kernel of the descriptor smoothing (pixels)", R{1, 31, false, false, 1, true},
                      [](auto& o) -> auto& { return o.smoothingKernel; }),
      realField<O>("smoothingSigma", "", "smoothing_sigma", "--smoothing-sigma", "sigma of the descriptor smoothing",
                   R::openLow(0, 8), [](auto& o) -> auto& { return o.smoothingSigma; }),
  };
  return table;
}

const OptionTable<DetectorOptions>& detectorOptionFields() {
  using O = DetectorOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t = {
        choiceField<O>("method", "", "detector", "--detector",
                       "keypoint detector: modorb (FAST corners, ORB's scheme) or hessian (scale-space blobs)",
                       kDetectorMethodNames, [](auto& o) -> auto& { return o.method; }),
        integerField<O>("nfeatures", "", "nfeatures", "--nfeatures", "maximum number of keypoints per image",
                        R::closed(1, 1e7), [](auto& o) -> auto& { return o.nfeatures; }),
    };
    appendNested(t, pyramidOptionFields(), "pyramid", "pyramid", [](auto& o) -> auto& { return o.pyramid; });
    // Blobs are extrema over scale on the inner levels: the Hessian method needs one.
    for (auto& f : t)
      if (f.member == "pyramid.levels")
        f.range = [](const O& o) { return R::closed(o.method == DetectorMethod::Hessian ? 3 : 1, 32); };
    const OptionTable<O> rest = {
        choiceField<O>("corners", "", "corners", "--corners", "corner detector of modorb", kCornerDetectorNames,
                       [](auto& o) -> auto& { return o.corners; }),
        integerField<O>("threshold", "", "threshold", "--threshold", "FAST/AGAST intensity threshold",
                        R::closed(1, 254), [](auto& o) -> auto& { return o.threshold; }),
        integerField<O>("fallbackThreshold", "", "fallback_threshold", "--fallback-threshold",
                        "threshold of a level where the threshold finds too few corners (at most the threshold)",
                        std::function<FieldRange(const O&)>(
                            [](const O& o) { return R::closed(1, std::clamp(o.threshold, 1, 254)); }),
                        [](auto& o) -> auto& { return o.fallbackThreshold; }),
        integerField<O>("harrisBlockSize", "", "harris_block_size", "--harris-block-size",
                        "window of the Harris score", R{3, 15, false, false, 1, true},
                        [](auto& o) -> auto& { return o.harrisBlockSize; }),
        realField<O>("harrisK", "", "harris_k", "--harris-k", "Harris' k", R::closed(0, 0.25),
                     [](auto& o) -> auto& { return o.harrisK; }),
        flagField<O>("spread", "", "spread", "--spread", "spread each level's keypoints with a quadtree",
                     [](auto& o) -> auto& { return o.spread; }),
        realField<O>("hessianSigma", "", "hessian_sigma", "--hessian-sigma",
                     "hessian: Gaussian smoothing of the derivatives (level pixels)", R::closed(0.5, 8),
                     [](auto& o) -> auto& { return o.hessianSigma; }),
        realField<O>("hessianThreshold", "", "hessian_threshold", "--hessian-threshold",
                     "hessian: smallest normalised determinant kept", R::closed(0, 1),
                     [](auto& o) -> auto& { return o.hessianThreshold; }),
        realField<O>("hessianScaleExponent", "", "hessian_scale_exponent", "--hessian-scale-exponent",
                     "hessian: blobs compete by determinant * scale^exponent (0: determinant alone)",
                     R::closed(0, 4), [](auto& o) -> auto& { return o.hessianScaleExponent; }),
        flagField<O>("relocalise", "", "relocalise", "--no-relocalise",
                     "hessian: locate each kept blob again on the input image at its own scale",
                     [](auto& o) -> auto& { return o.relocalise; }),
        integerField<O>("orientationRadius", "", "detector_orientation_radius", "--detector-orientation-radius",
                        "radius of the detector's intensity-centroid disc", R::closed(1, 64),
                        [](auto& o) -> auto& { return o.orientationRadius; }),
        integerField<O>("patchSize", "", "patch_size", "--patch-size", "keypoint size at level 0",
                        R::closed(1, 1024), [](auto& o) -> auto& { return o.patchSize; }),
        // The orientation disc and the Harris window (plus its Sobel ring) must fit in the margin.
        integerField<O>("borderMargin", "", "border_margin", "--border-margin",
                        "distance (level pixels) to the border and the camera's invalid area; at least the "
                        "detector's orientation radius and half the Harris window + 1",
                        std::function<FieldRange(const O&)>([](const O& o) {
                          return R::closed(std::clamp(std::max(o.orientationRadius, o.harrisBlockSize / 2 + 1), 0, 1024),
                                           1024);
                        }),
                        [](auto& o) -> auto& { return o.borderMargin; }),
        flagField<O>("conformal", "", "conformal", "--conformal",
                     "detect on the camera's stereographic view and map the keypoints back (needs a camera)",
                     [](auto& o) -> auto& { return o.conformal; }),
    };
    t.insert(t.end(), rest.begin(), rest.end());
    return t;
  }();
  return table;
}

const OptionTable<DescriptorOptions>& descriptorOptionFields() {
  using O = DescriptorOptions;
  static const OptionTable<O> table = {
      choiceField<O>("kind", "", "descriptor", "--descriptor", "descriptor kind", kDescriptorKindNames,
                     [](auto& o) -> auto& { return o.kind; }),
      integerField<O>("bits", "", "bits", "--bits", "descriptor length: the first `bits` tests of the set",
                      R{32, 512, false, false, 32}, [](auto& o) -> auto& { return o.bits; }),
      textField<O>("pattern", "", "pattern", "--pattern",
                   "test set: a built-in name or a JSON file ('' = the built-in default)",
                   [](auto& o) -> auto& { return o.pattern; }),
      flagField<O>("useOrientation", "", "use_orientation", "--no-orientation",
                   "rotate the tests by the keypoint angle", [](auto& o) -> auto& { return o.useOrientation; }),
      choiceField<O>("orientation", "", "orientation", "--orientation",
                     "dbrief/mdbrief: measure the angle on the tangent plane, or take the keypoint's",
                     kOrientationSourceNames, [](auto& o) -> auto& { return o.orientation; }),
      // At most 15 so the disc stays inside the 32x32 footprint that is checked.
      integerField<O>("orientationRadius", "", "orientation_radius", "--orientation-radius",
                      "tangent-plane orientation: disc radius in test-offset units", R::closed(4, 15),
                      [](auto& o) -> auto& { return o.orientationRadius; }),
      choiceField<O>("form", "", "form", "--form",
                     "how dBRIEF/mdBRIEF distort the tests: affine (fast) or paper (eq. 8-11)", kDistortionFormNames,
                     [](auto& o) -> auto& { return o.form; }),
      choiceField<O>("sampling", "", "sampling", "--sampling", "how a test point is read from the level",
                     kSamplingNames, [](auto& o) -> auto& { return o.sampling; }),
      realField<O>("maskRotationDeg", "", "mask_rotation_deg", "--mask-rotation-deg",
                   "mdBRIEF: the mask's extra rotations are +/- this angle (degrees)", R::open(0, 90),
                   [](auto& o) -> auto& { return o.maskRotationDeg; }),
      realField<O>("maxIncidenceDeg", "", "max_incidence_deg", "--max-incidence-deg",
                   "dBRIEF/mdBRIEF: keypoints further from the optical axis (degrees) are dropped",
                   R::openLow(0, 180), [](auto& o) -> auto& { return o.maxIncidenceDeg; }),
      realField<O>("supportScale", "", "support_scale", "--support-scale",
                   "the tests' 31-pixel diameter spans this times the keypoint size (1 = cv::ORB's convention)",
                   R::closed(0.1, 20), [](auto& o) -> auto& { return o.supportScale; }),
  };
  return table;
}

const OptionTable<MdBriefOptions>& mdBriefOptionFields() {
  static const OptionTable<MdBriefOptions> table = [] {
    OptionTable<MdBriefOptions> t;
    appendNested(t, detectorOptionFields(), "detector", "detector", [](auto& o) -> auto& { return o.detector; });
    appendNested(t, descriptorOptionFields(), "descriptor", "descriptor",
                 [](auto& o) -> auto& { return o.descriptor; });
    return t;
  }();
  return table;
}

const OptionTable<MatchOptions>& matchOptionFields() {
  using O = MatchOptions;
  static const OptionTable<O> table = {
      realField<O>("ratio", "", "ratio", "--ratio",
                   "Lowe's ratio test: keep a match if best < ratio * second best (unset = off)", R::openLow(0, 1),
                   [](auto& o) -> auto& { return o.ratio; }),
      flagField<O>("crossCheck", "", "cross_check", "--no-cross-check", "keep mutual nearest neighbours only",
                   [](auto& o) -> auto& { return o.crossCheck; }),
      // A distance never exceeds the longest descriptor's 512 bits.
      realField<O>("maxDistance", "", "max_distance", "--max-distance",
                   "keep matches with distance <= this many bits (unset = off)", R::closed(0, 512),
                   [](auto& o) -> auto& { return o.maxDistance; }),
      flagField<O>("parallel", "", "parallel", nullptr, "spread the queries over threads (same result)",
                   [](auto& o) -> auto& { return o.parallel; }),
  };
  return table;
}

const OptionTable<GuidedMatchOptions>& guidedMatchOptionFields() {
  using O = GuidedMatchOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t = {
        // 10000 px is beyond any camera's image: the window is then the whole image.
        realField<O>("radius", "", "radius", "--radius",
                     "search radius around each prediction, pixels of the train image", R::closed(0, 10000),
                     [](auto& o) -> auto& { return o.radius; }),
        realField<O>("maxAngleDifference", "", "max_angle_difference", "--max-angle-difference",
                     "keep candidates whose orientation differs by at most this many degrees (unset = off)",
                     R::openLow(0, 180), [](auto& o) -> auto& { return o.maxAngleDifference; }),
        realField<O>("maxScaleRatio", "", "max_scale_ratio", "--max-scale-ratio",
                     "keep candidates whose keypoint sizes differ by at most this factor (unset = off)",
                     R::closed(1, 1000), [](auto& o) -> auto& { return o.maxScaleRatio; }),
    };
    appendNested(t, matchOptionFields(), "matching", "matching", [](auto& o) -> auto& { return o.matching; });
    return t;
  }();
  return table;
}

void validate(const PyramidOptions& options) { validateFields(pyramidOptionFields(), options, "PyramidOptions"); }
void validate(const DetectorOptions& options) { validateFields(detectorOptionFields(), options, "DetectorOptions"); }
void validate(const DescriptorOptions& options) {
  validateFields(descriptorOptionFields(), options, "DescriptorOptions");
}
void validate(const MdBriefOptions& options) { validateFields(mdBriefOptionFields(), options, "MdBriefOptions"); }
void validate(const MatchOptions& options) { validateFields(matchOptionFields(), options, "MatchOptions"); }
void validate(const GuidedMatchOptions& options) {
  validateFields(guidedMatchOptionFields(), options, "GuidedMatchOptions");
}

}  // namespace mdbrief
