#pragma once
// Sub-pixel refinement of matches: for a matched pair of keypoints, the position in image b that
// best aligns b's patch with a's, by Lucas-Kanade on the pyramid's levels lightly smoothed. A keypoint
// sits where its detector's response peaks, a level pixel's fraction away from where the same
// surface point lies in the other image; on coarse levels that is pixels of the input. Aligning
// the patches moves b's point onto a's, to a tenth of a level pixel and less.
//
// The two patches are the same square on the plane tangent to the viewing sphere at each
// keypoint (camera/tangent_plane.hpp: the lens' distortion removed), mapped into each image by the
// camera's local Jacobian, b's scaled by the keypoints' size ratio: fisheye patches far apart in
// the image compare as a perspective camera would see them. Intensities are compared after each
// patch is normalised to zero mean and unit variance (a stereo pair's gain and offset differ),
// each sample by cubic convolution: a bilinear sample blurs by its fraction between pixels, in
// which the samples of a turned or scaled patch all differ.
// The alignment runs on the keypoints' own levels, then on the finest level (where the patch there
// still fixes both directions).
//
// It estimates b's shift, and the shape of b's patch against a's on the plane, about the patch
// centre: its turn and scale, and the stretch and shear that a surface slanted against both views
// adds, each view foreshortening it at its own angle. Without the stretch and shear (the build
// before, 13 x 13 patches at sigma 0.9), a texture stretched by 1.15 along one axis was aligned
// 0.134 px off at the median, 0.0075 px with them (tests/test_match_refinement.cpp); the stereo
// benchmark at ratio 0.8 (docs/RESULTS.md "Real stereo: poses against the known pose"), with 15 x
// 15 patches at sigma 0.6: EuRoC's residual 0.081 / 0.274 -> 0.072 / 0.229 px (median / p90), 521
// -> 540 right matches per pair; MYNT's 0.188 / 0.315 -> 0.185 / 0.303 px; the rendered rig's
// localisation RMS 0.158 -> 0.092 px; poster-dev against its ground truth 0.171 / 0.413 -> 0.110 /
// 0.271 px (scripts/refinement_poster_dev.py).
// Views rolled about the viewing direction turn the patches, and a shift alone aligns turned
// patches off the point (the guide's scene rolled 2 / 5 / 12 degrees: a shift alone took the
// median error from 0.08 / 0.09 / 0.09 px to 0.14 / 0.28 / 0.56 px, with the turn to 0.05-0.06 px
// at every roll). The scale starts at the keypoints' size ratio, which is noisy: on a rendered pair
// whose b sizes were made 15 % wrong, holding it left 0.10 px where estimating it gave 0.063 px
// (sigma 2), as with the true sizes; on EuRoC's stereo pairs it kept 17 more right matches per
// pair. The turn starts at zero, or at the keypoints' orientation difference where that exceeds the
// orientations' own noise (10 degrees): the orientations alone are too noisy to turn the patch by.
// A shape costs the shift precision where there is none to find, so it is kept only where it
// stands out of its noise (8 standard deviations), and on a patch that fixes it (not a disc, not
// stripes): all four, else turn and scale, else the shift is fitted alone. The shape is estimated
// on the keypoints' own level, whose patch spans the most of the image, and held on the finest (the
// same figures on the stereo benchmark, 13 % less time).
//
// A tracker that estimates a pose keeps the matches refinement accepts and drops the rest: the
// failures (edges, patches that do not align, points less certain than maxSigmaPx) are where the
// imprecise matches are (docs/RESULTS.md "Real stereo: poses against the known pose").
//
// Deterministic; matches are refined in parallel, each on its own.
#include <limits>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/base/option_fields.hpp"
#include "mdbrief/camera/camera.hpp"
#include "mdbrief/detect/image_pyramid.hpp"

