// Detection time per image: mdbrief::Detector (modORB) against cv::ORB::detect at 1000
// features on the same images, in the same run.
//   752x480: the shared fisheye sample (fisheye/calib-adapter/kalibr/image.png), or else
//            opencv-doc's graf1.png resized to 752x480;
//   graf:    opencv-doc's graf1.png (800x640).
// And the halving that blob localisation reads, against cv::pyrDown, whose bits it gives.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "detect/resize_kernels.hpp"
#include "mdbrief/detect/detector.hpp"
#include "toolkit/data_folders.hpp"
#include "toolkit/image_file.hpp"

namespace {

constexpr int kFeatures = 1000;

const cv::Mat& grafImage() {
  static const cv::Mat image = [] {
    const auto dir = mdbrief::opencvDocFolder();
    return dir ? mdbrief::decodeGreyImage(*dir / "graf1.png") : cv::Mat();
  }();
  return image;
}

const cv::Mat& vgaImage() {
  static const cv::Mat image = [] {
    const auto data = mdbrief::sharedDataFolder(MDBRIEF_SOURCE_DIR "/../shared/data");
    const cv::Mat fisheye =
        data ? mdbrief::decodeGreyImage(*data / "fisheye/calib-adapter/kalibr/image.png") : cv::Mat();
    if (!fisheye.empty() && fisheye.size() == cv::Size(752, 480)) return fisheye;
    cv::Mat resized;
    if (!grafImage().empty()) cv::resize(grafImage(), resized, cv::Size(752, 480), 0, 0, cv::INTER_AREA);
    return resized;
  }();
  return image;
}

const cv::Mat& imageFor(int which) { return which == 0 ? vgaImage() : grafImage(); }
const char* nameOf(int which) { return which == 0 ? "752x480" : "graf 800x640"; }

void ModOrbDetect(benchmark::State& state, mdbrief::CornerDetector corners) {
  const cv::Mat& image = imageFor(static_cast<int>(state.range(0)));
  if (image.empty()) {
    state.SkipWithError("image not found");
    return;
  }
  mdbrief::DetectorOptions options;
  options.nfeatures = kFeatures;
  options.corners = corners;
  const mdbrief::Detector detector(nullptr, options);
  size_t count = 0;
  for (auto _ : state) {
    const std::vector<cv::KeyPoint> keypoints = detector.detect(image);
    count = keypoints.size();
    benchmark::DoNotOptimize(keypoints.data());
  }
  state.counters["keypoints"] = static_cast<double>(count);
  state.SetLabel(nameOf(static_cast<int>(state.range(0))));
}

void BM_ModOrbDetectFast(benchmark::State& state) { ModOrbDetect(state, mdbrief::CornerDetector::Fast); }
void BM_ModOrbDetectAgast(benchmark::State& state) { ModOrbDetect(state, mdbrief::CornerDetector::Agast); }

void BM_CvOrbDetect(benchmark::State& state) {
  const cv::Mat& image = imageFor(static_cast<int>(state.range(0)));
  if (image.empty()) {
    state.SkipWithError("image not found");
    return;
  }
  const cv::Ptr<cv::ORB> orb = cv::ORB::create(kFeatures);
  std::vector<cv::KeyPoint> keypoints;
  for (auto _ : state) {
    orb->detect(image, keypoints);
    benchmark::DoNotOptimize(keypoints.data());
  }
  state.counters["keypoints"] = static_cast<double>(keypoints.size());
  state.SetLabel(nameOf(static_cast<int>(state.range(0))));
}

void Halve(benchmark::State& state, bool opencv) {
  const cv::Mat& image = imageFor(static_cast<int>(state.range(0)));
  if (image.empty()) {
    state.SkipWithError("image not found");
    return;
  }
  cv::Mat half((image.rows + 1) / 2, (image.cols + 1) / 2, CV_8UC1);
  // One thread, as the halving runs in the detector (and as `mdbrief bench` times OpenCV).
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  for (auto _ : state) {
    if (opencv)
      cv::pyrDown(image, half);
    else
      mdbrief::resize_kernels::halveImage(image.data, image.step, image.cols, image.rows, half.data, half.step);
    benchmark::DoNotOptimize(half.data);
  }
  cv::setNumThreads(threads);
  state.SetLabel(nameOf(static_cast<int>(state.range(0))));
}

void BM_HalveImage(benchmark::State& state) { Halve(state, false); }
void BM_CvPyrDown(benchmark::State& state) { Halve(state, true); }

}  // namespace

BENCHMARK(BM_HalveImage)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CvPyrDown)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ModOrbDetectFast)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ModOrbDetectAgast)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CvOrbDetect)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
