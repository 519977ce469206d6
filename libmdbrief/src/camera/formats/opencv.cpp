// OpenCV's calibration results: K and D as cv::calibrateCamera and cv::fisheye::calibrate return
// them (cameraFromOpenCv), and the FileStorage YAML the calibration samples write:
// camera_matrix and distortion_coefficients (opencv-matrix maps: rows, cols, dt, data),
// image_width, image_height and fisheye_model (0 or 1; the tutorial's camera_calibration writes
// it, calibration.cpp does not, and then D is the standard model's). Four coefficients without
// fisheye_model are either model's, so such a file is refused rather than guessed, unless the
// caller chooses (CameraFileOptions::opencvModel). Also a bare FileStorage with K and D, as
// cv2.fisheye and cv2.calibrateCamera users save their results, with the image size from
// image_width / image_height, width / height or image_size, else the caller's.
#include <sstream>
#include <string>
#include <vector>

#include "camera/construction.hpp"
#include "camera/formats/readers.hpp"
#include "camera/formats/yaml_reader.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/camera/kannala_brandt.hpp"
#include "mdbrief/camera/radtan.hpp"

namespace mdbrief {
namespace {

std::string numberText(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

}  // namespace

std::shared_ptr<Camera> cameraFromOpenCv(const cv::Matx33d& K, const std::vector<double>& D, cv::Size size,
                                         bool fisheye, const std::string& source) {
  const auto fail = [&](const std::string& what) { throw std::runtime_error(source + ": " + what); };
  if (K(0, 1) != 0.0)
    fail("K[0][1] = " + numberText(K(0, 1)) + " is a skew, which no camera model here has (it must be 0)");
  if (K(1, 0) != 0.0 || K(2, 0) != 0.0 || K(2, 1) != 0.0 || K(2, 2) != 1.0)
    fail("K must be [fx 0 cx; 0 fy cy; 0 0 1], its rows 2 and 3 are [" + numberText(K(1, 0)) + " " +
         numberText(K(1, 1)) + " " + numberText(K(1, 2)) + "; " + numberText(K(2, 0)) + " " + numberText(K(2, 1)) +
         " " + numberText(K(2, 2)) + "]");
  const CameraIntrinsics k{size.width, size.height, K(0, 0), K(1, 1), K(0, 2), K(1, 2)};
  if (fisheye) {
    if (D.size() != 4)
      fail("D of cv::fisheye needs 4 coefficients (k1 k2 k3 k4), found " + std::to_string(D.size()));
    return detail::construct<KannalaBrandtCamera>(source, KannalaBrandtParams{k, D[0], D[1], D[2], D[3]});
  }
  if (D.size() != 4 && D.size() != 5 && D.size() != 8 && D.size() != 12 && D.size() != 14)
    fail("D of cv::calibrateCamera needs 4, 5, 8, 12 or 14 coefficients (k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 "
         "[tx ty]]]]), found " + std::to_string(D.size()));
  // The thin-prism (s1..s4) and tilted-sensor (tx ty) terms have no model here.
  for (std::size_t i = 8; i < D.size(); ++i)
    if (D[i] != 0.0)
      fail("D[" + std::to_string(i) + "] = " + numberText(D[i]) + " is a thin-prism or tilted-sensor term, which no "
           "camera model here has (only k1 k2 p1 p2 k3 k4 k5 k6 may be non-zero)");
  const auto at = [&](std::size_t i) { return i < D.size() ? D[i] : 0.0; };
  RadTanParams p{k, at(0), at(1), at(2), at(3), at(4)};
  p.k4 = at(5);
  p.k5 = at(6);
  p.k6 = at(7);
  return detail::construct<RadTanCamera>(source, p);
}

namespace detail {

std::vector<double> openCvMatrix(const YamlReader& file, const std::string& key, int& rows, int& cols) {
  const YamlReader m = file.sub(key);
  rows = m.size("rows");
  cols = m.size("cols");
  return m.numbers("data", static_cast<std::size_t>(rows) * cols, "rows x cols values");
}

namespace {

// Whether four coefficients are cv::fisheye's: the file's fisheye_model, else the caller's
// choice, else refused as ambiguous naming both.
bool fisheyeModel(const YamlReader& file, const std::string& coefficientsKey, std::size_t count,
                  OpenCvModel choice) {
  if (file.has("fisheye_model")) {
    const double flag = file.number("fisheye_model");
    if (flag != 0.0 && flag != 1.0) file.fail("fisheye_model", "must be 0 or 1");
    const bool fisheye = flag == 1.0;
    if (choice != OpenCvModel::Unstated && fisheye != (choice == OpenCvModel::Fisheye))
      file.fail("fisheye_model", "says " + std::string(fisheye ? "fisheye" : "standard") + ", the OpenCV model chosen is " +
                                     toString(choice));
    return fisheye;
  }
  if (choice != OpenCvModel::Unstated) return choice == OpenCvModel::Fisheye;
  if (count == 4)
    file.fail(coefficientsKey, "has 4 coefficients, which are cv::fisheye's k1 k2 k3 k4 or cv::calibrateCamera's "
                               "k1 k2 p1 p2: add fisheye_model: 1 or 0 to say which, or choose (mdbrief "
                               "--camera-opencv-model fisheye|standard; Python opencv_model=\"fisheye\"|\"standard\"; "
                               "CameraFileOptions::opencvModel)");
  return false;
}

// The image size a file holds, checked against the caller's; the caller's when it holds none.
std::optional<cv::Size> imageSizeOf(const YamlReader& file, const CameraFileOptions& options) {
  std::optional<cv::Size> size;
  std::string key;
  if (file.has("image_width") || file.has("image_height")) {
    size = cv::Size(file.size("image_width"), file.size("image_height"));
    key = "image_width";
  } else if (file.has("width") || file.has("height")) {
    size = cv::Size(file.size("width"), file.size("height"));
    key = "width";
  } else if (file.has("image_size")) {
    size = file.imageSize("image_size");
    key = "image_size";
  }
  if (size && options.imageSize && *size != *options.imageSize)
    file.fail(key, "gives the size " + std::to_string(size->width) + "x" + std::to_string(size->height) +
                       ", the size given is " + std::to_string(options.imageSize->width) + "x" +
                       std::to_string(options.imageSize->height));
  return size ? size : options.imageSize;
}

}  // namespace

bool isOpenCvCalibration(const YAML::Node& root) { return static_cast<bool>(root["camera_matrix"]); }

std::shared_ptr<Camera> readOpenCvCalibration(const std::string& path, const YAML::Node& root,
                                              const CameraFileOptions& options) {
  const YamlReader file(path, root);
  int rows = 0, cols = 0;
  const std::vector<double> k = openCvMatrix(file, "camera_matrix", rows, cols);
  if (rows != 3 || cols != 3) file.fail("camera_matrix", "must be 3 x 3");
  const std::vector<double> d = openCvMatrix(file, "distortion_coefficients", rows, cols);
  if (rows != 1 && cols != 1) file.fail("distortion_coefficients", "must be one row or one column");
  const cv::Size size(file.size("image_width"), file.size("image_height"));
  if (options.imageSize && *options.imageSize != size)
    file.fail("image_width", "and image_height give the size " + std::to_string(size.width) + "x" +
                                 std::to_string(size.height) + ", the size given is " +
                                 std::to_string(options.imageSize->width) + "x" +
                                 std::to_string(options.imageSize->height));
  const bool fisheye = fisheyeModel(file, "distortion_coefficients", d.size(), options.opencvModel);
  return cameraFromOpenCv(cv::Matx33d(k.data()), d, size, fisheye, path);
}

bool isOpenCvKd(const YAML::Node& root) { return root["K"] && root["D"]; }

std::shared_ptr<Camera> readOpenCvKd(const std::string& path, const YAML::Node& root, const CameraFileOptions& options) {
  const YamlReader file(path, root);
  int rows = 0, cols = 0;
  const std::vector<double> k = openCvMatrix(file, "K", rows, cols);
  if (rows != 3 || cols != 3) file.fail("K", "must be 3 x 3");
  const std::vector<double> d = openCvMatrix(file, "D", rows, cols);
  if (rows != 1 && cols != 1) file.fail("D", "must be one row or one column");
  const std::optional<cv::Size> size = imageSizeOf(file, options);
  if (!size)
    throw std::runtime_error(path + ": holds no image size (keys image_width and image_height, width and height, "
                                    "or image_size): give it (mdbrief --camera-size WxH; Python image_size=(w, h); "
                                    "CameraFileOptions::imageSize)");
  const bool fisheye = fisheyeModel(file, "D", d.size(), options.opencvModel);
  return cameraFromOpenCv(cv::Matx33d(k.data()), d, *size, fisheye, path);
}

}  // namespace detail
}  // namespace mdbrief
