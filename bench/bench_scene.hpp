#pragma once
// The benches' fisheye frames: Graffiti (opencv-doc) as a plane seen through the paper's
// OCamCalib camera (configs/cameras/lafida_fisheye0.yaml), 754x480.
#include <benchmark/benchmark.h>

#include "mdbrief/camera/io.hpp"
#include "toolkit/data_folders.hpp"
#include "toolkit/image_file.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief::bench {

struct FisheyeScene {
  CameraPtr camera;
  PlaneScene plane;  // texture empty when opencv-doc is not installed
};

inline const FisheyeScene& fisheyeScene() {
  static const FisheyeScene scene = [] {
    FisheyeScene s;
    s.camera = loadCamera(MDBRIEF_SOURCE_DIR "/configs/cameras/lafida_fisheye0.yaml");
    if (const auto doc = opencvDocFolder()) s.plane.texture = decodeGreyImage(*doc / "graf1.png");
    s.plane.texelSize = 0.004;  // the plane is about 1 unit away: texture fills most of the view
    return s;
  }();
  return scene;
}

// The view from a camera at `centre` looking along +Z; empty without the texture.
inline cv::Mat renderFisheyeView(const cv::Vec3d& centre) {
  const FisheyeScene& s = fisheyeScene();
  if (s.plane.texture.empty()) return {};
  CameraPose pose;
  pose.centre = centre;
  return renderPlane(*s.camera, pose, s.plane);
}

// Reports microseconds per item (keypoint) from the items processed per iteration.
inline benchmark::Counter microsecondsPerItem(double itemsPerIteration, benchmark::IterationCount iterations) {
  return benchmark::Counter(itemsPerIteration * static_cast<double>(iterations),
                            benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::kIs1000);
}

}  // namespace mdbrief::bench
