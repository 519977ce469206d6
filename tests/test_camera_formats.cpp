// Other tools' calibration files (camera/io.hpp): each sample of tests/data/camera_formats is the
// same camera as its project YAML in expected/ (the same parameters bit for bit, projections
// within 1e-6 px over the image, byte-identical descriptors); the format is recognised from the
// content or chosen; multi-camera files need a choice; look-alikes, truncated files and the
// rejected combinations are refused with the file and the problem named.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/radtan.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mdbrief;

fs::path formatsDir() { return mdbrief::testing::sourceDir() / "tests" / "data" / "camera_formats"; }
fs::path seedsDir() { return mdbrief::testing::sourceDir() / "fuzz" / "seeds" / "camera"; }

struct Sample {
  std::string file;
  std::string cameraId;  // empty: the file's only camera
  CameraFormat format;
  std::string expected;  // expected/<name>.yaml
  std::string model;
};

const std::vector<Sample> kSamples = {
    {"kalibr_camchain.yaml", "cam0", CameraFormat::Kalibr, "kalibr_camchain_cam0", "kannala_brandt"},
    {"kalibr_camchain.yaml", "cam1", CameraFormat::Kalibr, "kalibr_camchain_cam1", "omni"},
    {"kalibr_camchain.yaml", "cam2", CameraFormat::Kalibr, "kalibr_camchain_cam2", "double_sphere"},
    {"kalibr_camchain.yaml", "cam3", CameraFormat::Kalibr, "kalibr_camchain_cam3", "eucm"},
    {"kalibr_camchain.yaml", "cam4", CameraFormat::Kalibr, "kalibr_camchain_cam4", "radtan"},
    {"basalt_calib.json", "0", CameraFormat::Basalt, "basalt_calib_0", "kannala_brandt"},
    {"basalt_calib.json", "1", CameraFormat::Basalt, "basalt_calib_1", "double_sphere"},
    {"basalt_calib.json", "2", CameraFormat::Basalt, "basalt_calib_2", "eucm"},
    {"basalt_calib.json", "3", CameraFormat::Basalt, "basalt_calib_3", "ucm"},
    {"basalt_calib.json", "4", CameraFormat::Basalt, "basalt_calib_4", "radtan"},
    {"orbslam3_kannala_brandt8_stereo.yaml", "1", CameraFormat::OrbSlam3, "orbslam3_kannala_brandt8_stereo_1",
     "kannala_brandt"},
    {"orbslam3_kannala_brandt8_stereo.yaml", "2", CameraFormat::OrbSlam3, "orbslam3_kannala_brandt8_stereo_2",
     "kannala_brandt"},
    {"orbslam3_pinhole.yaml", "", CameraFormat::OrbSlam3, "orbslam3_pinhole", "radtan"},
    // The same lenses as EuRoC / Kimera sensor.yaml files.
    {"euroc_cam0_sensor.yaml", "", CameraFormat::Euroc, "kalibr_camchain_cam0", "kannala_brandt"},
    {"euroc_cam1_sensor.yaml", "", CameraFormat::Euroc, "kalibr_camchain_cam4", "radtan"},
    {"euroc_omni_sensor.yaml", "", CameraFormat::Euroc, "kalibr_camchain_cam1", "omni"},
    {"kimera_omni_sensor.yaml", "", CameraFormat::Euroc, "kimera_omni_sensor", "ocam"},
    {"opencv_kd_standard.yaml", "", CameraFormat::OpenCvKd, "opencv_standard", "radtan"},
    {"opencv_fisheye.yaml", "", CameraFormat::OpenCv, "opencv_fisheye", "kannala_brandt"},
    {"opencv_standard.yaml", "", CameraFormat::OpenCv, "opencv_standard", "radtan"},
    {"opencv_rational.yaml", "", CameraFormat::OpenCv, "opencv_rational", "radtan"},
    {"colmap_cameras.txt", "1", CameraFormat::Colmap, "colmap_cameras_1", "kannala_brandt"},
    {"colmap_cameras.txt", "2", CameraFormat::Colmap, "colmap_cameras_2", "radtan"},
    {"colmap_cameras.txt", "3", CameraFormat::Colmap, "colmap_cameras_3", "radtan"},
    {"colmap_cameras.txt", "4", CameraFormat::Colmap, "colmap_cameras_4", "radtan"},
    {"colmap_cameras.txt", "5", CameraFormat::Colmap, "colmap_cameras_5", "pinhole"},
    {"colmap_cameras.txt", "6", CameraFormat::Colmap, "colmap_cameras_6", "pinhole"},
    {"colmap_cameras.txt", "7", CameraFormat::Colmap, "colmap_cameras_7", "radtan"},
};

std::string describe(const Sample& s) { return s.file + (s.cameraId.empty() ? "" : " camera " + s.cameraId); }

