// Camera rigs (camera/rig.hpp): every camera of a multi-camera file or of a list of EuRoC
// sensor.yaml files, the extrinsics each format gives (Kalibr's T_cn_cnm1 chain and T_cam_imu,
// basalt's T_imu_cam quaternions, ORB-SLAM3's Tlr, EuRoC's T_BS), relativePose's convention
// (x_i = R x_j + t), and clear errors for cameras without extrinsics.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <opencv2/calib3d.hpp>

#include "mdbrief/camera/rig.hpp"
#include "test_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace mdbrief;

fs::path formatsDir() { return mdbrief::testing::sourceDir() / "tests" / "data" / "camera_formats"; }
std::string sample(const char* name) { return (formatsDir() / name).string(); }

void expectNear(const RigidTransform& a, const RigidTransform& b, double tolerance) {
  EXPECT_LE(cv::norm(a.rotation - b.rotation, cv::NORM_INF), tolerance) << a.rotation << " vs " << b.rotation;
  EXPECT_LE(cv::norm(a.translation - b.translation, cv::NORM_INF), tolerance) << a.translation << " vs "
                                                                               << b.translation;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(CameraRig, RigidTransformComposesAndInverts) {
  cv::Vec3d axis(0.3, -0.2, 0.9);
  cv::Matx33d r;
  cv::Rodrigues(axis, r);
  const RigidTransform a{r, {0.1, -0.2, 0.3}};
  const RigidTransform b{r.t(), {-1.0, 0.5, 2.0}};
  const cv::Vec3d x(0.4, 0.5, 1.5);
  EXPECT_LE(cv::norm((a * b).apply(x) - a.apply(b.apply(x))), 1e-12);
  EXPECT_LE(cv::norm(a.inverse().apply(a.apply(x)) - x), 1e-12);
}

// camchain: cam1's T_cn_cnm1 maps cam0's points into cam1's, so relativePose(cam1, cam0) is it.
TEST(CameraRig, KalibrChainGivesTheRelativePoseOfConsecutiveCameras) {
  const CameraRig rig = readCameraRig(sample("kalibr_camchain.yaml"));
  EXPECT_EQ(rig.format(), CameraFormat::Kalibr);
  ASSERT_EQ(rig.size(), 5u);
  EXPECT_EQ(rig.at(0).id, "cam0");
  EXPECT_EQ(rig.at(4).id, "cam4");
  EXPECT_EQ(rig.at(1).camera->modelName(), "omni");
  const RigidTransform written{{0.999997256477797, 0.002317135723275, 0.000343393120620,  //
                                -0.002312067192432, 0.999898048507103, -0.014090668452683,  //
                                -0.000376008102320, 0.014089835846691, 0.999900662638081},
                               {-0.110074137800478, 0.000399121547014, -0.000853702503357}};
  expectNear(rig.relativePose("cam1", "cam0"), written, 1e-9);
  expectNear(rig.relativePose(0, 1), written.inverse(), 1e-9);
  // cam1's centre seen from cam0: 11 cm to the right (x).
  EXPECT_NEAR(rig.relativePose(0, 1).translation[0], 0.110, 1e-3);
  expectNear(rig.relativePose(2, 2), RigidTransform{}, 0.0);
  EXPECT_TRUE(rig.hasRelativePose(0, 1));
  EXPECT_FALSE(rig.hasRelativePose(0, 2));
  const std::string what = errorOf([&] { rig.relativePose("cam0", "cam2"); });
  EXPECT_NE(what.find(sample("kalibr_camchain.yaml") + ": camera 'cam2' has no extrinsics (a Kalibr camchain keeps "
                                                       "them in T_cn_cnm1 or T_cam_imu)"),
            std::string::npos)
      << what;
  EXPECT_NE(errorOf([&] { rig.index("cam9"); }).find("no camera 'cam9' (it has 'cam0', 'cam1'"), std::string::npos);
  EXPECT_THROW(rig.at(5), std::out_of_range);
}

// Without the chain, two cameras are placed through their T_cam_imu.
TEST(CameraRig, KalibrCamerasWithoutTheChainArePlacedThroughTheImu) {
  const fs::path file = fs::temp_directory_path() / ("mdbrief_rig_imu_" + std::to_string(::getpid()) + ".yaml");
  const std::string camera = "  camera_model: pinhole\n  distortion_model: none\n  distortion_coeffs: []\n"
                             "  intrinsics: [461, 460, 366, 249]\n  resolution: [752, 480]\n";
  std::ofstream(file) << "cam0:\n  T_cam_imu:\n  - [0, -1, 0, 0.1]\n  - [1, 0, 0, 0.2]\n  - [0, 0, 1, 0.3]\n"
                         "  - [0, 0, 0, 1]\n" + camera +
                             "cam1:\n  T_cam_imu:\n  - [0, -1, 0, 0.0]\n  - [1, 0, 0, 0.2]\n  - [0, 0, 1, 0.3]\n"
                             "  - [0, 0, 0, 1]\n" + camera;
  const CameraRig rig = readCameraRig(file.string());
  // x_c0 = T_c0_imu x_imu, x_c1 = T_c1_imu x_imu: x_c0 = x_c1 + (0.1, 0, 0).
  expectNear(rig.relativePose(0, 1), RigidTransform{cv::Matx33d::eye(), {0.1, 0.0, 0.0}}, 1e-12);
  fs::remove(file);
}

// basalt's T_imu_cam maps each camera's points into the IMU's.
TEST(CameraRig, BasaltQuaternionsGiveTheRelativePose) {
  const CameraRig rig = readCameraRig(sample("basalt_calib.json"));
  EXPECT_EQ(rig.format(), CameraFormat::Basalt);
  ASSERT_EQ(rig.size(), 5u);
  EXPECT_EQ(rig.at(3).id, "3");
  // The rotation of a unit quaternion, through its axis and angle (another route than the reader's).
  const auto pose = [](double px, double py, double pz, double qx, double qy, double qz, double qw) {
    const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
    const double angle = 2.0 * std::acos(qw / norm);
    const cv::Vec3d axis = cv::Vec3d(qx, qy, qz) / (norm * std::sin(angle / 2.0));
    cv::Matx33d r;
    cv::Rodrigues(axis * angle, r);
    return RigidTransform{r, {px, py, pz}};
  };
  const RigidTransform imuCam0 = pose(-0.016940, -0.066958, 0.005417, -0.007707, 0.010499, 0.701752, 0.712299);
  const RigidTransform imuCam1 = pose(-0.016940, 0.043050, 0.005417, -0.002553, 0.015245, 0.702685, 0.711333);
  expectNear(rig.relativePose(0, 1), imuCam0.inverse() * imuCam1, 1e-9);
  // The baseline is 11 cm.
  EXPECT_NEAR(cv::norm(rig.relativePose(0, 1).translation), 0.110, 1e-3);
}

// ORB-SLAM3's Tlr maps the right camera's points into the left's.
TEST(CameraRig, OrbSlam3TlrIsTheRightCamerasPoseInTheLeft) {
  const CameraRig rig = readCameraRig(sample("orbslam3_kannala_brandt8_stereo.yaml"));
  ASSERT_EQ(rig.size(), 2u);
  expectNear(rig.relativePose("1", "2"), RigidTransform{cv::Matx33d::eye(), {0.101, 0.0, 0.0}}, 1e-12);
  // A file with one camera has no other to relate it to, but itself.
  const CameraRig mono = readCameraRig(sample("orbslam3_pinhole.yaml"));
  ASSERT_EQ(mono.size(), 1u);
  expectNear(mono.relativePose(0, 0), RigidTransform{}, 0.0);
}

// EuRoC's cam0/sensor.yaml and cam1/sensor.yaml: both T_BS map into the same body frame.
TEST(CameraRig, EurocPairThroughTheirBodyFrame) {
  const CameraRig rig = readCameraRig(std::vector<std::string>{sample("euroc_cam0_sensor.yaml"),
                                                               sample("euroc_cam1_sensor.yaml")});
  EXPECT_EQ(rig.format(), CameraFormat::Euroc);
  ASSERT_EQ(rig.size(), 2u);
  // Each camera named by its file's stem (no ASL folder here).
  EXPECT_EQ(rig.at(0).id, "euroc_cam0_sensor");
  EXPECT_EQ(rig.at(1).id, "euroc_cam1_sensor");
  EXPECT_EQ(rig.at(0).camera->modelName(), "kannala_brandt");
  EXPECT_EQ(rig.at(1).camera->modelName(), "radtan");
  // Same orientation; the body's +y (camera x) offset of 11 cm: the right camera at +x.
  expectNear(rig.relativePose(0, 1), RigidTransform{cv::Matx33d::eye(), {0.11, 0.0, 0.0}}, 1e-12);
  expectNear(rig.relativePose("euroc_cam1_sensor", "euroc_cam0_sensor"),
             RigidTransform{cv::Matx33d::eye(), {-0.11, 0.0, 0.0}}, 1e-12);
  // A bearing of camera 1 is R b seen from camera 0; a point's coordinates move by t.
  const cv::Vec3d point1(0.5, -0.2, 3.0);
  EXPECT_LE(cv::norm(rig.relativePose(0, 1).apply(point1) - cv::Vec3d(0.61, -0.2, 3.0)), 1e-12);
  // One sensor.yaml alone is a rig of one camera placed in its body.
  const CameraRig one = readCameraRig(sample("euroc_cam0_sensor.yaml"));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one.at(0).id, "");
  ASSERT_TRUE(one.at(0).cameraToRig.has_value());
  EXPECT_EQ(one.at(0).cameraToRig->translation, cv::Vec3d(-0.02, -0.06, 0.01));
}

