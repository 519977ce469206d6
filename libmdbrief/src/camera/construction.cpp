#include "camera/construction.hpp"

#include <cmath>
#include <sstream>

#include "mdbrief/camera/io.hpp"

namespace mdbrief::detail {
namespace {

// The model's parameters as "key: value, ..." (its YAML form without the image size), for
// errors about the model as a whole.
std::string parameterList(const Camera& camera) {
  std::istringstream yaml(cameraToYaml(camera));
  std::string line, list;
  while (std::getline(yaml, line))
    if (line.rfind("model:", 0) != 0 && line.rfind("width:", 0) != 0 && line.rfind("height:", 0) != 0)
      list += (list.empty() ? "" : ", ") + line;
  return list;
}

}  // namespace

void requirePlausible(const Camera& camera, const std::string& source) {
  const auto fail = [&](const std::string& problem) {
    return std::runtime_error(source + ": " + camera.modelName() + " camera with " + parameterList(camera) + ": " +
                              problem);
  };
  cv::Point2d centre;
  if (!camera.bearingToPixel({0, 0, 1}, centre) || !camera.isValid(centre))
    throw fail("the optical axis does not project into the image");
  const cv::Size size = camera.imageSize();
  double widest = 0.0;
  for (int k = 0; k < 16; ++k) {
    const cv::Point2d dir(std::cos(k * CV_PI / 8), std::sin(k * CV_PI / 8));
    double previous = -1.0;
    for (double r = 1.0; r < size.width + size.height; r += 1.0) {
      const cv::Point2d px = centre + r * dir;
      if (!camera.isValid(px)) break;
      cv::Vec3d b;
      cv::Point2d back;
      if (!camera.pixelToBearing(px, b) || !camera.bearingToPixel(b, back) || !(cv::norm(back - px) < 0.01))
        throw fail("the inverse does not converge at pixel (" + std::to_string(px.x) + ", " + std::to_string(px.y) + ")");
      const double angle = std::atan2(std::hypot(b[0], b[1]), b[2]);
      if (!(angle > previous))
        throw fail("the distortion is not monotonic: the ray angle stops growing at pixel (" + std::to_string(px.x) +
                   ", " + std::to_string(px.y) + ")");
      previous = angle;
      widest = std::max(widest, angle);
    }
  }
  if (!(widest * 180.0 / CV_PI >= 0.5))
    throw fail("the image spans only " + std::to_string(widest * 180.0 / CV_PI) + " degrees from the axis");
}

std::shared_ptr<Camera> makeOcam(const std::string& source, OcamParams p) {
  if (!p.forward.empty() && p.forward.front() > 0.0)
    for (double& a : p.forward) a = -a;
  return construct<OcamCamera>(source, p);
}

}  // namespace mdbrief::detail