std::shared_ptr<Camera> loadSample(const Sample& s, CameraFormat format = CameraFormat::Auto) {
  return loadCamera((formatsDir() / s.file).string(), {format, s.cameraId});
}

std::shared_ptr<Camera> loadExpected(const Sample& s) {
  return loadCamera((formatsDir() / "expected" / (s.expected + ".yaml")).string());
}

TEST(CameraFormats, EachSampleIsRecognisedAsItsFormatAndModel) {
  for (const Sample& s : kSamples) {
    SCOPED_TRACE(describe(s));
    const CameraFile file = readCameraFile((formatsDir() / s.file).string(), {CameraFormat::Auto, s.cameraId});
    EXPECT_EQ(file.format, s.format);
    EXPECT_EQ(file.camera->modelName(), s.model);
  }
}

// The same parameters bit for bit: the YAML the library writes (17 significant digits) is equal.
TEST(CameraFormats, EachSampleHasTheParametersOfItsProjectYaml) {
  for (const Sample& s : kSamples) {
    SCOPED_TRACE(describe(s));
    EXPECT_EQ(cameraToYaml(*loadSample(s)), cameraToYaml(*loadExpected(s)));
    // An explicit format choice reads the same.
    EXPECT_EQ(cameraToYaml(*loadSample(s, s.format)), cameraToYaml(*loadExpected(s)));
  }
}

TEST(CameraFormats, EachSampleProjectsAsItsProjectYamlWithinAMicroPixelOverTheImage) {
  for (const Sample& s : kSamples) {
    SCOPED_TRACE(describe(s));
    const auto camera = loadSample(s);
    const auto expected = loadExpected(s);
    ASSERT_EQ(camera->imageSize(), expected->imageSize());
    const cv::Size size = camera->imageSize();
    const double step = std::max(size.width, size.height) / 96.0;
    int compared = 0;
    double worst = 0.0;
    for (double v = 0; v < size.height; v += step)
      for (double u = 0; u < size.width; u += step) {
        ASSERT_EQ(camera->isValid({u, v}), expected->isValid({u, v})) << u << ", " << v;
        cv::Vec3d ray;
        if (!expected->isValid({u, v}) || !expected->pixelToBearing({u, v}, ray)) continue;
        cv::Point2d a, b;
        ASSERT_TRUE(camera->bearingToPixel(ray, a));
        ASSERT_TRUE(expected->bearingToPixel(ray, b));
        worst = std::max(worst, cv::norm(a - b));
        ++compared;
      }
    EXPECT_GT(compared, 1000);
    EXPECT_LE(worst, 1e-6);
  }
}

// Described at a grid of keypoints over the image (given keypoints: only the full-resolution
// level is built, so the 7-megapixel samples stay quick).
TEST(CameraFormats, EachSampleGivesTheDescriptorsOfItsProjectYamlByteForByte) {
  for (const Sample& s : kSamples) {
    SCOPED_TRACE(describe(s));
    const auto camera = loadSample(s);
    const auto expected = loadExpected(s);
    const cv::Size size = camera->imageSize();
    cv::Mat image(size, CV_8U);
    cv::RNG rng(7);
    rng.fill(image, cv::RNG::UNIFORM, 0, 256);
    cv::GaussianBlur(image, image, cv::Size(0, 0), 2.0);
    std::vector<cv::KeyPoint> grid;
    for (int v = 20; v < size.height - 20; v += size.height / 20)
      for (int u = 20; u < size.width - 20; u += size.width / 20) grid.emplace_back(cv::Point2f(u, v), 31.f);
    std::vector<cv::KeyPoint> k1 = grid, k2 = grid;
    cv::Mat d1, d2, m1, m2;
    MdBrief::create(camera)->detectAndComputeWithMasks(image, cv::noArray(), k1, d1, m1, true);
    MdBrief::create(expected)->detectAndComputeWithMasks(image, cv::noArray(), k2, d2, m2, true);
    ASSERT_GT(k1.size(), 100u);
    ASSERT_EQ(k1.size(), k2.size());
    for (size_t i = 0; i < k1.size(); ++i) {
      ASSERT_EQ(k1[i].pt, k2[i].pt);
      ASSERT_EQ(k1[i].angle, k2[i].angle);
    }
    ASSERT_EQ(d1.size(), d2.size());
    EXPECT_EQ(std::memcmp(d1.data, d2.data, d1.total()), 0);
    EXPECT_EQ(std::memcmp(m1.data, m2.data, m1.total()), 0);
  }
}

// COLMAP's principal point is half a pixel off OpenCV's: checked on the pixel of the optical axis.
TEST(CameraFormats, ColmapPrincipalPointMovesByHalfAPixel) {
  const auto camera = loadCamera((formatsDir() / "colmap_cameras.txt").string(), {CameraFormat::Auto, "5"});
  cv::Point2d axis;
  ASSERT_TRUE(camera->bearingToPixel({0, 0, 1}, axis));
  EXPECT_EQ(axis, cv::Point2d(511.5, 383.5));  // COLMAP: cx, cy = 512, 384
}

