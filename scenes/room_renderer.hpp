#pragma once
// Renders a textured box room around the camera through any camera model: a 3D scene seen over
// the whole field of view, for two-view geometry with a known relative pose (a rendered stereo
// rig). Each wall is a plane holding a photo, repeated mirrored past its edges; the camera must
// be inside the box, where every ray meets exactly one wall.
#include <array>
#include <cstdint>
#include <optional>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief {

struct RoomScene {
  // Opposite corners of the box, world units (the camera poses' units).
  cv::Vec3d minCorner{-2.0, -1.4, -1.6}, maxCorner{2.2, 1.2, 3.0};
  // 8UC1 photos of the walls at x = min, x = max, y = min, y = max, z = min, z = max. Texel
  // (i, j) of a wall across axis a sits at the wall's centre plus (i - w/2, j - h/2) texels along
  // the next two axes in the order x, y, z, x.
  std::array<cv::Mat, 6> walls;
  double texelSize = 0.004;  // world units per texel
};

// 8UC1 image of camera.imageSize(); pixels outside the camera's valid area are 0. Throws
// std::invalid_argument for a wall that is empty or not 8UC1, a box with no volume, or a camera
// centre outside the box.
cv::Mat renderRoom(const Camera& camera, const CameraPose& pose, const RoomScene& scene,
                   const RenderOptions& options = {});

// Where the ray of camera-frame `bearing` from a camera at `pose` leaves the room: the wall
// point it sees (world units). Empty for a zero or non-finite bearing.
std::optional<cv::Vec3d> roomPointSeen(const CameraPose& pose, const RoomScene& scene, const cv::Vec3d& bearing);

// The rotation of a camera turned by `yawDeg` about its y axis, then tilted by `pitchDeg` about
// its x axis (world -> camera, as CameraPose::rotation).
cv::Matx33d yawPitchRotation(double yawDeg, double pitchDeg);

// A rendered image as a camera captures it: intensities times `gain` plus `offset`, Gaussian
// noise of `noiseSigma` grey levels (seeded), pixels outside the camera's area left 0.
cv::Mat simulateCapture(const cv::Mat& rendered, double gain, double offset, double noiseSigma, uint64_t seed);

}  // namespace mdbrief
