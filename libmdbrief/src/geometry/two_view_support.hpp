#pragma once
// What the two-view fits share: checked and normalised input, the inlier test in angles or
// pixels, the degenerate configurations, the point in front of both cameras.
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