// Kimera-VIO's omni camera as its documentation gives the back-projection: (x', y') =
// [1 A0; A1 A2]^-1 ((u, v) - omni_distortion_center), z = a0 + a1 rho + ... (rho = |(x', y')|),
// and the point at depth d is d (x'/z, y'/z, 1). A skewed affine tells each coefficient's place.
// OCamCalib's a0 is negative, so that point lies opposite the pixel across the optical axis;
// the library reads the lens as OCamCalib defines it (a pixel right of the centre sees to the
// right, as the same lens's calib_results.txt gives): Kimera's x and y negated.
TEST(CameraFormats, KimeraOmniBearingsAreKimerasDocumentedBackProjection) {
  const fs::path file = fs::temp_directory_path() / ("mdbrief_kimera_omni_" + std::to_string(::getpid()) + ".yaml");
  const double a[5] = {-209.2, 0.0, 0.0021, -4.2e-06, 1.77e-08};
  const double a0 = 0.05, a1 = -0.03, a2 = 0.97, cu = 380.5, cv = 236.25;
  std::ofstream(file) << "%YAML:1.0\ncamera_id: left_cam\nrate_hz: 20\nresolution: [754, 480]\ncamera_model: omni\n"
                         "intrinsics: [240.0, 240.0, 377.5, 240.5]\ndistortion_model: omni\n"
                         "distortion_coefficients: [-209.2, 0.0, 0.0021, -4.2e-06, 1.77e-08]\n"
                         "omni_distortion_center: [380.5, 236.25]\nomni_affine: [0.05, -0.03, 0.97]\n";
  const auto camera = loadCamera(file.string());
  fs::remove(file);
  const cv::Matx22d affineInverse = cv::Matx22d(1.0, a0, a1, a2).inv();
  int checked = 0;
  for (double v = 20; v < 480; v += 40)
    for (double u = 20; u < 754; u += 40) {
      const cv::Vec2d rectified = affineInverse * cv::Vec2d(u - cu, v - cv);
      const double rho = cv::norm(rectified);
      const double z = a[0] + rho * (a[1] + rho * (a[2] + rho * (a[3] + rho * a[4])));
      if (!(z < 0)) continue;  // Kimera's division by z reaches only the forward half
      const cv::Vec3d kimera = cv::normalize(cv::Vec3d(rectified[0] / z, rectified[1] / z, 1.0));
      const cv::Vec3d lens(-kimera[0], -kimera[1], kimera[2]);
      cv::Vec3d ours;
      ASSERT_TRUE(camera->pixelToBearing({u, v}, ours)) << u << ", " << v;
      EXPECT_LT(cv::norm(cv::normalize(ours) - lens), 1e-9) << u << ", " << v;
      EXPECT_GT(ours[0] * rectified[0], 0.0) << u << ", " << v;  // right of the centre sees to the right
      ++checked;
    }
  EXPECT_GT(checked, 100);
}

class CameraFileErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mdbrief_camera_formats_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The message of loading `file` with `options`, which must fail naming the file.
  static std::string errorOf(const fs::path& file, const CameraFileOptions& options = {}) {
    try {
      loadCamera(file.string(), options);
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file.string(), 0), 0u) << "the message does not start with the file: " << what;
      return what;
    }
    ADD_FAILURE() << file << ": no error";
    return "";
  }

  // Writes `content`, loads it and checks the error names the file and `needle`.
  void expectError(const std::string& name, const std::string& content, const std::string& needle,
                   const CameraFileOptions& options = {}) {
    const fs::path file = dir_ / name;
    std::ofstream(file) << content;
    const std::string what = errorOf(file, options);
    EXPECT_NE(what.find(needle), std::string::npos) << name << ": " << what;
  }

  fs::path dir_;
};

