// Two-view RANSAC on bearings (mdbrief/geometry/two_view.hpp): 500 matches of a general scene
// seen by a 215-degree double-sphere fisheye from two poses, 0.3 px noise, 30 % random pixel
// pairs; one thread (the fits do not spread). Target: fitEssential <= 5 ms. Counter "inliers".
//   mdbrief_bench --benchmark_filter=TwoView
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "mdbrief/camera/double_sphere.hpp"
#include "mdbrief/geometry/two_view.hpp"

namespace {

struct Matches {
  std::vector<cv::Vec3d> a, b;
  std::vector<double> scaleB;
};

// Fixed seed: the same matches on every run. `planar` puts the points on one plane.
const Matches& matches(bool planar) {
  static Matches cache[2];
  Matches& m = cache[planar ? 1 : 0];
  if (!m.a.empty()) return m;
  mdbrief::DoubleSphereParams p;
  p.intrinsics.width = p.intrinsics.height = 1024;
  p.intrinsics.fx = p.intrinsics.fy = 213;
  p.intrinsics.cx = p.intrinsics.cy = 511.5;
  p.xi = -0.2;
  p.alpha = 0.6;
  const mdbrief::DoubleSphereCamera camera(p);
  cv::Matx33d r;
  cv::Rodrigues(cv::Vec3d(0.03, 0.3, -0.06), r);
  const cv::Vec3d t(0.6, -0.1, 0.2);  // X_a = R X_b + t
  std::mt19937 rng(500);
  std::uniform_real_distribution<double> cosTheta(std::cos(110 * CV_PI / 180), 1.0), phi(0, 2 * CV_PI),
      depth(2, 8), side(-1.5, 1.5), up(-1.5, 3.0), u(0, 1023);
  std::normal_distribution<double> noise(0, 0.3);
  const auto add = [&](cv::Point2d pa, cv::Point2d pb) {
    cv::Vec3d ba, bb;
    const auto scale = mdbrief::pixelsPerRadian(camera, pb);
    if (!camera.isValid(pa) || !camera.isValid(pb) || !scale || !camera.pixelToBearing(pa, ba) ||
        !camera.pixelToBearing(pb, bb))
      return;
    m.a.push_back(ba), m.b.push_back(bb), m.scaleB.push_back(*scale);
  };
  while (m.a.size() < 350) {
    cv::Vec3d x;
    if (planar) {
      x = cv::Vec3d(2.0, side(rng), up(rng));
    } else {
      const double c = cosTheta(rng), s = std::sqrt(1 - c * c), f = phi(rng);
      x = cv::Vec3d(s * std::cos(f), s * std::sin(f), c) * depth(rng);
    }
    cv::Point2d pa, pb;
    if (!camera.bearingToPixel(x, pa) || !camera.bearingToPixel(r.t() * (x - t), pb)) continue;
    add(pa + cv::Point2d(noise(rng), noise(rng)), pb + cv::Point2d(noise(rng), noise(rng)));
  }
  while (m.a.size() < 500) add({u(rng), u(rng)}, {u(rng), u(rng)});
  return m;
}

void BM_TwoViewEssential(benchmark::State& state) {
  const Matches& m = matches(false);
  int inliers = 0;
  for (auto _ : state) {
    const auto fit = mdbrief::fitEssential(m.a, m.b, {}, m.scaleB);
    inliers = fit.inlierCount;
    benchmark::DoNotOptimize(fit.pose);
  }
  state.counters["inliers"] = inliers;
}
BENCHMARK(BM_TwoViewEssential)->Unit(benchmark::kMillisecond);

void BM_TwoViewHomography(benchmark::State& state) {
  const Matches& m = matches(true);
  int inliers = 0;
  for (auto _ : state) {
    const auto fit = mdbrief::fitHomography(m.a, m.b, {}, m.scaleB);
    inliers = fit.inlierCount;
    benchmark::DoNotOptimize(fit.homography);
  }
  state.counters["inliers"] = inliers;
}
BENCHMARK(BM_TwoViewHomography)->Unit(benchmark::kMillisecond);

}  // namespace
