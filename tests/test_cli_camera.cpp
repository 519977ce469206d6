// `mdbrief camera convert` and the calibration flags of extract and draw (--camera-format,
// --camera-id): every sample of tests/data/camera_formats converts to its project YAML, the bad
// calibration seeds exit 2 naming the file and the problem, and extract describes with a tool's
// file exactly as with the project YAML.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_runner.hpp"
#include "mdbrief/camera/io.hpp"
#include "test_data.hpp"

namespace mdbrief {
namespace {

namespace fs = std::filesystem;
using testing::expectOneLineNaming;
using testing::runMdbrief;

const fs::path kFormats = testing::sourceDir() / "tests/data/camera_formats";

std::string contentOf(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class CameraCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mdbrief_test_cli_camera_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(CameraCommand, ConvertWritesTheProjectYamlOfEachTool) {
  const struct {
    const char* file;
    const char* id;
    const char* expected;
    const char* format;
  } cases[] = {{"kalibr_camchain.yaml", "cam1", "kalibr_camchain_cam1", "kalibr"},
               {"basalt_calib.json", "4", "basalt_calib_4", "basalt"},
               {"orbslam3_kannala_brandt8_stereo.yaml", "2", "orbslam3_kannala_brandt8_stereo_2", "orbslam3"},
               {"orbslam3_pinhole.yaml", "", "orbslam3_pinhole", "orbslam3"},
               {"opencv_fisheye.yaml", "", "opencv_fisheye", "opencv"},
               {"colmap_cameras.txt", "1", "colmap_cameras_1", "colmap"},
               {"euroc_cam0_sensor.yaml", "", "kalibr_camchain_cam0", "euroc"},
               {"kimera_omni_sensor.yaml", "", "kimera_omni_sensor", "euroc"},
               {"opencv_kd_standard.yaml", "", "opencv_standard", "opencv-kd"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    std::vector<std::string> args = {"camera", "convert", (kFormats / c.file).string(), "-o", path("out.yaml")};
    if (*c.id) args.insert(args.end(), {"--camera-id", c.id});
    const auto r = runMdbrief(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string("(") + c.format), std::string::npos) << r.out;
    const auto expected = loadCamera((kFormats / "expected" / (std::string(c.expected) + ".yaml")).string());
    EXPECT_EQ(contentOf(path("out.yaml")), cameraToYaml(*expected));
  }
  // Without -o the YAML goes to stdout; an explicit format reads the same.
  const auto r = runMdbrief({"camera", "convert", (kFormats / "opencv_standard.yaml").string(), "--format", "opencv"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, cameraToYaml(*loadCamera((kFormats / "expected/opencv_standard.yaml").string())));
}

// Issue 29: `-o out.json` wrote YAML into a .json file.
TEST_F(CameraCommand, ConvertRefusesAnOutputThatIsNotYaml) {
  for (const char* name : {"out.json", "out.xml", "out"}) {
    expectOneLineNaming(runMdbrief({"camera", "convert", (kFormats / "opencv_fisheye.yaml").string(), "-o", path(name)}),
                        path(name) + ": the output is the project's YAML and must end in .yaml or .yml");
    EXPECT_FALSE(fs::exists(path(name)));
  }
}

TEST_F(CameraCommand, BadCalibrationsExitTwoNamingTheFileAndTheProblem) {
  int seen = 0;
  for (const auto& entry : fs::directory_iterator(testing::sourceDir() / "fuzz/seeds/camera")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("truncated_", 0) != 0 && name.rfind("lookalike_", 0) != 0) continue;
    SCOPED_TRACE(name);
    const auto r = runMdbrief({"camera", "convert", entry.path().string(), "-o", path("out.yaml")});
    expectOneLineNaming(r, entry.path().string() + ": ");
    EXPECT_FALSE(fs::exists(path("out.yaml")));
    ++seen;
  }
  EXPECT_GE(seen, 14);
  expectOneLineNaming(runMdbrief({"camera", "convert", (kFormats / "kalibr_camchain.yaml").string()}),
                      "holds cameras cam0, cam1, cam2, cam3, cam4: choose one");
  expectOneLineNaming(
      runMdbrief({"camera", "convert", (kFormats / "kalibr_camchain.yaml").string(), "--format", "colmap"}),
      "is not 'CAMERA_ID MODEL WIDTH HEIGHT PARAMS...'");
  expectOneLineNaming(runMdbrief({"camera", "convert", path("missing.yaml")}), path("missing.yaml"));
  expectOneLineNaming(
      runMdbrief({"camera", "convert", (kFormats / "opencv_fisheye.yaml").string(), "--format", "kalibr2"}),
      "--format");
}

// extract with a tool's file and --camera-id describes exactly as with the project YAML.
TEST_F(CameraCommand, ExtractWithAToolsFileMatchesTheProjectYamlByteForByte) {
  cv::Mat image(480, 752, CV_8U);
  cv::RNG(3).fill(image, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(image, image, cv::Size(0, 0), 2.0);
  ASSERT_TRUE(cv::imwrite(path("view.png"), image));
  const auto a = runMdbrief({"extract", "--camera", (kFormats / "kalibr_camchain.yaml").string(), "--camera-id", "cam1",
                             path("view.png"), "-o", path("a.yml")});
  ASSERT_EQ(a.code, 0) << a.err;
  const auto b = runMdbrief({"extract", "--camera", (kFormats / "expected/kalibr_camchain_cam1.yaml").string(),
                             path("view.png"), "-o", path("b.yml")});
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(contentOf(path("a.yml")), contentOf(path("b.yml")));
  EXPECT_GT(contentOf(path("a.yml")).size(), 10000u);
  expectOneLineNaming(runMdbrief({"extract", "--descriptor", "brief", "--camera-id", "cam1", path("view.png"), "-o",
                                  path("c.yml")}),
                      "--camera-format, --camera-id, --camera-size and --camera-opencv-model need --camera");
  expectOneLineNaming(runMdbrief({"extract", "--camera", (kFormats / "kalibr_camchain.yaml").string(), path("view.png"),
                                  "-o", path("c.yml")}),
                      "choose one");
}

// EuRoC / Kimera sensor files without a usable distortion model exit 2 naming the key, from
// every command that reads a camera; K and D alone take the size and model from flags.
TEST_F(CameraCommand, SensorFilesAndBareKdFilesOnTheCommandLine) {
  std::ofstream(path("sensor.yaml")) << "sensor_type: camera\nresolution: [752, 480]\ncamera_model: pinhole\n"
                                        "intrinsics: [461, 460, 366, 249]\ndistortion_coefficients: [0, 0, 0, 0]\n";
  std::ofstream(path("fov.yaml")) << "sensor_type: camera\nresolution: [752, 480]\ncamera_model: pinhole\n"
                                     "intrinsics: [461, 460, 366, 249]\ndistortion_model: fov\n";
  cv::Mat image(480, 752, CV_8U, cv::Scalar(128));
  ASSERT_TRUE(cv::imwrite(path("view.png"), image));
  for (const char* file : {"sensor.yaml", "fov.yaml"}) {
    SCOPED_TRACE(file);
    const std::string key = std::string(file) == "sensor.yaml" ? "key 'distortion_model' is missing"
                                                               : "key 'distortion_model' names an unknown model 'fov'";
    expectOneLineNaming(runMdbrief({"camera", "convert", path(file)}), path(file) + ": " + key);
    expectOneLineNaming(runMdbrief({"extract", "--camera", path(file), path("view.png"), "-o", path("out.yml")}),
                        path(file) + ": " + key);
    EXPECT_FALSE(fs::exists(path("out.yml")));
  }
  const std::string kd = (kFormats / "opencv_kd_fisheye.yaml").string();
  expectOneLineNaming(runMdbrief({"camera", "convert", kd}), "give it (mdbrief --camera-size WxH");
  expectOneLineNaming(runMdbrief({"camera", "convert", kd, "--camera-size", "752x480"}),
                      "--camera-opencv-model fisheye|standard");
  expectOneLineNaming(runMdbrief({"camera", "convert", kd, "--camera-size", "752 by 480"}),
                      "--camera-size must be WxH");
  const auto r = runMdbrief({"camera", "convert", kd, "--camera-size", "752x480", "--camera-opencv-model", "fisheye"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, cameraToYaml(*loadCamera((kFormats / "expected/opencv_fisheye.yaml").string())));
  // The refusal of an unknown file names the flag that chooses a format.
  std::ofstream(path("unknown.yaml")) << "a: 1\n";
  expectOneLineNaming(runMdbrief({"camera", "convert", path("unknown.yaml")}), "--camera-format NAME");
}

}  // namespace
}  // namespace mdbrief