TEST(CameraRig, FilesWithoutExtrinsicsAndBadRigsAreRefusedClearly) {
  // A file of another format in a rig of files has no place in the body frame.
  const CameraRig mixed = readCameraRig(std::vector<std::string>{sample("euroc_cam0_sensor.yaml"),
                                                                 sample("opencv_standard.yaml")});
  const std::string what = errorOf([&] { mixed.relativePose(0, 1); });
  EXPECT_NE(what.find(": camera 'opencv_standard' has no extrinsics"), std::string::npos)
      << what;
  // COLMAP's cameras.txt holds intrinsics only.
  const CameraRig colmap = readCameraRig(sample("colmap_cameras.txt"));
  EXPECT_EQ(colmap.size(), 7u);
  EXPECT_NE(errorOf([&] { colmap.relativePose("1", "2"); }).find("a colmap file has none"), std::string::npos);
  EXPECT_NE(errorOf([&] { readCameraRig(std::vector<std::string>{sample("kalibr_camchain.yaml")}); })
                .find("holds 5 cameras; a rig of files takes one camera per file"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { readCameraRig(sample("kalibr_camchain.yaml"), {CameraFormat::Auto, "cam0"}); })
                .find("the camera choice 'cam0' does not apply"),
            std::string::npos);
  EXPECT_THROW(readCameraRig(std::vector<std::string>{}), std::invalid_argument);
  EXPECT_NE(errorOf([&] {
              readCameraRig(std::vector<std::string>{sample("euroc_cam0_sensor.yaml"), sample("euroc_cam0_sensor.yaml")});
            }).find("given twice"),
            std::string::npos);
  // The same file under another name (issue 45: the identity pose came back).
  const std::string other = (fs::path(sample("euroc_cam0_sensor.yaml")).parent_path() / "." / "euroc_cam0_sensor.yaml").string();
  EXPECT_NE(errorOf([&] { readCameraRig(std::vector<std::string>{sample("euroc_cam0_sensor.yaml"), other}); })
                .find("the same file as"),
            std::string::npos);
}

