#include "eval_datasets.hpp"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "mdbrief/internal/base/size_text.hpp"
#include "patchextract/view_change.hpp"
#include "plane_geometry.hpp"
#include "toolkit/homography_file.hpp"
#include "toolkit/image_file.hpp"
#include "scenes/photo_camera.hpp"
#include "scenes/plane_renderer.hpp"

namespace mdbrief::eval {
namespace {

GroundTruthMap homographyMap(const cv::Matx33d& h, cv::Size target) {
  return [h, target](const cv::Point2d& p) -> std::optional<cv::Point2d> {
    const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1.0);
    if (!(q[2] > 0 || q[2] < 0)) return std::nullopt;
    const cv::Point2d r(q[0] / q[2], q[1] / q[2]);
    if (r.x < 0 || r.y < 0 || r.x > target.width - 1 || r.y > target.height - 1) return std::nullopt;
    return r;
  };
}

// The scene of the rendered sequences: the texture spans 3.2 units, the reference 1 unit away.
PlaneScene renderedScene(const cv::Mat& texture) { return {texture, 3.2 / texture.cols}; }

}  // namespace

cv::Mat loadEvaluationImage(const std::string& path) {
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw std::runtime_error(path + ": " + problem);
  // An evaluation on a partly decoded image would be wrong without saying so.
  if (const std::string problem = truncationProblem(path); !problem.empty())
    throw std::runtime_error(path + ": " + problem);
  cv::Mat image = decodeGreyImage(path);
  if (image.empty()) throw std::runtime_error(path + ": cannot read the image");
  return image;
}

std::optional<EvalSequence> loadOxfordSequence(const std::string& dir, const std::string& name) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) return std::nullopt;
  EvalSequence s;
  s.name = name;
  for (int k = 1; k <= 6; ++k) {
    fs::path img = fs::path(dir) / ("img" + std::to_string(k) + ".png");
    if (!fs::exists(img)) img = fs::path(dir) / ("img" + std::to_string(k) + ".ppm");
    if (!fs::exists(img)) return std::nullopt;
    s.images.push_back(loadEvaluationImage(img.string()));
  }
  for (int k = 2; k <= 6; ++k) {
    const fs::path h = fs::path(dir) / ("H1to" + std::to_string(k) + "p");
    if (!fs::exists(h)) return std::nullopt;
    s.pairs.push_back({0, k - 1, homographyMap(readHomography(h.string()), s.images[k - 1].size())});
  }
  s.camera = photoCamera(s.images[0].size());
  return s;
}

std::vector<CameraPose> renderedSequencePoses(int poses) {
  std::vector<CameraPose> ps;
  for (int k = 0; k < poses; ++k) {
    const double t = poses > 1 ? static_cast<double>(k) / (poses - 1) : 0.0;
    CameraPose p;
    p.centre = {1.2 * t, 0.4 * t, -1.0};
    p.rotation = cameraRotation(20.0 * t, -10.0 * t, 30.0 * t);
    ps.push_back(p);
  }
  return ps;
}

UserSequenceFiles userSequenceFiles(const std::string& dir, int images) {
  namespace fs = std::filesystem;
  UserSequenceFiles files;
  for (int k = 1; k <= images; ++k)
    files.images.push_back((fs::path(dir) / ("img" + std::to_string(k) + ".png")).string());
  for (int k = 2; k <= images; ++k)
    files.homographies.push_back((fs::path(dir) / ("H1to" + std::to_string(k))).string());
  files.camera = (fs::path(dir) / "camera.yaml").string();
  return files;
}

std::vector<std::string> allPaths(const UserSequenceFiles& files) {
  std::vector<std::string> paths = files.images;
  paths.insert(paths.end(), files.homographies.begin(), files.homographies.end());
  paths.push_back(files.camera);
  return paths;
}

namespace {

// Writes images, the bearing homographies image 1 -> image k and the camera into dir (created
// if missing), each file through a temporary name and a rename.
UserSequenceFiles writeUserSequence(const std::string& dir, const std::vector<cv::Mat>& images,
                                    const std::vector<cv::Matx33d>& homographies, const Camera& camera) {
  std::filesystem::create_directories(dir);
  const UserSequenceFiles files = userSequenceFiles(dir, static_cast<int>(images.size()));
  for (size_t k = 0; k < images.size(); ++k) writeImageAtomically(files.images[k], images[k]);
  for (size_t k = 0; k < homographies.size(); ++k) writeHomography(files.homographies[k], homographies[k]);
  saveCamera(camera, files.camera);  // atomic itself
  return files;
}

}  // namespace

UserSequenceFiles exportUserSequence(const std::string& dir, const cv::Mat& texture, const CameraPtr& camera,
                                     int poses) {
  const PlaneScene scene = renderedScene(texture);
  const std::vector<CameraPose> ps = renderedSequencePoses(poses);
  std::vector<cv::Mat> images;
  std::vector<cv::Matx33d> homographies;
  for (int k = 0; k < poses; ++k) {
    images.push_back(renderPlane(*camera, ps[k], scene));
    if (k > 0) homographies.push_back(planeBearingHomography(ps[0], ps[k]));
  }
  return writeUserSequence(dir, images, homographies, *camera);
}

