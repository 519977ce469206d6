#include "scenes/plane_renderer.hpp"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace mdbrief {

cv::Point2d texelToPlane(const PlaneScene& scene, const cv::Point2d& texel) {
  return {(texel.x - scene.texture.cols / 2.0) * scene.texelSize,
          (texel.y - scene.texture.rows / 2.0) * scene.texelSize};
}

bool projectPlanePoint(const Camera& camera, const CameraPose& pose, const cv::Point2d& planeXY,
                       cv::Point2d& pixel) {
  const cv::Vec3d p = pose.rotation * (cv::Vec3d(planeXY.x, planeXY.y, 0.0) - pose.centre);
  return camera.bearingToPixel(p, pixel);
}

cv::Mat renderPlane(const Camera& camera, const CameraPose& pose, const PlaneScene& scene,
                    const RenderOptions& options) {
  if (scene.texture.empty() || scene.texture.type() != CV_8UC1)
    throw std::invalid_argument("renderPlane: the texture must be a non-empty 8UC1 image");
  if (options.supersampling < 1) throw std::invalid_argument("renderPlane: supersampling must be >= 1");
  const int ss = options.supersampling;
  const cv::Size size = camera.imageSize();
  const cv::Matx33d toWorld = pose.rotation.t();

  // Sub-ray maps into the texture; a pixel with a ray that misses the plane is painted 0.
  cv::Mat mapX(size.height * ss, size.width * ss, CV_32F), mapY(mapX.size(), CV_32F);
  cv::Mat valid(size, CV_8U);
  cv::parallel_for_(cv::Range(0, size.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < size.width; ++u) {
        bool allHit = true;
        for (int sy = 0; sy < ss; ++sy) {
          for (int sx = 0; sx < ss; ++sx) {
            const cv::Point2d px(u + (sx + 0.5) / ss - 0.5, v + (sy + 0.5) / ss - 0.5);
            float tx = -1e6f, ty = -1e6f;
            cv::Vec3d b;
            if (camera.pixelToBearing(px, b)) {
              const cv::Vec3d d = toWorld * b;
              const double lambda = -pose.centre[2] / d[2];
              if (d[2] != 0.0 && lambda > 0.0) {
                const double X = pose.centre[0] + lambda * d[0], Y = pose.centre[1] + lambda * d[1];
                tx = static_cast<float>(X / scene.texelSize + scene.texture.cols / 2.0);
                ty = static_cast<float>(Y / scene.texelSize + scene.texture.rows / 2.0);
              }
            }
            allHit = allHit && tx > -1e6f;
            mapX.at<float>(v * ss + sy, u * ss + sx) = tx;
            mapY.at<float>(v * ss + sy, u * ss + sx) = ty;
          }
        }
        valid.at<uchar>(v, u) = allHit && camera.isValid(cv::Point2d(u, v)) ? 255 : 0;
      }
    }
  });
  // The mirrored border continues the texture over the whole plane.
  cv::Mat fine, out;
  cv::remap(scene.texture, fine, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_REFLECT_101);
  cv::resize(fine, out, size, 0, 0, cv::INTER_AREA);
  out.setTo(0, valid == 0);
  return out;
}

}  // namespace mdbrief