TEST_F(CameraFileErrors, MultiCameraFilesNeedAChoiceAndOneCameraFilesRefuseIt) {
  const auto sample = [](const char* name) { return formatsDir() / name; };
  EXPECT_NE(errorOf(sample("kalibr_camchain.yaml")).find("holds cameras cam0, cam1, cam2, cam3, cam4: choose one"),
            std::string::npos);
  EXPECT_NE(errorOf(sample("basalt_calib.json")).find("holds cameras 0, 1, 2, 3, 4: choose one"), std::string::npos);
  EXPECT_NE(errorOf(sample("orbslam3_kannala_brandt8_stereo.yaml")).find("holds cameras 1, 2"), std::string::npos);
  EXPECT_NE(errorOf(sample("colmap_cameras.txt")).find("holds cameras 1, 2, 3, 4, 5, 6, 7"), std::string::npos);
  // The refusal has its own type, which lists the ids for a caller's own message.
  try {
    loadCamera(sample("basalt_calib.json").string());
    ADD_FAILURE() << "a rig file loaded without an id";
  } catch (const CameraIdRequired& e) {
    EXPECT_EQ(e.ids(), (std::vector<std::string>{"0", "1", "2", "3", "4"}));
  }
  EXPECT_NE(errorOf(sample("kalibr_camchain.yaml"), {CameraFormat::Auto, "cam9"}).find("has no camera 'cam9'"),
            std::string::npos);
  EXPECT_NE(errorOf(sample("colmap_cameras.txt"), {CameraFormat::Auto, "8"}).find("has no camera '8'"),
            std::string::npos);
  EXPECT_NE(errorOf(sample("opencv_fisheye.yaml"), {CameraFormat::Auto, "1"}).find("holds one camera"),
            std::string::npos);
  const fs::path project = mdbrief::testing::sourceDir() / "configs" / "cameras" / "pinhole_example.yaml";
  EXPECT_NE(errorOf(project, {CameraFormat::Auto, "cam0"}).find("holds one camera"), std::string::npos);
}

// Issue 29: of two equal keys the first won without a word, in every format (an appended
// `valid_radius: -5` was ignored, a second `cam0` or COLMAP camera 1 never read). A duplicate is
// refused, naming the key and both lines.
TEST_F(CameraFileErrors, DuplicateKeysAreRefusedNamingTheKeyAndBothLines) {
  const auto text = [](const fs::path& file) { return mdbrief::testing::readFile(file); };
  const fs::path cameras = mdbrief::testing::sourceDir() / "configs" / "cameras";
  const auto inserted = [](std::string s, const std::string& after, const std::string& line) {
    const size_t at = s.find('\n', s.find(after)) + 1;
    return s.insert(at, line);
  };
  const std::string kalibr = text(formatsDir() / "kalibr_camchain.yaml");
  std::string basalt = text(formatsDir() / "basalt_calib.json");
  basalt.replace(basalt.find("\"fx\":"), 5, "\"fx\": 1, \"fx\":");
  expectError("project.yaml", text(cameras / "pinhole_example.yaml") + "fx: 400\n",
              "key 'fx' appears twice, on lines 6 and");
  expectError("ocam.yaml", text(cameras / "lafida_fisheye0.yaml") + "valid_radius: -5\n",
              "key 'valid_radius' appears twice, on lines 16 and");
  expectError("basalt.json", basalt, "key 'fx' appears twice, on lines 14 and 14");
  expectError("opencv.yaml", inserted(text(formatsDir() / "opencv_standard.yaml"), "image_width", "image_width: 320\n"),
              "key 'image_width' appears twice, on lines 5 and 6");
  expectError("kalibr.yaml", inserted(kalibr, "camera_model", "  camera_model: omni\n"),
              "key 'camera_model' appears twice, on lines 8 and 9");
  expectError("kalibr_cam0.yaml", kalibr + kalibr.substr(0, kalibr.find("cam1:")),
              "key 'cam0' appears twice, on lines 1 and");
  const std::string colmap = text(formatsDir() / "colmap_cameras.txt");
  const size_t first = colmap.find("\n1 ") + 1;
  expectError("cameras.txt", colmap + colmap.substr(first, colmap.find('\n', first) - first + 1),
              "CAMERA_ID 1 appears twice, on lines");
}

// Issue 29: COLMAP files with a lower-case model or a negative CAMERA_ID were taken for OCamCalib
// files, one with a byte order mark was unrecognised, and so was a Kalibr file with a merge key.
TEST_F(CameraFileErrors, ColmapLookAlikesAndMergeKeysGetTheirOwnMessages) {
  const std::string colmap = mdbrief::testing::readFile(formatsDir() / "colmap_cameras.txt");
  std::string lower = colmap, negative = colmap;
  lower.replace(lower.find("PINHOLE 1024 768"), 7, "pinhole");
  negative.replace(negative.find("\n1 OPENCV_FISHEYE"), 2, "\n-1");
  expectError("lower.txt", lower, "model pinhole has no camera model here", {CameraFormat::Auto, "5"});
  expectError("lower.txt", lower, "COLMAP's model names are upper case: PINHOLE", {CameraFormat::Auto, "5"});
  expectError("negative.txt", negative, ": CAMERA_ID -1 must be a non-negative integer");
  const fs::path bom = dir_ / "bom.txt";
  std::ofstream(bom) << "\xEF\xBB\xBF" + colmap;
  EXPECT_EQ(readCameraFile(bom.string(), {CameraFormat::Auto, "5"}).format, CameraFormat::Colmap);
  expectError("merge.yaml", "base: &base\n  camera_model: pinhole\ncam0:\n  <<: *base\n  resolution: [752, 480]\n",
              "line 4: YAML merge keys ('<<') are not supported");
}

