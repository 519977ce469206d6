// `mdbrief bench` (cli/command_bench.cpp): a line per SIMD level with its ratios to OpenCV, and
// clear refusals of what it cannot measure.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_runner.hpp"
#include "program_runner.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "mdbrief/detect/detector.hpp"
#include "option_flag_message.hpp"

namespace {

namespace fs = std::filesystem;
using mdbrief::testing::expectOneLineNaming;
using mdbrief::testing::runMdbrief;

class CliBenchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mdbrief_cli_bench_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    cv::Mat noise(240, 320, CV_8U), image;
    cv::randu(noise, 0, 256);
    cv::GaussianBlur(noise, image, cv::Size(), 2.0);
    cv::normalize(image, image, 0, 255, cv::NORM_MINMAX);
    image_ = (dir_ / "texture.png").string();
    ASSERT_TRUE(cv::imwrite(image_, image));
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::string image_;
};

TEST_F(CliBenchTest, PrintsTheCpuOpenCvAndALinePerLevel) {
  const auto r = runMdbrief({"bench", "--image", image_, "--nfeatures", "200", "--repeat", "1"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("one thread, " + image_ + " (320x240), median of 1 runs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("OpenCV " CV_VERSION ": ORB "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" x ORB "), std::string::npos) << r.out;
  for (const mdbrief::SimdLevel level : mdbrief::supportedSimdLevels())
    EXPECT_NE(r.out.find("\n" + mdbrief::toString(level) + " ("), std::string::npos) << r.out;
  EXPECT_EQ(mdbrief::activeSimdLevel(), mdbrief::supportedSimdLevel());  // the cap is lifted again
}

TEST_F(CliBenchTest, OneLevelWhenNamed) {
  const auto r = runMdbrief({"bench", "--image", image_, "--nfeatures", "100", "--repeat", "1", "--level", "portable"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\nportable (SCALAR) "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("\navx2 "), std::string::npos) << r.out;
}

TEST_F(CliBenchTest, RefusesWhatItCannotMeasure) {
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--level", "sse9"}),
                      "SIMD level 'sse9' is not one of: portable, sse4, neon, avx2, avx512");
#if defined(__x86_64__)
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--level", "neon"}),
                      "--level: this CPU or build does not run 'neon'");
#endif
  expectOneLineNaming(runMdbrief({"bench", "--image", (dir_ / "missing.png").string()}), "missing.png");
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--repeat", "0"}), "--repeat");
  // Issue 46: --nfeatures is the library's flag (detectorOptionFields), with its range and message.
  for (const char* bad : {"0", "10000001"})
    expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--nfeatures", bad}),
                        mdbrief::testing::optionFlagMessage(mdbrief::detectorOptionFields(), "nfeatures", bad));
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--camera",
                                  MDBRIEF_SOURCE_DIR "/configs/cameras/lafida_fisheye0.yaml"}),
                      "--camera");
  // A rig file's camera by --camera-id, as for extract.
  const std::string kalibr = MDBRIEF_SOURCE_DIR "/tests/data/camera_formats/kalibr_camchain.yaml";
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--camera", kalibr}), "choose one by its id");
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--camera", kalibr, "--camera-id", "cam1"}),
                      "--camera: " + kalibr + " is for 752x480 images");
}

// Issue 45: MDBRIEF_SIMD_LEVEL=AVX2 gave "invalid descriptor options" without naming the
// variable, `bench` ignored it, and `bench --level avx2` with it set ran AKAZE and BRISK and
// printed a header before failing. A bad value is refused before any work naming the variable,
// --level replaces it, and without --level it caps bench's levels as it caps every kernel.
TEST_F(CliBenchTest, MdbriefSimdLevelIsRefusedNamedOrReplacedByLevel) {
  using mdbrief::testing::runProgram;
  const std::chrono::seconds limit(120);
  const std::string named = "the environment variable MDBRIEF_SIMD_LEVEL is 'AVX2', not a SIMD level: portable, sse4, "
                            "neon, avx2, avx512";
  const std::string keypoints = (dir_ / "k.yml").string();
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"bench", "--image", image_, "--repeat", "1", "--nfeatures", "50"},
           {"extract", image_, "-o", keypoints},
           {"sim", "--out", dir_.string()}}) {
    const auto r = runProgram(MDBRIEF_CLI_PATH, args, limit, {"MDBRIEF_SIMD_LEVEL=AVX2"});
    EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << args[0] << ": " << r.err;
    EXPECT_EQ(r.err.find("invalid descriptor options"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(keypoints));
  const auto evalRun = runProgram(MDBRIEF_EVAL_PATH, {"sim", "--out", dir_.string()}, limit, {"MDBRIEF_SIMD_LEVEL=AVX2"});
  EXPECT_EQ(evalRun.code, 2) << evalRun.err;
  EXPECT_NE(evalRun.err.find(named), std::string::npos) << evalRun.err;
  const auto bench = [&](std::vector<std::string> args, const std::string& level) {
    args.insert(args.begin(), {"bench", "--image", image_, "--repeat", "1", "--nfeatures", "50"});
    return runProgram(MDBRIEF_CLI_PATH, args, limit, {"MDBRIEF_SIMD_LEVEL=" + level});
  };
  // --level replaces the variable, a bad value included.
  const auto replaced = bench({"--level", "portable"}, "AVX2");
  EXPECT_EQ(replaced.code, 0) << replaced.err;
  EXPECT_NE(replaced.out.find("\nportable (SCALAR) "), std::string::npos) << replaced.out;
  // Without --level the variable caps the levels.
  const auto capped = bench({}, "portable");
  EXPECT_EQ(capped.code, 0) << capped.err;
  const std::string& lines = capped.out;
  EXPECT_NE(lines.find("\nportable (SCALAR) "), std::string::npos) << lines;
  for (const mdbrief::SimdLevel level : mdbrief::supportedSimdLevels()) {
    if (level != mdbrief::SimdLevel::Portable) {
      EXPECT_EQ(lines.find("\n" + mdbrief::toString(level) + " ("), std::string::npos) << lines;
    }
  }
}

}  // namespace
