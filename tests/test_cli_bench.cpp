// `mdbrief bench` (cli/command_bench.cpp): a line per SIMD level with its ratios to OpenCV, and
// clear refusals of what it cannot measure.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_runner.hpp"
#include "mdbrief/base/simd_level.hpp"

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
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--camera",
                                  MDBRIEF_SOURCE_DIR "/configs/cameras/lafida_fisheye0.yaml"}),
                      "--camera");
  // A rig file's camera by --camera-id, as for extract.
  const std::string kalibr = MDBRIEF_SOURCE_DIR "/tests/data/camera_formats/kalibr_camchain.yaml";
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--camera", kalibr}), "choose one by its id");
  expectOneLineNaming(runMdbrief({"bench", "--image", image_, "--camera", kalibr, "--camera-id", "cam1"}),
                      "--camera: " + kalibr + " is for 752x480 images");
}

}  // namespace