// Issue 45: translations of +-1e308 gave t = [-inf, 0, 0] with no error.
TEST(CameraRig, APoseThatOverflowsIsRefused) {
  const fs::path dir = fs::temp_directory_path() / ("mdbrief_rig_far_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string head = "sensor_type: camera\nresolution: [752, 480]\ncamera_model: pinhole\n"
                           "intrinsics: [461, 460, 366, 249]\ndistortion_model: none\n";
  for (const auto& [name, x] : {std::pair{"near.yaml", "-1e308"}, std::pair{"far.yaml", "1e308"}})
    std::ofstream(dir / name) << head << "T_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, " << x
                              << ", 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n";
  const CameraRig rig = readCameraRig(std::vector<std::string>{(dir / "near.yaml").string(), (dir / "far.yaml").string()});
  EXPECT_NE(errorOf([&] { rig.relativePose("near", "far"); }).find("is not finite"), std::string::npos);
  fs::remove_all(dir);
}

// EuRoC's ASL layout names each camera by its folder (cam0/sensor.yaml -> "cam0"), the ids a
// user types; two files that would share an id keep their paths instead.
TEST(CameraRig, AslFoldersNameTheirCameras) {
  const fs::path dir = fs::temp_directory_path() / ("mdbrief_rig_asl_" + std::to_string(::getpid()));
  for (const char* name : {"cam0", "cam1", "other/cam0"}) {
    fs::create_directories(dir / name);
    fs::copy_file(sample("euroc_cam0_sensor.yaml"), dir / name / "sensor.yaml", fs::copy_options::overwrite_existing);
  }
  const CameraRig rig =
      readCameraRig(std::vector<std::string>{(dir / "cam0/sensor.yaml").string(), (dir / "cam1/sensor.yaml").string()});
  EXPECT_EQ(rig.at(0).id, "cam0");
  EXPECT_EQ(rig.at(1).id, "cam1");
  EXPECT_EQ(rig.index("cam1"), 1u);
  const std::vector<std::string> clash{(dir / "cam0/sensor.yaml").string(), (dir / "other/cam0/sensor.yaml").string()};
  const CameraRig both = readCameraRig(clash);
  EXPECT_EQ(both.at(0).id, clash[0]);
  EXPECT_EQ(both.at(1).id, clash[1]);
  fs::remove_all(dir);
}

TEST(CameraRig, BadExtrinsicsAreRefusedNamingTheKey) {
  const fs::path file = fs::temp_directory_path() / ("mdbrief_rig_bad_" + std::to_string(::getpid()) + ".yaml");
  const std::string head = "sensor_type: camera\nresolution: [752, 480]\ncamera_model: pinhole\n"
                           "intrinsics: [461, 460, 366, 249]\ndistortion_model: none\n";
  const auto error = [&](const std::string& tbs) {
    std::ofstream(file) << head << "T_BS:\n  cols: 4\n  rows: 4\n  data: " << tbs << "\n";
    return errorOf([&] { readCameraRig(file.string()); });
  };
  EXPECT_NE(error("[2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]").find("key 'T_BS' has no rotation"),
            std::string::npos);
  EXPECT_NE(error("[-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]").find("key 'T_BS' has no rotation"),
            std::string::npos);  // a reflection
  EXPECT_NE(error("[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1]").find("key 'T_BS' must end with the row 0 0 0 1"),
            std::string::npos);
  EXPECT_NE(error("[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]").find("key 'T_BS.data' needs 16 numbers"),
            std::string::npos);
  std::ofstream(file) << head << "T_BS:\n  cols: 3\n  rows: 4\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]\n";
  EXPECT_NE(errorOf([&] { readCameraRig(file.string()); }).find("key 'T_BS' must be 4 x 4"), std::string::npos);
  fs::remove(file);
}

}  // namespace