TEST_F(CameraFileErrors, AnExplicitFormatReadsOnlyThatFormat) {
  const fs::path kalibr = formatsDir() / "kalibr_camchain.yaml";
  EXPECT_NE(errorOf(kalibr, {CameraFormat::Basalt, ""}).find("key 'value0' is missing"), std::string::npos);
  EXPECT_NE(errorOf(kalibr, {CameraFormat::Colmap, "cam0"}).find("is not 'CAMERA_ID MODEL WIDTH HEIGHT"),
            std::string::npos);
  EXPECT_NE(errorOf(formatsDir() / "colmap_cameras.txt", {CameraFormat::Kalibr, "1"}).find("is a YAML map"),
            std::string::npos);
  EXPECT_NE(errorOf(kalibr, {CameraFormat::Mdbrief, ""}).find("key 'model' is missing"), std::string::npos);
}

// Files that resemble a format but are not one of its calibrations are refused, never read as
// another model.
TEST_F(CameraFileErrors, LookAlikesAreRefused) {
  const std::string tried = "none of the formats tried matches (mdbrief: ";
  expectError("no_model.yaml", "width: 10\nheight: 10\n", tried);
  expectError("kalibr_no_model.yaml", "cam0:\n  intrinsics: [1, 2, 3, 4]\n  resolution: [752, 480]\n", tried);
  expectError("kalibr_fov.yaml",
              "cam0:\n  camera_model: pinhole\n  intrinsics: [461, 460, 366, 249]\n  distortion_model: fov\n"
              "  distortion_coeffs: [0.9]\n  resolution: [752, 480]\n",
              "'pinhole' with distortion_model 'fov' has no camera model here");
  expectError("kalibr_ds_radtan.yaml",
              "cam0:\n  camera_model: ds\n  intrinsics: [-0.2, 0.56, 348, 347, 366, 249]\n  distortion_model: radtan\n"
              "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [752, 480]\n",
              "'ds' with distortion_model 'radtan'");
  expectError("kalibr_short_intrinsics.yaml",
              "cam0:\n  camera_model: omni\n  intrinsics: [833, 830, 373, 253]\n  distortion_model: none\n"
              "  resolution: [752, 480]\n",
              "key 'cam0.intrinsics' needs 5 numbers (xi fu fv pu pv), found 4");
  expectError("basalt_fov.json",
              R"({"value0": {"intrinsics": [{"camera_type": "fov", "intrinsics": {"fx": 1, "fy": 1, "cx": 1, "cy": 1, "w": 1}}], "resolution": [[752, 480]]}})",
              "'fov' has no camera model here");
  expectError("basalt_typo.json",
              R"({"value0": {"intrinsics": [{"camera_type": "kb4", "intrinsics": {"fx": 461, "fy": 460, "cx": 366, "cy": 249, "k1": 0, "k2": 0, "k3": 0, "kk4": 0}}], "resolution": [[752, 480]]}})",
              "key 'value0.intrinsics[0].intrinsics.kk4' is not part of the 'basalt kb4' schema");
  expectError("basalt_no_resolution.json",
              R"({"value0": {"intrinsics": [{"camera_type": "ucm", "intrinsics": {"fx": 461, "fy": 460, "cx": 366, "cy": 249, "alpha": 0.6}}], "resolution": []}})",
              "key 'value0.resolution' has 0 entries, none at index 0");
  expectError("orbslam2.yaml", "%YAML:1.0\nCamera.fx: 458.654\nCamera.fy: 457.296\nCamera.cx: 367.215\n", tried);
  expectError("orbslam3_unknown_type.yaml", "%YAML:1.0\nCamera.type: \"Fisheye\"\nCamera.fx: 458\n",
              "'Fisheye' is not one of: PinHole, KannalaBrandt8, Rectified");
  expectError("orbslam3_kb_missing_k4.yaml",
              "%YAML:1.0\nCamera.type: \"KannalaBrandt8\"\nCamera.fx: 190\nCamera.fy: 190\nCamera.cx: 254\n"
              "Camera.cy: 256\nCamera.k1: 0\nCamera.k2: 0\nCamera.k3: 0\nCamera.width: 512\nCamera.height: 512\n",
              "key 'Camera.k4' is missing");
  const std::string k = "camera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: [461, 0, 366, 0, 460, 249, 0, 0, 1]\n"
                        "image_width: 752\nimage_height: 480\n";
  const std::string d4 = "distortion_coefficients: !!opencv-matrix\n  rows: 4\n  cols: 1\n  dt: d\n  data: [0.01, 0.02, 0.001, 0.002]\n";
  expectError("opencv_ambiguous.yaml", "%YAML:1.0\n---\n" + k + d4, "add fisheye_model: 1 or 0");
  expectError("opencv_no_distortion.yaml", "%YAML:1.0\n---\n" + k, "key 'distortion_coefficients' is missing");
  expectError("opencv_skew.yaml",
              "%YAML:1.0\n---\nfisheye_model: 1\n" + std::string(k).replace(k.find("461, 0"), 6, "461, 2") + d4,
              "K[0][1] = 2 is a skew");
  expectError("opencv_thin_prism.yaml",
              "%YAML:1.0\n---\n" + k +
                  "distortion_coefficients: !!opencv-matrix\n  rows: 1\n  cols: 12\n  dt: d\n"
                  "  data: [0.01, 0.02, 0, 0, 0, 0, 0, 0, 0.001, 0, 0, 0]\n",
              "D[8] = 0.001 is a thin-prism or tilted-sensor term");
  expectError("opencv_fisheye_five.yaml", "%YAML:1.0\n---\nfisheye_model: 1\n" + k +
                  "distortion_coefficients: !!opencv-matrix\n  rows: 5\n  cols: 1\n  dt: d\n  data: [0, 0, 0, 0, 0]\n",
              "cv::fisheye needs 4 coefficients");
  const std::string sensor = "sensor_type: camera\nresolution: [752, 480]\ncamera_model: pinhole\n"
                             "intrinsics: [461, 460, 366, 249]\n";
  expectError("euroc_no_distortion.yaml", sensor + "distortion_coefficients: [0, 0, 0, 0]\n",
              "key 'distortion_model' is missing (one of: radtan, radial-tangential, plumb_bob, equidistant, none");
  expectError("euroc_fov.yaml", sensor + "distortion_model: fov\ndistortion_coefficients: [0.9]\n",
              "key 'distortion_model' names an unknown model 'fov'");
  expectError("euroc_equidistant_three.yaml", sensor + "distortion_model: equidistant\ndistortion_coefficients: [0, 0, 0]\n",
              "key 'distortion_coefficients' needs 4 numbers (k1 k2 k3 k4), found 3");
  expectError("euroc_imu.yaml", "sensor_type: imu\nrate_hz: 200\n", "key 'sensor_type' is 'imu', not camera");
  expectError("euroc_unknown_camera.yaml",
              "camera_model: fisheye\nresolution: [752, 480]\ndistortion_model: none\nintrinsics: [461, 460, 366, 249]\n",
              "key 'camera_model' names an unknown model 'fisheye' (known: pinhole, omni, ds, eucm)");
  expectError("kimera_omni_no_centre.yaml",
              "camera_model: omni\nresolution: [754, 480]\ndistortion_model: omni\n"
              "distortion_coefficients: [-209, 0, 0.002, -4e-06, 1.8e-08]\nomni_affine: [0, 0, 1]\n",
              "key 'omni_distortion_center' is missing");
  expectError("kd_no_size.yaml",
              "%YAML:1.0\n---\nK: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: [461, 0, 366, 0, 460, 249, 0, 0, 1]\n"
              "D: !!opencv-matrix\n  rows: 1\n  cols: 5\n  dt: d\n  data: [0.01, 0.02, 0.001, 0.002, 0]\n",
              "holds no image size (keys image_width and image_height, width and height, or image_size): give it "
              "(mdbrief --camera-size WxH; Python image_size=(w, h)");
  expectError("colmap_fov.txt", "# Camera list\n1 FOV 752 480 461 460 366 249 0.9\n",
              "model FOV has no camera model here (supported: SIMPLE_PINHOLE");
  expectError("colmap_short.txt", "1 OPENCV_FISHEYE 752 480 461 460 366 249 0.01 0.02\n",
              "OPENCV_FISHEYE needs 8 parameters (fx fy cx cy k1 k2 k3 k4), found 6");
  expectError("colmap_bad_line.txt", "1 PINHOLE 752 480 461 460 366 249\nsome words here\n",
              "line 2 is not 'CAMERA_ID MODEL WIDTH HEIGHT PARAMS...'", {CameraFormat::Auto, "1"});
  // An OCamCalib-looking file (numbers only) is not taken for COLMAP, nor COLMAP for OCamCalib.
  expectError("ocam_like_colmap.txt", "1 2 752 480 461 460 366 249\n", "OCamCalib calib_results.txt needs 5 lines");
}

