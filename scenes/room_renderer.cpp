#include "scenes/room_renderer.hpp"

#include <algorithm>

#include <cmath>

#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace mdbrief {

cv::Mat renderRoom(const Camera& camera, const CameraPose& pose, const RoomScene& scene,
                   const RenderOptions& options) {
  for (const cv::Mat& wall : scene.walls)
    if (wall.empty() || wall.type() != CV_8UC1)
      throw std::invalid_argument("renderRoom: every wall must be a non-empty 8UC1 image");
  for (int a = 0; a < 3; ++a) {
    if (!(scene.minCorner[a] < scene.maxCorner[a]))
      throw std::invalid_argument("renderRoom: the box has no volume");
    if (!(pose.centre[a] > scene.minCorner[a] && pose.centre[a] < scene.maxCorner[a]))
      throw std::invalid_argument("renderRoom: the camera must be inside the box");
  }
  if (options.supersampling < 1) throw std::invalid_argument("renderRoom: supersampling must be >= 1");
  const int ss = options.supersampling;
  const cv::Size size = camera.imageSize();
  const cv::Matx33d toWorld = pose.rotation.t();

  // Per sub-ray: the wall it leaves the box through (the nearest of the three walls it heads
  // for) and the texel there; the walls are then sampled one after the other.
  cv::Mat mapX(size.height * ss, size.width * ss, CV_32F, cv::Scalar(0)), mapY(mapX.size(), CV_32F, cv::Scalar(0));
  cv::Mat wallOf(mapX.size(), CV_8U, cv::Scalar(255));
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v)
      for (int u = 0; u < size.width; ++u)
        for (int sy = 0; sy < ss; ++sy)
          for (int sx = 0; sx < ss; ++sx) {
            const cv::Point2d px(u + (sx + 0.5) / ss - 0.5, v + (sy + 0.5) / ss - 0.5);
            cv::Vec3d b;
            if (!camera.pixelToBearing(px, b)) continue;
            const cv::Vec3d d = toWorld * b;
            double nearest = std::numeric_limits<double>::infinity();
            int wall = -1;
            for (int a = 0; a < 3; ++a) {
              if (d[a] == 0.0) continue;
              const bool up = d[a] > 0.0;
              const double t = ((up ? scene.maxCorner[a] : scene.minCorner[a]) - pose.centre[a]) / d[a];
              if (t < nearest) nearest = t, wall = 2 * a + (up ? 1 : 0);
            }
            if (wall < 0) continue;
            const int a = wall / 2, i = (a + 1) % 3, j = (a + 2) % 3;
            const cv::Vec3d hit = pose.centre + nearest * d;
            const cv::Mat& photo = scene.walls[wall];
            const double ci = 0.5 * (scene.minCorner[i] + scene.maxCorner[i]);
            const double cj = 0.5 * (scene.minCorner[j] + scene.maxCorner[j]);
            const int r = v * ss + sy, c = u * ss + sx;
            mapX.at<float>(r, c) = static_cast<float>((hit[i] - ci) / scene.texelSize + photo.cols / 2.0);
            mapY.at<float>(r, c) = static_cast<float>((hit[j] - cj) / scene.texelSize + photo.rows / 2.0);
            wallOf.at<uchar>(r, c) = static_cast<uchar>(wall);
          }
  });
  cv::Mat fine(mapX.size(), CV_8U, cv::Scalar(0)), sampled;
  for (int wall = 0; wall < 6; ++wall) {
    // The mirrored border continues each photo over its whole wall.
    cv::remap(scene.walls[wall], sampled, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
    sampled.copyTo(fine, wallOf == wall);
  }
  cv::Mat out, valid(size, CV_8U);
  cv::resize(fine, out, size, 0, 0, cv::INTER_AREA);
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u) valid.at<uchar>(v, u) = camera.isValid(cv::Point2d(u, v)) ? 255 : 0;
  out.setTo(0, valid == 0);
  return out;
}

std::optional<cv::Vec3d> roomPointSeen(const CameraPose& pose, const RoomScene& scene, const cv::Vec3d& bearing) {
  const cv::Vec3d d = pose.rotation.t() * bearing;
  double t = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] > 0) t = std::min(t, (scene.maxCorner[axis] - pose.centre[axis]) / d[axis]);
    if (d[axis] < 0) t = std::min(t, (scene.minCorner[axis] - pose.centre[axis]) / d[axis]);
  }
  if (!std::isfinite(t) || !(t > 0)) return std::nullopt;
  return pose.centre + t * d;
}

cv::Matx33d yawPitchRotation(double yawDeg, double pitchDeg) {
  const double y = yawDeg * CV_PI / 180.0, p = pitchDeg * CV_PI / 180.0;
  const cv::Matx33d yaw(std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y));
  const cv::Matx33d pitch(1, 0, 0, 0, std::cos(p), -std::sin(p), 0, std::sin(p), std::cos(p));
  return pitch * yaw;
}

cv::Mat simulateCapture(const cv::Mat& rendered, double gain, double offset, double noiseSigma, uint64_t seed) {
  cv::Mat noise(rendered.size(), CV_32F), grey, out;
  cv::RNG(seed).fill(noise, cv::RNG::NORMAL, 0.0, noiseSigma);
  rendered.convertTo(grey, CV_32F, gain, offset);
  cv::Mat(grey + noise).convertTo(out, CV_8U);
  out.setTo(0, rendered == 0);
  return out;
}

}  // namespace mdbrief
