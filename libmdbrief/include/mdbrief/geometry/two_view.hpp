#pragma once
// Two-view geometry on matched bearing vectors (the unit rays of camera.hpp's pixelToBearing),
// as a tracker checks its matches: it holds for any lens and beyond 90 degrees of incidence,
// where the image coordinates of a perspective model do not exist.
//   fitEssential:   relative pose of a general scene, RANSAC over the 5-point solver (Nister, by
//                   OpenGV), the pose that puts the inliers in front of both cameras, refined on
//                   the inliers;
//   fitHomography:  b ~ H a for a plane (or a pure rotation), RANSAC over a 4-point DLT, refined
//                   on the inliers;
//   checkKnownPose: labels matches with a relative pose known beforehand (a calibrated stereo
//                   pair, odometry).
// Each returns per match the inlier flag and the residual (an angle, radians), and the model; on
// failure an empty result whose `reason` says why (too few matches, all on one point, all on a
// line, no model found): never an exception for data. Invalid arguments (sizes that differ, a
// bearing that is zero or not finite, an option out of range) throw std::invalid_argument.
//
// Threshold: an angle (TwoViewOptions::maxAngle, radians) by default. Given the pixels per radian
// at each match's pixel in image b (pixelsPerRadian() of the camera), the threshold is
// TwoViewOptions::maxPixels instead: a match is an inlier when residual x scale <= maxPixels.
// Residuals stay angles either way.
//
// Convention: the pose (R, t) of camera b in camera a's frame: a point X_b in b's coordinates is
// X_a = R X_b + t (T_ab). The essential matrix is E = [t]x R, so a . (E b) = 0 for a match
// (a, b); |t| = 1 for a fitted pose (the scale of a two-view fit is unknown).
//
// Deterministic: the same input and seed give the same result on every run and thread count.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/rig.hpp"
#include "mdbrief/base/option_fields.hpp"