namespace {

// The photo and the views of the same lens turned by cameraRotation(8 k, -4 k, 12 k) degrees,
// with the rotations (the bearing homographies image 1 -> image k + 1).
void turnedLensViews(const cv::Mat& photo, const CameraPtr& camera, int views, std::vector<cv::Mat>& images,
                     std::vector<cv::Matx33d>& rotations) {
  if (photo.size() != camera->imageSize())
    throw std::runtime_error("the photo is " + internal::sizeText(photo.size()) + " but the calibration " +
                             internal::sizeText(camera->imageSize()));
  images = {photo};
  rotations.clear();
  for (int k = 1; k < views; ++k) {
    const cv::Matx33d r = cameraRotation(8.0 * k, -4.0 * k, 12.0 * k);
    images.push_back(train::lensRotation(camera, r)->render(photo, 0));
    rotations.push_back(r);
  }
}

// Pixel of image a -> pixel of image b through a homography between bearings (b ~ h a, det > 0).
GroundTruthMap bearingHomographyMap(const CameraPtr& camera, const cv::Matx33d& h) {
  return [h, camera](const cv::Point2d& px) -> std::optional<cv::Point2d> {
    cv::Vec3d b;
    cv::Point2d out;
    if (!camera->pixelToBearing(px, b)) return std::nullopt;
    if (!camera->bearingToPixel(h * b, out) || !camera->isValid(out)) return std::nullopt;
    return out;
  };
}

}  // namespace

UserSequenceFiles exportRotatedViews(const std::string& dir, const cv::Mat& photo, const CameraPtr& camera,
                                     int views) {
  std::vector<cv::Mat> images;
  std::vector<cv::Matx33d> rotations;
  turnedLensViews(photo, camera, views, images, rotations);
  return writeUserSequence(dir, images, rotations, *camera);
}

EvalSequence turnedLensSequence(const std::string& name, const cv::Mat& photo, const CameraPtr& camera, int views) {
  EvalSequence s;
  s.name = name;
  s.camera = camera;
  s.cameraIsModel = true;
  std::vector<cv::Matx33d> rotations;
  turnedLensViews(photo, camera, views, s.images, rotations);
  for (size_t k = 0; k < rotations.size(); ++k)
    s.pairs.push_back({0, static_cast<int>(k + 1), bearingHomographyMap(camera, rotations[k])});
  return s;
}

EvalSequence renderedFisheyeSequence(const std::string& name, const cv::Mat& texture, const CameraPtr& camera,
                                     int poses) {
  EvalSequence s;
  s.name = name;
  s.camera = camera;
  s.cameraIsModel = true;
  s.baseline = true;
  const PlaneScene scene = renderedScene(texture);
  const std::vector<CameraPose> ps = renderedSequencePoses(poses);
  for (const auto& p : ps) s.images.push_back(renderPlane(*camera, p, scene));
  for (int k = 1; k < poses; ++k) {
    const CameraPose a = ps[0], b = ps[k];
    s.pairs.push_back({0, k, [camera, a, b, scene](const cv::Point2d& px) -> std::optional<cv::Point2d> {
                         const auto plane = pixelToPlane(*camera, a, px);
                         cv::Point2d out;
                         if (!plane || !onTexture(scene, *plane) || !projectPlanePoint(*camera, b, *plane, out) ||
                             !camera->isValid(out))
                           return std::nullopt;
                         return out;
                       }});
  }
  return s;
}

EvalSequence loadUserSequence(const std::string& name, const std::vector<std::string>& images,
                              const std::string& cameraPath, const std::vector<std::string>& homographyFiles,
                              const std::string& cameraId) {
  if (images.size() < 2) throw std::runtime_error("user data: at least two images are needed");
  if (homographyFiles.size() != images.size() - 1)
    throw std::runtime_error("user data: need one homography per image after the first (" +
                             std::to_string(images.size() - 1) + "), got " + std::to_string(homographyFiles.size()));
  EvalSequence s;
  s.name = name;
  CameraFileOptions cameraOptions;
  cameraOptions.cameraId = cameraId;
  s.camera = loadCamera(cameraPath, cameraOptions);
  s.cameraIsModel = true;
  for (const auto& p : images) {
    s.images.push_back(loadEvaluationImage(p));
    if (s.images.back().size() != s.camera->imageSize())
      throw std::runtime_error(p + ": image size differs from the camera's calibration size");
  }
  for (size_t k = 0; k < homographyFiles.size(); ++k) {
    cv::Matx33d h = readHomography(homographyFiles[k]);
    const double det = cv::determinant(h);
    if (!(std::abs(det) > 1e-12 * std::pow(cv::norm(h), 3)))
      throw std::runtime_error(homographyFiles[k] + ": the homography is singular");
    if (det < 0) h = -h;
    s.pairs.push_back({0, static_cast<int>(k + 1), bearingHomographyMap(s.camera, h)});
  }
  return s;
}

}  // namespace mdbrief::eval
