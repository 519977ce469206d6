// `mdbrief bench`: how fast the library is on this machine, against OpenCV in the same run. One
// thread, one image (given, or opencv-doc's Graffiti), the defaults' detection + description of
// `--nfeatures` keypoints against cv::ORB, cv::AKAZE and cv::BRISK, and masked matching against
// cv::BFMatcher's knnMatch, at every SIMD level the CPU runs (or the one named). The lines name
// the CPU and each level, so a figure says where it was measured (docs/speed.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/features2d.hpp>
#include <tbb/global_control.h>

#include "cli/commands.hpp"
#include "mdbrief/camera_io.hpp"
#include "mdbrief/feature2d.hpp"
#include "mdbrief/matcher.hpp"
#include "mdbrief/presets.hpp"
#include "mdbrief/simd_level.hpp"
#include "toolkit/cpu_model.hpp"
#include "toolkit/data_folders.hpp"
#include "toolkit/image_file.hpp"
#include "toolkit/photo_camera.hpp"

namespace mdbrief::cli {
namespace {

struct BenchFlags {
  std::string image, camera, level = "all";
  int nfeatures = 1000;
  int repeat = 15;
};

// Median wall time of `repeat` runs, in milliseconds, after one run that warms the caches.
double medianMs(int repeat, const std::function<void()>& run) {
  run();
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    const auto start = std::chrono::steady_clock::now();
    run();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(ms.begin(), ms.begin() + repeat / 2, ms.end());
  return ms[repeat / 2];
}

// The time of one OpenCV detector's detectAndCompute, and the keypoints it found.
double openCvMs(const cv::Ptr<cv::Feature2D>& feature, const cv::Mat& image, int repeat, size_t& found) {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  const double ms = medianMs(repeat, [&] { feature->detectAndCompute(image, cv::noArray(), keypoints, descriptors); });
  found = keypoints.size();
  return ms;
}

void run(const BenchFlags& flags) {
  if (flags.repeat < 1 || flags.repeat > 1000) throw InputError("--repeat: must be in [1, 1000]");
  if (flags.nfeatures < 1 || flags.nfeatures > 100000) throw InputError("--nfeatures: must be in [1, 100000]");
  std::string imagePath = flags.image;
  if (imagePath.empty()) {
    const auto doc = opencvDocFolder();
    if (!doc) throw InputError("--image: none given, and opencv-doc's graf1.png (the default) is not installed");
    imagePath = (*doc / "graf1.png").string();
  }
  if (const std::string problem = truncationProblem(imagePath); !problem.empty())
    throw InputError(imagePath + ": " + problem);
  const cv::Mat image = decodeGreyImage(imagePath);
  if (image.empty()) throw InputError(imagePath + ": no image decoder reads it");
  const CameraPtr camera = flags.camera.empty() ? photoCamera(image.size()) : loadCamera(flags.camera);
  if (camera->imageSize() != image.size())
    throw InputError("--camera: " + flags.camera + " is for " + std::to_string(camera->imageSize().width) + "x" +
                     std::to_string(camera->imageSize().height) + " images, " + imagePath + " is " +
                     std::to_string(image.cols) + "x" + std::to_string(image.rows));
  std::vector<SimdLevel> levels = supportedSimdLevels();
  if (flags.level != "all") {
    const SimdLevel wanted = parseSimdLevel(flags.level);
    if (std::find(levels.begin(), levels.end(), wanted) == levels.end())
      throw InputError("--level: this CPU or build does not run '" + flags.level + "'");
    levels = {wanted};
  }

  // One thread, as the speed figures of docs/speed.md.
  cv::setNumThreads(1);
  const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  const int repeat = flags.repeat;
  size_t orbFound = 0, akazeFound = 0, briskFound = 0;
  const double orb = openCvMs(cv::ORB::create(flags.nfeatures), image, repeat, orbFound);
  const double akaze = openCvMs(cv::AKAZE::create(), image, repeat, akazeFound);
  const double brisk = openCvMs(cv::BRISK::create(), image, repeat, briskFound);
  std::printf("mdbrief bench: %s, one thread, %s (%dx%d), median of %d runs\n", toolkit::cpuModel().c_str(),
              imagePath.c_str(), image.cols, image.rows, repeat);
  std::printf("OpenCV %s: ORB %.2f ms (%zu keypoints), AKAZE %.2f ms (%zu), BRISK %.2f ms (%zu)\n", CV_VERSION, orb,
              orbFound, akaze, akazeFound, brisk, briskFound);
  std::printf("%-20s %10s %10s %8s %8s %8s %12s %12s %10s\n", "level", "keypoints", "det+desc", "x ORB", "x AKAZE",
              "x BRISK", "match", "BFMatcher", "x BF");

  MdBriefOptions options = presetSettings(Preset::Tracking).features;
  options.detector.nfeatures = flags.nfeatures;
  const cv::Ptr<MdBrief> features = MdBrief::create(camera, options);
  MatchOptions ratioOnly;  // the two nearest, as knnMatch(k = 2), without the mutual check
  ratioOnly.crossCheck = false;
  for (const SimdLevel level : levels) {
    limitSimdLevel(level);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors, masks;
    const double ours = medianMs(
        repeat, [&] { features->detectAndComputeWithMasks(image, cv::noArray(), keypoints, descriptors, masks); });
    // Each frame's descriptors against themselves: brute force costs the same whatever they are.
    const double match = medianMs(repeat, [&] { matchBruteForceMasked(descriptors, masks, descriptors, masks, ratioOnly); });
    const cv::BFMatcher bf(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    const double bfMs = medianMs(repeat, [&] { bf.knnMatch(descriptors, descriptors, knn, 2); });
    const std::string name = toString(level) + " (" + activeSimdTargetName() + ")";
    std::printf("%-20s %10zu %7.2f ms %8.2f %8.2f %8.2f %9.2f ms %9.2f ms %10.2f\n", name.c_str(), keypoints.size(),
                ours, ours / orb, ours / akaze, ours / brisk, match, bfMs, match / bfMs);
  }
  limitSimdLevel(SimdLevel::Avx512);
  std::fflush(stdout);
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time detection + description and matching on this machine against OpenCV's ORB, AKAZE, BRISK and "
               "BFMatcher, at every SIMD level this CPU runs");
  cmd->add_option("--image", flags->image, "Image to detect on (default: opencv-doc's graf1.png)");
  cmd->add_option("--camera", flags->camera, "Its calibration (default: a pinhole for an undistorted photo)");
  cmd->add_option("--nfeatures", flags->nfeatures, "Keypoints to detect (ORB's budget too)")->capture_default_str();
  cmd->add_option("--level", flags->level, "A SIMD level (portable, sse4, neon, avx2, avx512), or all")
      ->capture_default_str();
  cmd->add_option("--repeat", flags->repeat, "Runs per figure; the median is printed")->capture_default_str();
  cmd->callback([flags] { run(*flags); });
}

}  // namespace mdbrief::cli
