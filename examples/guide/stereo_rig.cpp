// The user guide's rig walk-through (docs/guide/README.md "Rigs and SLAM calibration files"):
// read a stereo rig's Kalibr camchain, take its cameras and the relative pose between them, and
// check matches against that pose. ctest `guide_stereo_rig` runs it on points seen by both
// cameras (their true matches, and as many shuffled ones) and checks the labels.
// Usage: guide_stereo_rig WORK_DIR
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <mdbrief/mdbrief.hpp>

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "guide_stereo_rig: %s\n", what.c_str());
  return 1;
}

// A camchain as Kalibr writes it: two equidistant fisheye cameras, cam1 11 cm right of cam0.
void writeCamchain(const std::string& path) {
  const std::string camera =
      "  camera_model: pinhole\n  distortion_model: equidistant\n"
      "  distortion_coeffs: [-0.0125, 0.0578, -0.0850, 0.0436]\n"
      "  intrinsics: [461.6, 460.3, 366.3, 249.1]\n  resolution: [752, 480]\n";
  std::ofstream(path) << "cam0:\n" << camera << "  rostopic: /cam0/image_raw\ncam1:\n  T_cn_cnm1:\n"
                      << "  - [1.0, 0.0, 0.0, -0.11]\n  - [0.0, 1.0, 0.0, 0.0]\n"
                      << "  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n"
                      << camera << "  rostopic: /cam1/image_raw\n";
}

// The same rig in EuRoC's ASL layout: DIR/cam0/sensor.yaml and DIR/cam1/sensor.yaml, each
// camera's pose in the body frame (T_BS), cam1 11 cm to cam0's right.
void writeAslSensors(const std::string& dir) {
  const std::string camera =
      "camera_model: pinhole\nintrinsics: [461.6, 460.3, 366.3, 249.1]\nresolution: [752, 480]\n"
      "distortion_model: equidistant\ndistortion_coefficients: [-0.0125, 0.0578, -0.0850, 0.0436]\n";
  for (const auto& [name, x] : {std::pair{"cam0", "0.0"}, std::pair{"cam1", "0.11"}}) {
    std::filesystem::create_directories(dir + "/" + name);
    std::ofstream(dir + "/" + name + "/sensor.yaml")
        << "sensor_type: camera\nT_BS:\n  cols: 4\n  rows: 4\n  data: [1.0, 0.0, 0.0, " << x
        << ", 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]\nrate_hz: 20\n" << camera;
  }
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 2) return fail("usage: guide_stereo_rig WORK_DIR");
  const std::string camchainPath = std::string(argv[1]) + "/camchain.yaml";
  writeCamchain(camchainPath);

  const std::string asl = argv[1];
  writeAslSensors(asl);

  // [guide:rig]
  // Every camera of a rig file (Kalibr camchain, basalt calib.json, ORB-SLAM3 stereo settings).
  const mdbrief::CameraRig rig = mdbrief::readCameraRig(camchainPath);
  const std::shared_ptr<mdbrief::Camera> left = rig.at(rig.index("cam0")).camera;
  const std::shared_ptr<mdbrief::Camera> right = rig.at(rig.index("cam1")).camera;
  // x_cam0 = R x_cam1 + t: cam1's pose in cam0's frame, as the two-view geometry's RelativePose.
  const mdbrief::RelativePose pose = rig.relativePose("cam0", "cam1");
  // EuRoC's sensor.yaml files, one per camera folder: each camera is named by its folder.
  const mdbrief::CameraRig euroc = mdbrief::readCameraRig({asl + "/cam0/sensor.yaml", asl + "/cam1/sensor.yaml"});
  const mdbrief::RelativePose eurocPose = euroc.relativePose("cam0", "cam1");
  // ... match left and right images, take the matches' bearings (pixelToBearing), then:
  //   mdbrief::TwoViewResult labels = mdbrief::checkKnownPose(bearingsLeft, bearingsRight, pose);
  // [guide]
  if (cv::norm(eurocPose.translation - pose.translation) > 1e-12 || cv::norm(eurocPose.rotation - pose.rotation) > 1e-12)
    return fail("the ASL layout's pose differs from the camchain's");

  // Points 1-5 m in front of the rig, seen by both cameras: true matches, then shuffled ones.
  std::vector<cv::Vec3d> bearingsLeft, bearingsRight;
  cv::RNG rng(3);
  const cv::Matx33d toRight = pose.rotation.t();
  while (bearingsLeft.size() < 200) {
    const cv::Vec3d point(rng.uniform(-2.0, 2.0), rng.uniform(-1.5, 1.5), rng.uniform(1.0, 5.0));  // cam0 frame
    const cv::Vec3d inRight = toRight * (point - pose.translation);
    cv::Point2d pixelLeft, pixelRight;
    if (!left->bearingToPixel(point, pixelLeft) || !right->bearingToPixel(inRight, pixelRight)) continue;
    cv::Vec3d a, b;
    if (!left->pixelToBearing(pixelLeft, a) || !right->pixelToBearing(pixelRight, b)) continue;
    bearingsLeft.push_back(a), bearingsRight.push_back(b);
  }
  for (size_t i = 0; i < 200; ++i) bearingsLeft.push_back(bearingsLeft[i]), bearingsRight.push_back(bearingsRight[(i + 7) % 200]);
  const mdbrief::TwoViewResult labels = mdbrief::checkKnownPose(bearingsLeft, bearingsRight, pose);
  int right200 = 0, wrongShuffled = 0;
  for (size_t i = 0; i < 200; ++i) right200 += labels.inliers[i], wrongShuffled += !labels.inliers[200 + i];
  std::printf("rig of %zu cameras, baseline %.3f m: %d of 200 true matches right, %d of 200 shuffled ones wrong\n",
              rig.size(), cv::norm(pose.translation), right200, wrongShuffled);
  if (right200 != 200) return fail("a true match was labelled wrong");
  if (wrongShuffled < 190) return fail("fewer than 190 of 200 shuffled matches labelled wrong");
  return 0;
} catch (const std::exception& e) {
  return fail(e.what());
}