// Every line-boundary truncation of every sample either gives exactly the sample's camera or an
// error naming the file: a truncated calibration is never read as another camera.
TEST_F(CameraFileErrors, TruncatedSamplesGiveTheSameCameraOrAnError) {
  for (const Sample& s : kSamples) {
    SCOPED_TRACE(describe(s));
    std::ifstream in(formatsDir() / s.file, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string expected = cameraToYaml(*loadExpected(s));
    int refused = 0;
    for (std::size_t end = text.find('\n'); end != std::string::npos && end + 1 < text.size();
         end = text.find('\n', end + 1)) {
      const fs::path file = dir_ / ("truncated_" + std::to_string(end) + "_" + s.file);
      std::ofstream(file, std::ios::binary) << text.substr(0, end + 1);
      try {
        EXPECT_EQ(cameraToYaml(*loadCamera(file.string(), {s.format, s.cameraId})), expected) << "cut at " << end;
      } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(file.string(), 0), 0u) << e.what();
        ++refused;
      }
    }
    EXPECT_GT(refused, 0);
  }
}

// The bad files kept as fuzzing seeds: a truncated file and a look-alike of every format, each
// refused naming the file and the problem. (The samples themselves are seeds too.)
TEST(CameraFormatSeeds, TruncatedAndLookAlikeSeedsAreRefusedNamingTheProblem) {
  const std::map<std::string, std::string> needles = {
      {"truncated_kalibr_camchain.yaml", "key 'cam0.resolution' is missing"},
      {"truncated_basalt_calib.json", "unparsable camera file (YAML: "},
      {"truncated_orbslam3_pinhole.yaml", "key 'Camera.width' is missing"},
      {"truncated_opencv_fisheye.yaml", "unparsable camera file (YAML: "},
      {"truncated_colmap_cameras.txt", "OPENCV_FISHEYE needs 8 parameters"},
      {"truncated_euroc_cam0_sensor.yaml", "key 'distortion_model' is missing"},
      {"lookalike_euroc_fov.yaml", "key 'distortion_model' names an unknown model 'fov'"},
      {"lookalike_opencv_kd_no_size.yaml", "holds no image size"},
      {"truncated_ocam_minimal.txt", "needs 5 lines of numbers"},
      {"lookalike_kalibr_fov.yaml", "distortion_model 'fov' has no camera model here"},
      {"lookalike_basalt_fov.json", "'fov' has no camera model here"},
      {"lookalike_orbslam2.yaml", "none of the formats tried matches"},
      {"lookalike_opencv_four_coefficients.yaml", "add fisheye_model: 1 or 0"},
      {"lookalike_colmap_thin_prism.txt", "model THIN_PRISM_FISHEYE has no camera model here"},
  };
  for (const auto& [name, needle] : needles) {
    const fs::path file = seedsDir() / name;
    SCOPED_TRACE(name);
    ASSERT_TRUE(fs::exists(file));
    try {
      loadCamera(file.string());
      ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file.string(), 0), 0u) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  }
  for (const auto& entry : fs::directory_iterator(seedsDir())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("truncated_", 0) == 0 || name.rfind("lookalike_", 0) == 0) {
      EXPECT_TRUE(needles.count(name)) << name << " is a bad seed this test does not check";
    }
  }
}

