// Description time per keypoint: BRIEF, dBRIEF (both forms) and mdBRIEF, 256 bits, against
// cv::ORB::compute on the same 752x480 fisheye image and the same 1000 keypoints. Each
// benchmark builds its own pyramid from the image, as cv::ORB::compute does.
// The image is Graffiti rendered through the paper's fisheye camera (needs opencv-doc).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/global_control.h>

#include "bench_scene.hpp"
#include "mdbrief/describe/descriptor.hpp"

namespace {

struct Frame {
  mdbrief::CameraPtr camera;
  cv::Mat image;
  std::vector<cv::KeyPoint> keypoints;
};

const Frame& fisheyeFrame() {
  static const Frame frame = [] {
    Frame f;
    f.camera = mdbrief::bench::fisheyeScene().camera;
    f.image = mdbrief::bench::renderFisheyeView({0.3, 0.1, -0.8});
    if (!f.image.empty()) cv::ORB::create(1000)->detect(f.image, f.keypoints);
    return f;
  }();
  return frame;
}

void setThreads(benchmark::State& state) {
  // Arg 1: single thread everywhere (OpenCV and TBB); 0: the libraries' defaults.
  cv::setNumThreads(state.range(0) == 1 ? 1 : -1);
}

void BM_OrbCompute(benchmark::State& state) {
  const Frame& f = fisheyeFrame();
  if (f.image.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  setThreads(state);
  const auto orb = cv::ORB::create(1000);
  size_t n = 0;
  for (auto _ : state) {
    auto kps = f.keypoints;
    cv::Mat desc;
    orb->compute(f.image, kps, desc);
    n = kps.size();
    benchmark::DoNotOptimize(desc.data);
  }
  state.counters["us_per_kp"] = mdbrief::bench::microsecondsPerItem(double(n), state.iterations());
  state.counters["keypoints"] = double(n);
  cv::setNumThreads(-1);
}

void describe(benchmark::State& state, mdbrief::DescriptorKind kind, mdbrief::DistortionForm form) {
  const Frame& f = fisheyeFrame();
  if (f.image.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  mdbrief::DescriptorOptions o;
  o.kind = kind;
  o.form = form;
  const mdbrief::DescriptorExtractor ex(f.camera, o);
  std::unique_ptr<tbb::global_control> single;
  setThreads(state);
  if (state.range(0) == 1) single = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
  size_t n = 0;
  for (auto _ : state) {
    auto kps = f.keypoints;
    cv::Mat desc, masks;
    ex.compute(f.image, kps, desc, masks);
    n = kps.size();
    benchmark::DoNotOptimize(desc.data);
  }
  state.counters["us_per_kp"] = mdbrief::bench::microsecondsPerItem(double(n), state.iterations());
  state.counters["keypoints"] = double(n);
  cv::setNumThreads(-1);
}

void BM_Brief(benchmark::State& s) { describe(s, mdbrief::DescriptorKind::Brief, mdbrief::DistortionForm::Affine); }
void BM_DBriefAffine(benchmark::State& s) { describe(s, mdbrief::DescriptorKind::DBrief, mdbrief::DistortionForm::Affine); }
void BM_DBriefPaper(benchmark::State& s) { describe(s, mdbrief::DescriptorKind::DBrief, mdbrief::DistortionForm::Paper); }
void BM_MdBriefAffine(benchmark::State& s) { describe(s, mdbrief::DescriptorKind::MdBrief, mdbrief::DistortionForm::Affine); }
void BM_MdBriefPaper(benchmark::State& s) { describe(s, mdbrief::DescriptorKind::MdBrief, mdbrief::DistortionForm::Paper); }

// Arg: 1 = single-threaded, 0 = default threading.
BENCHMARK(BM_OrbCompute)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Brief)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DBriefAffine)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DBriefPaper)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MdBriefAffine)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MdBriefPaper)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