namespace mdbrief {

struct TwoViewOptions {
  // Inlier threshold as an angle, radians: the residual (see each function) of an inlier is at
  // most this. In (0, 0.5]. Default 0.005 rad (0.29 degrees): about 1.5 px on a 190-degree lens
  // 1000 px wide, whose equidistant projection has about 300 px per radian.
  double maxAngle = 0.005;
  // Inlier threshold in pixels, used instead of maxAngle when the call passes the pixels per
  // radian of each match (residual x pixelsPerRadian[k] <= maxPixels). In (0, 1000]. Default 2.
  double maxPixels = 2.0;
  // RANSAC (fitEssential, fitHomography): stop when finding a better model by further samples is
  // this unlikely. In (0, 1). Default 0.999.
  double confidence = 0.999;
  // RANSAC: at most this many samples. In [1, 1000000]. Default 3000, enough for 30 % inliers.
  int maxIterations = 3000;
  // RANSAC: the random generator's seed, in [0, 2^32 - 1]; the same seed gives the same result.
  // Default 1.
  std::uint32_t seed = 1;
  // fitEssential, fitHomography: refine the model on its inliers (non-linear least squares) and
  // relabel; fitEssential keeps the refined pose unless its MSAC score (each inlier's squared
  // residual over the threshold's, each outlier 1) is worse than RANSAC's. Default on.
  bool refine = true;
  // fitEssential, checkKnownPose: an inlier's triangulated point must lie in front of both
  // cameras. A match whose rays are parallel within the threshold (a point far away, or a pure
  // rotation) passes: its depth has no sign to check. Default on.
  bool inFront = true;
  // fitEssential, fitHomography: a model counts as found when its number of false alarms is below
  // this (an a-contrario test; Moisan and Stival 2004). For the best minimal sample's model, with
  // k inliers of n matches, sample size s, and p the probability that a random match is an
  // inlier of it,
  //   NFA = (models scored) x P[Binomial(n - s, p) >= k - s],
  // the expected number of models as good among those RANSAC tried if the matches were random:
  // below 0.01, random matches give such a model in fewer than 1 fit in 100. k counts the
  // sample's model (a refit on its inliers may add some, but they no longer test it). p is
  // measured on the fitted model by pairing each a with another match's b (four shifted
  // pairings), and is at least what bearings spread over the whole sphere give at the
  // threshold. A model at or above it fails with NotSignificant; a minimal sample alone (k = s)
  // never passes. In (0, 1e300]. Default 0.01. Random bearings fail in at least 99 fits of 100
  // (tests/test_two_view_geometry.cpp).
  double maxFalseAlarms = 0.01;
  // fitEssential, fitHomography: when set, called on the calling thread before every RANSAC
  // sample; an exception it throws ends the fit (the Python module stops a fit at Ctrl-C this
  // way: 300,000 bearings took 92 s to notice one). Not an option field.
  std::function<void()> interruptCheck;
};

// The fields of TwoViewOptions (option_fields.hpp); Python's keywords.
const OptionTable<TwoViewOptions>& twoViewOptionFields();
// Throws OptionError naming the first option out of its field's range.
void validate(const TwoViewOptions& options);

// Why a fit returned no model.
enum class TwoViewFailure {
  None,           // a model was found
  TooFewMatches,  // fewer matches than the minimal sample (5 for the essential, 4 for a homography)
  SamePoint,      // every bearing of an image within the threshold of one direction
  OnALine,        // every bearing of an image within the threshold of one plane through the camera
                  // centre: the matches lie on one line (of a pinhole image), which fixes no model
  NoModel,        // no sample gave a model that explains the minimal number of matches
  NotSignificant, // the best model's inliers are no more than chance gives (maxFalseAlarms)
};
// "too few matches", "all matches on the same point", "all matches on a line", "no model found",
// "inliers no more than chance".
const char* toString(TwoViewFailure failure);

// The pose of camera b in camera a's frame (X_a = R X_b + t): the rigid transform a rig gives
// between its cameras (CameraRig::relativePose(a, b)).
using RelativePose = RigidTransform;
// E = [t]x R.
cv::Matx33d essentialMatrix(const RelativePose& pose);

struct TwoViewResult {
  TwoViewFailure failure = TwoViewFailure::None;
  std::string reason;                // empty when a model was found; toString(failure) and the counts
  std::vector<unsigned char> inliers;  // per match, 1 = inlier; all 0 on failure
  std::vector<double> residuals;       // per match, radians; empty on failure
  int inlierCount = 0;
  // fitEssential, fitHomography: log10 of the model's number of false alarms (maxFalseAlarms),
  // also on failure NotSignificant; 0 otherwise. The lower, the less a model can be chance.
  double log10FalseAlarms = 0;
  bool ok() const { return failure == TwoViewFailure::None; }
};

struct EssentialResult : TwoViewResult {
  // Residual: the angle between bearing b and the epipolar plane of a (through the centres and
  // a), measured at camera b as the pixels per radian of image b expect.
  RelativePose pose;     // |t| = 1
  cv::Matx33d essential;  // essentialMatrix(pose): [t]x R with |t| = 1
};

struct HomographyResult : TwoViewResult {
  // Residual: the angle between b and H a (more than 90 degrees when H a points away from b).
  cv::Matx33d homography;  // b ~ H a with a positive factor for the inliers; unit Frobenius norm
};

// Matches (a[k], b[k]); bearings need not be unit, but non-zero and finite. pixelsPerRadian:
// empty (threshold maxAngle), or one positive scale per match at its pixel in image b
// (threshold maxPixels).
EssentialResult fitEssential(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                             const TwoViewOptions& options = {}, const std::vector<double>& pixelsPerRadian = {});

HomographyResult fitHomography(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                               const TwoViewOptions& options = {}, const std::vector<double>& pixelsPerRadian = {});

// Labels matches with a known pose (X_a = R X_b + t, any |t| > 0): the residual is the epipolar
// angle as for fitEssential, and options.inFront asks the point in front of both cameras. Each
// match is labelled on its own, so any number of matches (none included) gives an ok result.
// RANSAC's options and `refine` are not used. Throws std::invalid_argument for a rotation that
// is not one (R^T R = I, det 1, within 1e-6) or a zero or non-finite translation.
TwoViewResult checkKnownPose(const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                             const RelativePose& pose, const TwoViewOptions& options = {},
                             const std::vector<double>& pixelsPerRadian = {});

// The angle between bearing b and the epipolar plane of a under the pose, radians. Bearings of
// any finite, non-zero length; std::invalid_argument otherwise.
double epipolarAngle(const RelativePose& pose, const cv::Vec3d& a, const cv::Vec3d& b);

// Pixels per radian of ray angle around `pixel` (the mean of both image axes): turns a pixel
// threshold into an angle there. Empty where the camera has no ray for the neighbourhood.
std::optional<double> pixelsPerRadian(const Camera& camera, const cv::Point2d& pixel);

// RANSAC iterations that find an all-inlier sample of `sampleSize` with `confidence` at an inlier
// share `w`, at most `cap`. std::invalid_argument for w outside [0, 1], a sample size or cap
// below 1, or a confidence outside (0, 1) (NaN included).
int ransacIterationsNeeded(double w, int sampleSize, double confidence, int cap);

}  // namespace mdbrief
