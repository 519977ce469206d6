#pragma once
// What the two-view fits share: checked and normalised input, the inlier test in angles or
// pixels, the degenerate configurations, the point in front of both cameras.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/geometry/two_view.hpp"

namespace mdbrief::geometry {

// The matches as unit bearings, and the inlier test of the options.
struct CheckedMatches {
  std::vector<cv::Vec3d> a, b;
  std::vector<double> scale;  // pixels per radian per match, or empty (angles)
  double maxAngle = 0, maxPixels = 0;

  int size() const { return static_cast<int>(a.size()); }
  // Inlier test of a residual (radians) of match k; the same comparison whichever unit.
  bool within(int k, double residual) const {
    return scale.empty() ? residual <= maxAngle : residual * scale[k] <= maxPixels;
  }
  // The threshold as an angle, for the tests that have no single match (degeneracy, parallel
  // rays): the mean of the matches' when the threshold is in pixels.
  double typicalAngle() const;
};

// Throws std::invalid_argument, prefixed by `function`, for an option out of range, sizes that
// differ, a bearing that is zero or not finite, or a scale that is not positive and finite.
CheckedMatches checkMatches(const char* function, const std::vector<cv::Vec3d>& a, const std::vector<cv::Vec3d>& b,
                            const TwoViewOptions& options, const std::vector<double>& pixelsPerRadian);

// TooFewMatches, SamePoint or OnALine for matches no model of `minimal` points can be fitted to,
// else None.
TwoViewFailure degeneracy(const CheckedMatches& m, int minimal);

// Marks `result` failed: every match an outlier, a reason with the numbers.
void fail(TwoViewResult& result, TwoViewFailure failure, int matches, int minimal);

double angleBetween(const cv::Vec3d& u, const cv::Vec3d& v);

// log10 P[Binomial(trials, p) >= successes].
double binomialTailLog10(int trials, int successes, double p);
// log10 of a model's number of false alarms (TwoViewOptions::maxFalseAlarms): `models` scored,
// `inliers` of `matches` for a minimal `sample`, each other match an inlier by chance with
// probability `chance`.
double significanceLog10(int models, int matches, int inliers, int sample, double chance);
// Marks `result` NotSignificant when its log10FalseAlarms exceeds maxFalseAlarms; keeps the figure.
void failIfChance(TwoViewResult& result, double maxFalseAlarms, int matches, int sample);

// The share of matches a model takes as inliers by chance (TwoViewOptions::maxFalseAlarms):
// `inlier(ka, kb)` tells whether a[ka] with b[kb] is an inlier; counted over four pairings of
// each a with another match's b (cyclic shifts drawn from `seed`), and at least `sphere`, the
// share that bearings spread over the whole sphere would give.
template <class Inlier>
double chanceShare(int matches, std::uint32_t seed, double sphere, Inlier inlier) {
  constexpr int kPairings = 4;
  std::uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1;
  long long count = 0;
  for (int p = 0; p < kPairings; ++p) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const int shift = 1 + static_cast<int>((state >> 33) % static_cast<std::uint64_t>(matches - 1));
    for (int k = 0; k < matches; ++k) count += inlier(k, (k + shift) % matches);
  }
  return std::max(sphere, static_cast<double>(count) / (static_cast<double>(kPairings) * matches));
}

// The epipolar angle of unit b against unit a under E = [t]x R: the angle between b and the
// epipolar plane of a (through t and a, in b's frame E^T a is its normal), so that times the
// pixels per radian at b it is the distance in pixels of image b. pi/2 where the plane is
// undefined (a parallel to t).
double epipolarResidual(const cv::Matx33d& e, const cv::Vec3d& a, const cv::Vec3d& b);

// Whether the point seen along unit a and unit b lies in front of both cameras under (R, t),
// or the rays are parallel within `parallel` radians (a point too far for its depth to have a
// sign).
bool inFront(const cv::Matx33d& r, const cv::Vec3d& t, const cv::Vec3d& a, const cv::Vec3d& b, double parallel);

}  // namespace mdbrief::geometry