namespace {

// Description alone on a prebuilt, smoothed pyramid (what a detect-and-describe pipeline pays
// on top of detection, which builds the pyramid anyway).
void describePrebuilt(benchmark::State& state, mdbrief::DescriptorKind kind,
                      mdbrief::OrientationSource source = mdbrief::OrientationSource::TangentPlane) {
  const Frame& f = fisheyeFrame();
  if (f.image.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  mdbrief::DescriptorOptions o;
  o.kind = kind;
  o.orientation = source;
  const mdbrief::DescriptorExtractor ex(f.camera, o);
  const mdbrief::ImagePyramid pyramid(f.image, mdbrief::PyramidOptions{});
  pyramid.prepareSmoothed(pyramid.levels() - 1);
  tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  size_t n = 0;
  for (auto _ : state) {
    auto kps = f.keypoints;
    cv::Mat desc, masks;
    ex.compute(pyramid, kps, desc, masks);
    n = kps.size();
    benchmark::DoNotOptimize(desc.data);
  }
  state.counters["us_per_kp"] = mdbrief::bench::microsecondsPerItem(double(n), state.iterations());
}
void BM_BriefPrebuiltPyramid(benchmark::State& s) { describePrebuilt(s, mdbrief::DescriptorKind::Brief); }
void BM_DBriefPrebuiltPyramid(benchmark::State& s) { describePrebuilt(s, mdbrief::DescriptorKind::DBrief); }
void BM_MdBriefPrebuiltPyramid(benchmark::State& s) { describePrebuilt(s, mdbrief::DescriptorKind::MdBrief); }
// The same with the detector's angle: what re-measuring the orientation on the tangent plane costs.
void BM_DBriefKeypointAnglePrebuiltPyramid(benchmark::State& s) {
  describePrebuilt(s, mdbrief::DescriptorKind::DBrief, mdbrief::OrientationSource::Keypoint);
}
void BM_MdBriefKeypointAnglePrebuiltPyramid(benchmark::State& s) {
  describePrebuilt(s, mdbrief::DescriptorKind::MdBrief, mdbrief::OrientationSource::Keypoint);
}
BENCHMARK(BM_BriefPrebuiltPyramid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DBriefKeypointAnglePrebuiltPyramid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MdBriefKeypointAnglePrebuiltPyramid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DBriefPrebuiltPyramid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MdBriefPrebuiltPyramid)->Unit(benchmark::kMillisecond);

// The 8-level pyramid's levels alone (the bilinear reductions), one thread.
void BM_Pyramid(benchmark::State& state) {
  const Frame& f = fisheyeFrame();
  if (f.image.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  cv::setNumThreads(1);
  for (auto _ : state) {
    const mdbrief::ImagePyramid pyramid(f.image, mdbrief::PyramidOptions{});
    benchmark::DoNotOptimize(pyramid.image(pyramid.levels() - 1).data);
  }
  cv::setNumThreads(-1);
}
BENCHMARK(BM_Pyramid)->Unit(benchmark::kMicrosecond)->UseRealTime();

// The part of every description that does not depend on the descriptor: the 8-level pyramid
// and its smoothing (shared with the detector in a whole-frame pipeline).
void BM_PyramidAndSmoothing(benchmark::State& state) {
  const Frame& f = fisheyeFrame();
  if (f.image.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  cv::setNumThreads(1);
  for (auto _ : state) {
    const mdbrief::ImagePyramid pyramid(f.image, mdbrief::PyramidOptions{});
    pyramid.prepareSmoothed(pyramid.levels() - 1);
    benchmark::DoNotOptimize(pyramid.smoothed(0).data);
  }
  cv::setNumThreads(-1);
}
BENCHMARK(BM_PyramidAndSmoothing)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same part of ORB::compute: OpenCV's 7x7 Gaussian (sigma 2) over ORB's 8 levels, each a view
// inside a copy with a 31-pixel border (edgeThreshold), as cv::ORB smooths them before it reads
// its tests. Without its resizing, so a lower bound of what it pays for the pyramid.
void BM_OrbSmoothing(benchmark::State& state) {
  const Frame& f = fisheyeFrame();
  if (f.image.empty()) return state.SkipWithError("opencv-doc graf1.png missing");
  constexpr int kLevels = 8, kBorder = 31;
  std::vector<cv::Mat> bordered(kLevels);
  for (int k = 0; k < kLevels; ++k) {
    const double scale = std::pow(1.2, k);
    cv::Mat level;
    cv::resize(f.image, level, cv::Size(cvRound(f.image.cols / scale), cvRound(f.image.rows / scale)), 0, 0,
               cv::INTER_LINEAR_EXACT);
    cv::copyMakeBorder(level, bordered[k], kBorder, kBorder, kBorder, kBorder, cv::BORDER_REFLECT_101);
  }
  cv::setNumThreads(1);
  for (auto _ : state) {
    for (const cv::Mat& b : bordered) {
      cv::Mat view = b(cv::Rect(kBorder, kBorder, b.cols - 2 * kBorder, b.rows - 2 * kBorder));
      cv::GaussianBlur(view, view, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
    }
    benchmark::DoNotOptimize(bordered[0].data);
  }
  cv::setNumThreads(-1);
}
BENCHMARK(BM_OrbSmoothing)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
