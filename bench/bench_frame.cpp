// Whole-frame figure (issue 3): detect + describe + match for 1000 keypoints on a 754x480
// fisheye frame, the library's defaults (MdBrief::create(), the `tracking` preset: Hessian,
// mdBRIEF-256, masked matching with MatchOptions{}'s ratio test and mutual check) against
// cv::ORB detectAndCompute + cv::BFMatcher(NORM_HAMMING) with Lowe's ratio 0.8, on the same
// image in the same run. Each iteration processes frame A and matches it against the
// precomputed features of a second rendered view B (as a tracker matches a new frame against the
// previous one).
// Arg 1: single-threaded (OpenCV and TBB), 0: the libraries' default threading.
// Frames: Graffiti rendered through configs/cameras/lafida_fisheye0.yaml (needs opencv-doc).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>

#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <tbb/global_control.h>

#include "bench_scene.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/api/presets.hpp"
#include "mdbrief/match/match_refinement.hpp"
#include "mdbrief/match/matcher.hpp"

namespace {

constexpr int kFeatures = 1000;
constexpr float kRatio = 0.8f;  // cv::ORB + BFMatcher: the usual ratio

struct Views {
  mdbrief::CameraPtr camera;
  cv::Mat a, b;
};

const Views& views() {
  static const Views v = [] {
    return Views{mdbrief::bench::fisheyeScene().camera, mdbrief::bench::renderFisheyeView({0.3, 0.1, -0.8}),
                 mdbrief::bench::renderFisheyeView({0.25, 0.1, -0.8})};
  }();
  return v;
}

// Arg 1: cv::setNumThreads(1) and a TBB limit of 1 for the benchmark's lifetime.
struct Threading {
  explicit Threading(const benchmark::State& state) {
    if (state.range(0) == 1) {
      cv::setNumThreads(1);
      single = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
    }
  }
  ~Threading() { cv::setNumThreads(-1); }
  std::unique_ptr<tbb::global_control> single;
};

void BM_FrameMdBrief(benchmark::State& state) {
  const Views& v = views();
  if (v.a.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  const Threading threading(state);
  mdbrief::MdBriefOptions options;
  options.detector.nfeatures = kFeatures;
  const cv::Ptr<mdbrief::MdBrief> md = mdbrief::MdBrief::create(v.camera, options);
  std::vector<cv::KeyPoint> kb;
  cv::Mat db, mb;
  md->detectAndComputeWithMasks(v.b, cv::noArray(), kb, db, mb);
  const mdbrief::MatchOptions match;
  size_t keypoints = 0, matches = 0;
  for (auto _ : state) {
    std::vector<cv::KeyPoint> ka;
    cv::Mat da, ma;
    md->detectAndComputeWithMasks(v.a, cv::noArray(), ka, da, ma);
    const auto m = mdbrief::matchBruteForceMasked(da, ma, db, mb, match);
    keypoints = ka.size();
    matches = m.size();
    benchmark::DoNotOptimize(m.data());
  }
  state.counters["keypoints"] = double(keypoints);
  state.counters["matches"] = double(matches);
}

void BM_FrameOrb(benchmark::State& state) {
  const Views& v = views();
  if (v.a.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  const Threading threading(state);
  const cv::Ptr<cv::ORB> orb = cv::ORB::create(kFeatures);
  std::vector<cv::KeyPoint> kb;
  cv::Mat db;
  orb->detectAndCompute(v.b, cv::noArray(), kb, db);
  const cv::BFMatcher matcher(cv::NORM_HAMMING);
  size_t keypoints = 0, matches = 0;
  for (auto _ : state) {
    std::vector<cv::KeyPoint> ka;
    cv::Mat da;
    orb->detectAndCompute(v.a, cv::noArray(), ka, da);
    std::vector<std::vector<cv::DMatch>> knn;
    matcher.knnMatch(da, db, knn, 2);
    size_t kept = 0;
    for (const auto& m : knn) kept += m.size() == 2 && m[0].distance < kRatio * m[1].distance;
    keypoints = ka.size();
    matches = kept;
    benchmark::DoNotOptimize(knn.data());
  }
  state.counters["keypoints"] = double(keypoints);
  state.counters["matches"] = double(matches);
}

// The defaults' features of both views, as the benchmarks below start from them.
struct FrameFeatures {
  cv::Ptr<mdbrief::MdBrief> md;
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, ma, db, mb;
};
FrameFeatures frameFeatures(const Views& v) {
  FrameFeatures f;
  mdbrief::MdBriefOptions options;
  options.detector.nfeatures = kFeatures;
  f.md = mdbrief::MdBrief::create(v.camera, options);
  f.md->detectAndComputeWithMasks(v.a, cv::noArray(), f.ka, f.da, f.ma);
  f.md->detectAndComputeWithMasks(v.b, cv::noArray(), f.kb, f.db, f.mb);
  return f;
}

// The three stages of BM_FrameMdBrief, single-threaded, to see where the time goes.
void BM_FrameMdBriefStages(benchmark::State& state) {
  const Views& v = views();
  if (v.a.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  cv::setNumThreads(1);
  const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  const FrameFeatures f = frameFeatures(v);
  const cv::Ptr<mdbrief::MdBrief>& md = f.md;
  const std::vector<cv::KeyPoint>& ka = f.ka;
  const cv::Mat &da = f.da, &ma = f.ma, &db = f.db, &mb = f.mb;
  const mdbrief::MatchOptions match;
  const int stage = static_cast<int>(state.range(0));
  for (auto _ : state) {
    if (stage == 0) {  // pyramid + detection
      const mdbrief::ImagePyramid pyramid(v.a, md->options().detector.pyramid);
      benchmark::DoNotOptimize(md->detector().detect(pyramid).data());
    } else if (stage == 1) {  // pyramid + smoothing + description of the detected keypoints
      auto kps = ka;
      cv::Mat d, m;
      md->extractor().compute(v.a, kps, d, m, md->options().detector.pyramid);
      benchmark::DoNotOptimize(d.data);
    } else {  // masked matching
      benchmark::DoNotOptimize(mdbrief::matchBruteForceMasked(da, ma, db, mb, match).data());
    }
  }
  cv::setNumThreads(-1);
}

// Sub-pixel refinement of the frame's matches (match_refinement.hpp) against the matching that
// found them, single-threaded, timed alternately in each iteration: counters us_per_match (the
// refinement) and refine_over_match (its time over the masked brute-force match's). The
// pyramids are the detection's, built outside the timing as a tracker keeps them. Arg: the
// finer levels refined on (MatchRefinementOptions::finerLevels: 10 the default, 2 the default
// before).
void BM_RefineMatches(benchmark::State& state) {
  const Views& v = views();
  if (v.a.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  cv::setNumThreads(1);
  const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  const FrameFeatures f = frameFeatures(v);
  const std::vector<cv::KeyPoint> &ka = f.ka, &kb = f.kb;
  const cv::Mat &da = f.da, &ma = f.ma, &db = f.db, &mb = f.mb;
  const mdbrief::PyramidOptions& pyramid = f.md->options().detector.pyramid;
  const mdbrief::ImagePyramid pa(v.a, pyramid), pb(v.b, pyramid);
  const mdbrief::MatchOptions match;
  const std::vector<cv::DMatch> matches = mdbrief::matchBruteForceMasked(da, ma, db, mb, match);
  mdbrief::MatchRefinementOptions refinement;
  refinement.finerLevels = static_cast<int>(state.range(0));
  for (int level = 0; level < pa.levels(); ++level)
    pa.smoothedFloat(level, refinement.smoothingSigma), pb.smoothedFloat(level, refinement.smoothingSigma);
  double refineSeconds = 0, matchSeconds = 0;
  size_t refined = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto m = mdbrief::matchBruteForceMasked(da, ma, db, mb, match);
    const auto t1 = std::chrono::steady_clock::now();
    const auto r = mdbrief::refineMatches(pa, *v.camera, ka, pb, *v.camera, kb, matches, refinement);
    const auto t2 = std::chrono::steady_clock::now();
    matchSeconds += std::chrono::duration<double>(t1 - t0).count();
    refineSeconds += std::chrono::duration<double>(t2 - t1).count();
    refined = 0;
    for (const auto& x : r) refined += x.ok();
    benchmark::DoNotOptimize(m.data());
  }
  state.counters["matches"] = double(matches.size());
  state.counters["refined"] = double(refined);
  state.counters["us_per_match"] = 1e6 * refineSeconds / double(state.iterations()) / double(std::max<size_t>(1, matches.size()));
  state.counters["refine_over_match"] = refineSeconds / std::max(1e-12, matchSeconds);
}

BENCHMARK(BM_FrameOrb)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RefineMatches)->Arg(10)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FrameMdBrief)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
// Arg: 0 = detect, 1 = describe, 2 = match.
BENCHMARK(BM_FrameMdBriefStages)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Detectors alone and with their descriptors, single-threaded, on frame A (issue 17's speed
// targets): Arg 0 the library's defaults (Hessian + mdBRIEF-256), 1 the `matching` preset
// (mdBRIEF-512), 2 the `paper` preset (modORB + mdBRIEF-256), 3 cv::ORB, 4 cv::AKAZE, 5 cv::BRISK,
// 6 the defaults without locating the blobs again on the input (DetectorOptions::relocalise): 0
// against 6 is that step's cost.
// AKAZE and BRISK have no keypoint budget (the count is in the `keypoints` counter): AKAZE at its
// defaults; BRISK at the threshold that finds about kFeatures on frame A (its default finds about
// five times as many and takes four times as long).
constexpr int kBriskThreshold = 74;
void detectorRun(benchmark::State& state, bool describe) {
  const Views& v = views();
  if (v.a.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  cv::setNumThreads(1);
  const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  const int which = static_cast<int>(state.range(0));
  cv::Ptr<cv::Feature2D> feature;
  if (which <= 2 || which == 6) {
    const mdbrief::Preset preset = std::array{mdbrief::Preset::Tracking, mdbrief::Preset::Matching,
                                              mdbrief::Preset::Paper}[which % 6];
    mdbrief::MdBriefOptions options = mdbrief::presetSettings(preset).features;
    options.detector.nfeatures = kFeatures;
    options.detector.relocalise = which != 6;
    feature = mdbrief::MdBrief::create(v.camera, options);
  } else if (which == 3) {
    feature = cv::ORB::create(kFeatures);
  } else if (which == 4) {
    feature = cv::AKAZE::create();
  } else {
    feature = cv::BRISK::create(kBriskThreshold);
  }
  state.SetLabel(std::array<const char*, 7>{"defaults (tracking)", "matching", "paper", "cv::ORB", "cv::AKAZE",
                                            "cv::BRISK", "defaults, blobs not relocalised"}[which]);
  size_t keypoints = 0;
  for (auto _ : state) {
    std::vector<cv::KeyPoint> ka;
    cv::Mat da;
    if (describe)
      feature->detectAndCompute(v.a, cv::noArray(), ka, da);
    else
      feature->detect(v.a, ka);
    keypoints = ka.size();
    benchmark::DoNotOptimize(ka.data());
  }
  state.counters["keypoints"] = double(keypoints);
  cv::setNumThreads(-1);
}
void BM_Detect(benchmark::State& state) { detectorRun(state, false); }
void BM_DetectAndDescribe(benchmark::State& state) { detectorRun(state, true); }

}  // namespace
BENCHMARK(BM_Detect)->DenseRange(0, 6)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DetectAndDescribe)->DenseRange(0, 6)->Unit(benchmark::kMillisecond)->UseRealTime();