TEST(CameraFormatSeeds, EverySampleIsAFuzzingSeed) {
  for (const auto& entry : fs::directory_iterator(formatsDir())) {
    if (!entry.is_regular_file()) continue;
    const fs::path seed = seedsDir() / entry.path().filename();
    ASSERT_TRUE(fs::exists(seed)) << seed;
    std::ifstream a(entry.path(), std::ios::binary), b(seed, std::ios::binary);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}), std::string(std::istreambuf_iterator<char>(b), {}))
        << seed << " differs from the sample";
  }
}

// What the library builds from parameters (Python's Camera(model, ...)) is what the file gives.
TEST(CameraParameters, MakeCameraFromTheParametersGivesTheSameCamera) {
  for (const Sample& s : kSamples) {
    SCOPED_TRACE(describe(s));
    const auto camera = loadSample(s);
    const auto made = makeCamera(camera->modelName(), camera->imageSize(), cameraParameters(*camera));
    EXPECT_EQ(cameraToYaml(*made), cameraToYaml(*camera));
  }
  try {
    makeCamera("kannala_brandt", {752, 480}, {{"fx", 461.0}, {"fy", 460.0}, {"cx", 366.0}, {"cy", 249.0}}, "Camera",
               "keyword");
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "Camera: keyword 'k1' is missing");
  }
  EXPECT_THROW(makeCamera("pinhole", {0, 480}, {{"fx", 1.0}, {"fy", 1.0}, {"cx", 0.0}, {"cy", 0.0}}),
               std::runtime_error);
  EXPECT_EQ(cameraModelKeys("omni"), (std::vector<std::string>{"cx", "cy", "fx", "fy", "k1", "k2", "p1", "p2", "xi"}));
}