namespace mdbrief {

struct MatchRefinementOptions {
  // Half the patch side in level pixels: (2 r + 1)^2 samples, one per level pixel. In [2, 15].
  // Default 7, a 15 x 15 patch: with the stretch and shear estimated, a wider patch no longer
  // spans more than its model holds. Stereo benchmark at ratio 0.8 (right matches per pair,
  // residual median / p90), at sigma 0.6: 6: EuRoC 509, 0.075 / 0.250 px; MYNT 0.186 / 0.311 px;
  // the rendered rig's RMS 0.097 px. 7: EuRoC 540, 0.072 / 0.229 px; MYNT 0.185 / 0.303 px; rig
  // 0.092 px. 8 (sigma 0.7): EuRoC 558, 0.071 / 0.216 px, but MYNT 0.188 / 0.305 px, rig 0.092 px.
  // Time grows with the samples (BM_RefineMatches: docs/RESULTS.md "Real stereo: poses against
  // the known pose").
  int patchRadius = 7;
  // The Gaussian the levels are smoothed by before the patches are aligned, level pixels (3 sigma
  // wide; ImagePyramid::smoothedFloat). In (0, 8]. Default 0.6: the descriptors' smoothing (sigma
  // 2) takes the fine texture that fixes a point (the tests' rendered plane: 0.016 px at the
  // median against 0.035 px). Stereo benchmark as above, 15 x 15 patches: 0.5: EuRoC 536, 0.072 /
  // 0.226 px; MYNT 0.186 / 0.302 px; rig 0.092 px, with fewer right matches at the best ratio
  // (EuRoC 521 against 525). 0.6: as above. 0.7: EuRoC 542, 0.072 / 0.232 px; MYNT 0.185 / 0.304
  // px; rig 0.094 px. 0.8: EuRoC 542, 0.073 / 0.240 px; MYNT 0.187 / 0.306 px; rig 0.097 px.
  // Poster-dev against its ground truth (scripts/refinement_poster_dev.py): 0.110 / 0.274, 0.112
  // / 0.281, 0.114 / 0.287, 0.117 / 0.294 px.
  double smoothingSigma = 0.6;
  // How many levels below the keypoints' own the second alignment runs on, from the first one's
  // result: the finest level where the pyramid ends first. In [0, 16]; 0, the keypoints' levels
  // alone. Default 10: the finest level from every level of the default pyramid. Two levels left
  // the rendered rig's coarse keypoints at 0.74 / 0.81 px RMS (levels 5 / 6, with the turn and
  // scale alone); down to the finest, 0.64 / 0.65 px. Aligning on every level between changed no
  // figure by more than 0.001 px, at 1.4 times the time.
  int finerLevels = 10;
  // Gauss-Newton iterations per level at most. In [1, 100]. Default 10.
  int maxIterations = 10;
  // A match whose refined point moves more than this from b's keypoint fails (Diverged), in
  // level pixels of b's keypoint. In (0, 10]. Default 2.
  double maxShift = 2.0;
  // The smallest eigenvalue of the patch's structure tensor (normalised intensities, per sample,
  // with what the normalisation takes out: a ramp's mean gradient) below which it does not fix
  // both directions (Aperture: an edge or a flat patch). In [0, 10]. Default 0.0002: a floor for
  // patches whose residual is too small to measure their spread; elsewhere maxSigmaPx decides,
  // and it weighs the patch's structure against how well the patches agree (EuRoC's stereo pairs,
  // ratio 0.7, maxSigmaPx 0.1, before the scale was estimated: 416 right matches per pair at
  // 0.002, 489 at 0.0002, the residual's median 0.105 / 0.107 px).
  double minEigenvalue = 0.0002;
  // A match whose refined point is less certain than this fails (Uncertain): its standard deviation
  // (RefinedMatch::sigmaPx), input pixels. In (0, 100]; 100 keeps every alignment. Default 0.08: on
  // EuRoC's stereo pairs (11 x 11 patches, each at its best ratio), 0.07 / 0.08 / 0.09 / 0.1 keep
  // 444 / 474 / 495 / 494 right matches per pair, 0.084 / 0.086 / 0.086 / 0.087 px from their
  // epipolar planes at the median (ratio 0.8), and the relative pose's AUC@5 is 0.89 / 0.89 / 0.86
  // / 0.87; on the MYNT pair 529 / 535 / 538 / 539 right matches (SIFT: 530) (docs/RESULTS.md "Real
  // stereo: poses against the known pose").
  double maxSigmaPx = 0.08;
};

// The fields of MatchRefinementOptions (option_fields.hpp); Python's keywords, the CLI's flags.
const OptionTable<MatchRefinementOptions>& matchRefinementOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const MatchRefinementOptions& options);

enum class RefinementFailure {
  None,
  OutsideImage,  // a patch leaves its level, or a keypoint has no ray (outside the lens' circle)
  Aperture,      // the patch on the keypoints' own level does not fix both directions
  Diverged,      // moved further than maxShift, scaled b's patch by over 2, or did not settle
  Uncertain,     // the refined point's standard deviation exceeds maxSigmaPx
};
// "", "patch outside the image", "aperture: the patch does not fix both directions", "diverged",
// "uncertain: its standard deviation exceeds maxSigmaPx".
const char* toString(RefinementFailure failure);

struct RefinedMatch {
  RefinementFailure failure = RefinementFailure::None;
  cv::Point2d pointB;  // b's refined position, input pixels (b's keypoint itself on failure)
  cv::Vec3d bearingB;  // its unit ray (b's keypoint's, or zero without one, on failure)
  // Standard deviation of pointB along its least certain direction, input pixels: the residual's
  // spread through the shift's covariance (the turn's uncertainty included where it was
  // estimated). +inf on failure.
  double sigmaPx = std::numeric_limits<double>::infinity();
  int level = -1;  // the finest level b's point was refined on; -1 on failure
  bool ok() const { return failure == RefinementFailure::None; }
};

// Refines b's side of every match (queryIdx into keypointsA, trainIdx into keypointsB, as the
// matchers give them). Each keypoint's octave is its pyramid level, as MdBrief's detectors set
// it; the pyramids are the images' (the same options as the detection, so the levels agree).
// Throws std::invalid_argument for a camera whose image size is not its pyramid's input size, an
// index out of range, an octave that is no level of its pyramid, a keypoint position that is not
// finite, or options out of range.
std::vector<RefinedMatch> refineMatches(const ImagePyramid& pyramidA, const Camera& cameraA,
                                        const std::vector<cv::KeyPoint>& keypointsA, const ImagePyramid& pyramidB,
                                        const Camera& cameraB, const std::vector<cv::KeyPoint>& keypointsB,
                                        const std::vector<cv::DMatch>& matches,
                                        const MatchRefinementOptions& options = {});

}  // namespace mdbrief
