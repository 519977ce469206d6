#pragma once
// Renders a textured plane through any camera model: the paper's simulation (Graffiti as the
// plane z = 0, a virtual camera moving in front of it) and the synthetic ground truth of the
// tests and the evaluation. The plane is the world plane z = 0; texel (i, j) of the texture
// sits at world (X, Y) = ((i - w/2) * texelSize, (j - h/2) * texelSize); outside the texture
// the plane repeats it mirrored, so every ray that hits the plane sees texture.
#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"

namespace mdbrief {

struct PlaneScene {
  cv::Mat texture;         // 8UC1
  double texelSize = 1.0;  // world units per texel
};

// World -> camera: p_cam = rotation * (p_world - centre). The identity rotation looks along
// world +Z, so a camera at centre (0, 0, -D) faces the plane fronto-parallel from distance D.
struct CameraPose {
  cv::Matx33d rotation = cv::Matx33d::eye();
  cv::Vec3d centre{0, 0, -1};
};

struct RenderOptions {
  // Rays per pixel along each axis (box-filtered): 3x3 keeps the minified rim of a fisheye
  // view from aliasing.
  int supersampling = 3;
};

// 8UC1 image of imageSize(); pixels whose ray misses the plane or lies outside the camera's
// valid area are 0. Throws std::invalid_argument for an empty or non-8UC1 texture.
cv::Mat renderPlane(const Camera& camera, const CameraPose& pose, const PlaneScene& scene,
                    const RenderOptions& options = {});

// World point of the plane -> pixel; false if it is behind the camera or not projectable.
bool projectPlanePoint(const Camera& camera, const CameraPose& pose, const cv::Point2d& planeXY,
                       cv::Point2d& pixel);

// Texel coordinates <-> plane coordinates (see the file comment).
cv::Point2d texelToPlane(const PlaneScene& scene, const cv::Point2d& texel);

}  // namespace mdbrief