// K and D as cv::fisheye and cv::calibrateCamera return them: the projections are OpenCV's own.
TEST(CameraParameters, OpenCvResultsProjectAsOpenCvDoes) {
  const cv::Matx33d K(461.5, 0, 366.3, 0, 460.2, 249.1, 0, 0, 1);
  const std::vector<double> fisheyeD = {-0.0125, 0.0578, -0.085, 0.0436};
  const std::vector<double> rationalD = {0.208, -1.02, -5.8e-4, -3.4e-3, 1.40, 0.0936, -0.831, 1.18};
  const auto fisheye = cameraFromOpenCv(K, fisheyeD, {752, 480}, true);
  const auto standard = cameraFromOpenCv(K, rationalD, {752, 480}, false);
  std::vector<cv::Point3d> rays;
  for (double x = -0.6; x <= 0.6; x += 0.1)
    for (double y = -0.4; y <= 0.4; y += 0.1) rays.emplace_back(x, y, 1.0);
  std::vector<cv::Point2d> viaFisheye, viaStandard;
  cv::fisheye::projectPoints(rays, viaFisheye, cv::Vec3d::all(0), cv::Vec3d::all(0), K, fisheyeD);
  cv::projectPoints(rays, cv::Vec3d::all(0), cv::Vec3d::all(0), K, rationalD, viaStandard);
  for (size_t i = 0; i < rays.size(); ++i) {
    cv::Point2d a, b;
    ASSERT_TRUE(fisheye->bearingToPixel(cv::Vec3d(rays[i].x, rays[i].y, rays[i].z), a));
    ASSERT_TRUE(standard->bearingToPixel(cv::Vec3d(rays[i].x, rays[i].y, rays[i].z), b));
    EXPECT_LT(cv::norm(a - viaFisheye[i]), 1e-6) << rays[i];
    EXPECT_LT(cv::norm(b - viaStandard[i]), 1e-6) << rays[i];
  }
}

// cv2.fisheye users save K and D alone: the size and, for four coefficients, the model come from
// the caller when the file does not hold them; a file that does must agree.
TEST_F(CameraFileErrors, OpenCvKdTakesTheSizeAndModelFromTheCaller) {
  const std::string kd = (formatsDir() / "opencv_kd_fisheye.yaml").string();
  CameraFileOptions options;
  options.imageSize = cv::Size(752, 480);
  EXPECT_NE(errorOf(kd, options).find("has 4 coefficients, which are cv::fisheye's k1 k2 k3 k4 or "
                                      "cv::calibrateCamera's k1 k2 p1 p2"),
            std::string::npos);
  EXPECT_NE(errorOf(kd, options).find("--camera-opencv-model fisheye|standard; Python opencv_model="),
            std::string::npos);
  options.opencvModel = OpenCvModel::Fisheye;
  const CameraFile file = readCameraFile(kd, options);
  EXPECT_EQ(file.format, CameraFormat::OpenCvKd);
  EXPECT_EQ(cameraToYaml(*file.camera), cameraToYaml(*loadCamera((formatsDir() / "expected/opencv_fisheye.yaml").string())));
  options.opencvModel = OpenCvModel::Standard;
  EXPECT_EQ(readCameraFile(kd, options).camera->modelName(), "radtan");
  options.imageSize.reset();
  EXPECT_NE(errorOf(kd, options).find("holds no image size"), std::string::npos);

  // A file with its own size: the caller's must be the same.
  const std::string standard = (formatsDir() / "opencv_kd_standard.yaml").string();
  CameraFileOptions other;
  other.imageSize = cv::Size(1280, 960);
  EXPECT_NE(errorOf(standard, other).find("key 'image_size' gives the size 640x480, the size given is 1280x960"),
            std::string::npos);
  other.imageSize = cv::Size(640, 480);
  EXPECT_EQ(readCameraFile(standard, other).camera->imageSize(), cv::Size(640, 480));

  // The samples' format too: four coefficients without fisheye_model, the caller says which.
  const fs::path lookalike = seedsDir() / "lookalike_opencv_four_coefficients.yaml";
  CameraFileOptions fisheye;
  fisheye.opencvModel = OpenCvModel::Fisheye;
  EXPECT_EQ(loadCamera(lookalike.string(), fisheye)->modelName(), "kannala_brandt");
  // A file that says fisheye_model: 1 is not read as the standard model.
  CameraFileOptions contrary;
  contrary.opencvModel = OpenCvModel::Standard;
  EXPECT_NE(errorOf(formatsDir() / "opencv_fisheye.yaml", contrary)
                .find("key 'fisheye_model' says fisheye, the OpenCV model chosen is standard"),
            std::string::npos);
}

// The refusal of an unknown file says what chooses a format, on the command line and in Python.
TEST_F(CameraFileErrors, UnrecognisedFilesNameTheFlagAndKeywordThatChooseAFormat) {
  expectError("unknown.yaml", "a: 1\n", "choose the format (mdbrief --camera-format NAME");
  expectError("unknown.yaml", "a: 1\n", "Python format=\"NAME\"");
  expectError("unknown.yaml", "a: 1\n", "euroc: EuRoC / Kimera sensor.yaml");
  expectError("unknown.yaml", "a: 1\n", "opencv-kd: OpenCV FileStorage with 'K' and 'D'");
}

}  // namespace
