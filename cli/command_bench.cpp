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
#include <utility>
#include <vector>

#include <opencv2/features2d.hpp>
#include <tbb/global_control.h>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/extraction_flags.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/match/matcher.hpp"
#include "mdbrief/api/presets.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "toolkit/cpu_model.hpp"
#include "toolkit/data_folders.hpp"
#include "toolkit/image_file.hpp"
#include "toolkit/option_flags.hpp"
#include "scenes/photo_camera.hpp"

namespace mdbrief::cli {
namespace {

struct BenchFlags {
  std::string image, level = "all";
  bool levelGiven = false;  // --level replaces MDBRIEF_SIMD_LEVEL
  CameraFileFlags camera;
  int nfeatures = presetSettings(Preset::Tracking).features.detector.nfeatures;  // the preset bench runs
  int repeat = 15;
};

// Median wall times of `repeat` runs of each of a and b, in milliseconds, after one run of each
// that warms the caches. The runs alternate, so that a change of the machine's load between
// them moves both figures and not their ratio.
std::pair<double, double> medianMs(int repeat, const std::function<void()>& a, const std::function<void()>& b) {
  const auto ms = [](const std::function<void()>& run) {
    const auto start = std::chrono::steady_clock::now();
    run();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  a();
  b();
  std::vector<double> ta, tb;
  for (int i = 0; i < repeat; ++i) ta.push_back(ms(a)), tb.push_back(ms(b));
  const auto median = [repeat](std::vector<double>& t) {
    std::nth_element(t.begin(), t.begin() + repeat / 2, t.end());
    return t[repeat / 2];
  };
  return {median(ta), median(tb)};
}

// A run of one OpenCV detector's detectAndCompute, which keeps the keypoints it found.
std::function<void()> openCvRun(const cv::Ptr<cv::Feature2D>& feature, const cv::Mat& image,
                                std::vector<cv::KeyPoint>& keypoints) {
  return [feature, &image, &keypoints] {
    cv::Mat descriptors;
    feature->detectAndCompute(image, cv::noArray(), keypoints, descriptors);
  };
}

void run(const BenchFlags& flags) {
  if (flags.repeat < 1 || flags.repeat > 1000) throw InputError("--repeat: must be in [1, 1000]");
  // The levels first, before any work: --level replaces MDBRIEF_SIMD_LEVEL; without it the
  // variable caps them as it caps every kernel.
  std::vector<SimdLevel> levels = supportedSimdLevels();
  if (flags.levelGiven) limitSimdLevel(levels.back());
  if (flags.level != "all") {
    const SimdLevel wanted = parseSimdLevel(flags.level);
    if (std::find(levels.begin(), levels.end(), wanted) == levels.end())
      throw InputError("--level: this CPU or build does not run '" + flags.level + "'");
    levels = {wanted};
  }
  const SimdLevel top = activeSimdLevel();
  if (!flags.levelGiven) levels.erase(std::find(levels.begin(), levels.end(), top) + 1, levels.end());
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
  if (flags.camera.path.empty() && flags.camera.anyGiven())
    throw InputError("--camera-format, --camera-id, --camera-size and --camera-opencv-model need --camera");
  const CameraPtr camera =
      flags.camera.path.empty() ? photoCamera(image.size()) : readCalibrationFile(flags.camera).camera;
  if (camera->imageSize() != image.size())
    throw InputError("--camera: " + flags.camera.path + " is for " + std::to_string(camera->imageSize().width) + "x" +
                     std::to_string(camera->imageSize().height) + " images, " + imagePath + " is " +
                     std::to_string(image.cols) + "x" + std::to_string(image.rows));

  // One thread, as the speed figures of docs/speed.md.
  cv::setNumThreads(1);
  const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
  const int repeat = flags.repeat;
  // AKAZE and BRISK take ten times as long as ORB: timed once, side by side, as the reference
  // for their ratios; ORB beside each level.
  std::vector<cv::KeyPoint> orbFound, akazeFound, briskFound;
  const auto orbRun = openCvRun(cv::ORB::create(flags.nfeatures), image, orbFound);
  const auto [akaze, brisk] = medianMs(repeat, openCvRun(cv::AKAZE::create(), image, akazeFound),
                                       openCvRun(cv::BRISK::create(), image, briskFound));
  orbRun();
  std::printf("mdbrief bench: %s, one thread, %s (%dx%d), median of %d runs\n", toolkit::cpuModel().c_str(),
              imagePath.c_str(), image.cols, image.rows, repeat);
  std::printf("OpenCV %s: ORB %zu keypoints; AKAZE %.2f ms (%zu keypoints), BRISK %.2f ms (%zu)\n", CV_VERSION,
              orbFound.size(), akaze, akazeFound.size(), brisk, briskFound.size());
  std::printf("%-18s %9s %9s %9s %6s %7s %7s %9s %9s %6s\n", "level", "keypoints", "det+desc", "ORB", "x ORB",
              "x AKAZE", "x BRISK", "match", "BF knn", "x BF");

  MdBriefOptions options = presetSettings(Preset::Tracking).features;
  options.detector.nfeatures = flags.nfeatures;
  const cv::Ptr<MdBrief> features = MdBrief::create(camera, options);
  MatchOptions ratioOnly;  // the two nearest, as knnMatch(k = 2), without the mutual check
  ratioOnly.crossCheck = false;
  for (const SimdLevel level : levels) {
    limitSimdLevel(level);
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors, masks;
    const auto [ours, orb] = medianMs(
        repeat, [&] { features->detectAndComputeWithMasks(image, cv::noArray(), keypoints, descriptors, masks); },
        orbRun);
    // Each frame's descriptors against themselves: brute force costs the same whatever they are.
    const cv::BFMatcher bf(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    const auto [match, bfMs] =
        medianMs(repeat, [&] { matchBruteForceMasked(descriptors, masks, descriptors, masks, ratioOnly); },
                 [&] { bf.knnMatch(descriptors, descriptors, knn, 2); });
    const std::string name = toString(level) + " (" + activeSimdTargetName() + ")";
    std::printf("%-18s %9zu %6.2f ms %6.2f ms %6.2f %7.2f %7.2f %6.2f ms %6.2f ms %6.2f\n", name.c_str(),
                keypoints.size(), ours, orb, ours / orb, ours / akaze, ours / brisk, match, bfMs, match / bfMs);
  }
  limitSimdLevel(top);
  std::fflush(stdout);
}

}  // namespace

void addBenchCommand(CLI::App& app) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* cmd = app.add_subcommand(
      "bench", "Time detection + description and matching on this machine against OpenCV's ORB, AKAZE, BRISK and "
               "BFMatcher, at every SIMD level this CPU runs");
  cmd->add_option("--image", flags->image, "Image to detect on (default: opencv-doc's graf1.png)")
      ->check(inputFileCheck());
  cmd->add_option("--camera", flags->camera.path, "Its calibration (default: a pinhole for an undistorted photo)")
      ->check(inputFileCheck());
  addCameraFileFlags(*cmd, flags->camera, "--camera");
  addFieldFlag(*cmd, detectorOptionFields(), "nfeatures", flags->nfeatures, "cv::ORB's budget too");
  CLI::Option* level =
      cmd->add_option("--level", flags->level, "A SIMD level (portable, sse4, neon, avx2, avx512), or all")
          ->capture_default_str();
  cmd->add_option("--repeat", flags->repeat, "Runs per figure; the median is printed")->capture_default_str();
  cmd->callback([flags, level] {
    flags->levelGiven = level->count() > 0;
    run(*flags);
  });
}

}  // namespace mdbrief::cli
