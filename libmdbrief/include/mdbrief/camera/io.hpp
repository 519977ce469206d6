#pragma once
// Loading and saving camera calibrations: the project's YAML (its schema is documented in
// configs/cameras/README.md) and the files of the calibration tools users already have, each
// read into the matching camera model.
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/base/enum_names.hpp"

namespace mdbrief {

// The calibration file formats (configs/cameras/README.md "Other tools' files" has the keys each
// one is read from and the camera model it becomes):
//  - mdbrief: the project's YAML (a `model:` key);
//  - calib-adapter: fisheye-calib-adapter YAML (`image: {width, height}` and `parameter: {...}`;
//    the model is recognised from the parameter keys: coefficients -> ocam, k1..k4 ->
//    kannala_brandt, p1/p2 -> radtan, xi + alpha -> double_sphere, alpha + beta -> eucm,
//    alpha -> ucm, fx fy cx cy only -> pinhole);
//  - kalibr: Kalibr's camchain.yaml (cam0, cam1, ... with camera_model);
//  - basalt: basalt's calib.json (value0 with intrinsics);
//  - orbslam3: ORB-SLAM3's settings (Camera.type; the old flat keys and the newer Camera1.*);
//  - euroc: a EuRoC / Kimera-VIO sensor.yaml (camera_model, intrinsics, distortion_model,
//    distortion_coefficients, resolution, T_BS);
//  - opencv: the FileStorage YAML OpenCV's calibration samples write (camera_matrix,
//    distortion_coefficients, image_width, image_height, fisheye_model);
//  - opencv-kd: a FileStorage file with K and D as cv2.fisheye or cv2.calibrateCamera users
//    save them (the image size from image_width / image_height, width / height or image_size,
//    else CameraFileOptions::imageSize);
//  - colmap: COLMAP's cameras.txt (lines "CAMERA_ID MODEL WIDTH HEIGHT PARAMS...");
//  - ocamcalib: OCamCalib's calib_results.txt (comment lines and five lines of numbers).
// auto recognises the format from the content, in this order.
enum class CameraFormat { Auto, Mdbrief, CalibAdapter, Kalibr, Basalt, OrbSlam3, Euroc, OpenCv, OpenCvKd, Colmap, OcamCalib };
inline constexpr EnumName<CameraFormat> kCameraFormatNames[] = {
    {CameraFormat::Auto, "auto"},         {CameraFormat::Mdbrief, "mdbrief"},     {CameraFormat::CalibAdapter, "calib-adapter"},
    {CameraFormat::Kalibr, "kalibr"},     {CameraFormat::Basalt, "basalt"},       {CameraFormat::OrbSlam3, "orbslam3"},
    {CameraFormat::Euroc, "euroc"},       {CameraFormat::OpenCv, "opencv"},       {CameraFormat::OpenCvKd, "opencv-kd"},
    {CameraFormat::Colmap, "colmap"},     {CameraFormat::OcamCalib, "ocamcalib"}};
inline std::string toString(CameraFormat format) { return nameOf(format, kCameraFormatNames); }
inline CameraFormat parseCameraFormat(const std::string& name) {
  return parseName(name, kCameraFormatNames, "camera format");
}

// Which model four OpenCV distortion coefficients are when the file does not say (opencv's
// fisheye_model key, opencv-kd's fisheye_model key): cv::fisheye's k1 k2 k3 k4 or
// cv::calibrateCamera's k1 k2 p1 p2.
enum class OpenCvModel { Unstated, Fisheye, Standard };
inline constexpr EnumName<OpenCvModel> kOpenCvModelNames[] = {
    {OpenCvModel::Unstated, "unstated"}, {OpenCvModel::Fisheye, "fisheye"}, {OpenCvModel::Standard, "standard"}};
inline std::string toString(OpenCvModel model) { return nameOf(model, kOpenCvModelNames); }
inline OpenCvModel parseOpenCvModel(const std::string& name) {
  return parseName(name, kOpenCvModelNames, "OpenCV model");
}

// Thrown when a file holds several cameras and CameraFileOptions::cameraId chooses none; the
// message ends "choose one by its id", and ids() lists them so that a caller can say how its own
// interface takes one.
class CameraIdRequired : public std::runtime_error {
 public:
  CameraIdRequired(const std::string& message, std::vector<std::string> ids)
      : std::runtime_error(message), ids_(std::move(ids)) {}
  const std::vector<std::string>& ids() const noexcept { return ids_; }

 private:
  std::vector<std::string> ids_;
};

struct CameraFileOptions {
  CameraFormat format = CameraFormat::Auto;  // auto: recognised from the content
  // Which camera of a file that holds several: Kalibr's "cam0", "cam1", ...; basalt's index "0",
  // "1", ...; ORB-SLAM3's "1" or "2" (Camera1 / Camera2); COLMAP's CAMERA_ID. Empty: the file's
  // only camera (a file with several is refused, naming them). The one-camera formats refuse a
  // choice.
  std::string cameraId;
  // The image size of a file that does not hold one (opencv-kd); a file that holds one must
  // agree with it. None: the file's own, and an opencv-kd file without a size is refused.
  std::optional<cv::Size> imageSize = std::nullopt;
  // unstated: four coefficients of an opencv or opencv-kd file without fisheye_model are refused
  // as ambiguous. A file whose fisheye_model says otherwise is refused.
  OpenCvModel opencvModel = OpenCvModel::Unstated;
};

struct CameraFile {
  std::shared_ptr<Camera> camera;
  CameraFormat format = CameraFormat::Auto;  // the format it was read as (never auto)
};

// Reads a calibration. A file no format recognises is refused with a message listing the
// formats tried and naming what chooses one (CameraFileOptions::format, the command line's
// --camera-format, Python's format=); a recognised one is read only as its format's model (never guessed into
// another). Kalibr, basalt and ORB-SLAM3 use OpenCV's pixel convention, as this library does
// (camera.hpp); COLMAP's principal point is moved by -0.5 px (COLMAP puts the centre of the
// top-left pixel at (0.5, 0.5)).
// An OCam forward polynomial with a0 > 0 (z pointing forward, as in fisheye-calib-adapter) is
// negated to OCamCalib's a0 < 0; the inverse polynomial is in OCamCalib's theta convention in
// both cases (checked on the data: it vanishes at theta = -pi/2 for either file).
// Throws std::runtime_error whose message starts with the path and names the offending key or
// line (missing, not a number, NaN/inf, non-positive size, wrong count, unknown model or key,
// unparsable file, a camera choice the file does not have), or says the file is over 1 MiB
// (refused unparsed: calibrations are a few hundred bytes).
CameraFile readCameraFile(const std::string& path, const CameraFileOptions& options = {});
// readCameraFile(path, options).camera.
std::shared_ptr<Camera> loadCamera(const std::string& path, const CameraFileOptions& options = {});

// The camera in the project's YAML schema (OCam: forward polynomial with a0 < 0, and the
// inverse polynomial actually used, fitted or not). Throws std::invalid_argument for a Camera
// subclass this library does not know.
std::string cameraToYaml(const Camera& camera);

// Writes cameraToYaml(camera) to path atomically (temporary file in the same directory, then
// rename). Throws std::runtime_error naming the path on failure.
void saveCamera(const Camera& camera, const std::string& path);

// A parameter as the project's YAML holds it: a number, or a list (OCam's polynomials).
using CameraParameter = std::variant<double, std::vector<double>>;
using CameraParameters = std::map<std::string, CameraParameter>;

// The model names of the project's YAML, and each model's keys (besides model, width, height).
std::vector<std::string> cameraModelNames();
// Throws std::invalid_argument listing the models for an unknown one.
std::vector<std::string> cameraModelKeys(const std::string& model);

// A camera from its model, image size and parameters named as the project's YAML keys, read and
// checked as loadCamera reads such a file. Errors start with `source` and call the parameters by
// `noun` ("<source>: keyword 'k1' is missing"). Throws std::runtime_error.
std::shared_ptr<Camera> makeCamera(const std::string& model, cv::Size size, const CameraParameters& parameters,
                                   const std::string& source = "camera", const std::string& noun = "key");
// The camera's parameters by those names: makeCamera(camera.modelName(), camera.imageSize(),
// cameraParameters(camera)) is the same camera, bit for bit. Throws as cameraToYaml.
CameraParameters cameraParameters(const Camera& camera);

// A camera from OpenCV's calibration results: K = [fx 0 cx; 0 fy cy; 0 0 1] (no skew) and D,
// cv::fisheye's k1 k2 k3 k4 (fisheye: kannala_brandt) or cv::calibrateCamera's 4, 5, 8, 12 or 14
// coefficients (radtan: k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 [tx ty]]]], the thin-prism and
// tilt terms zero). Throws std::runtime_error starting with `source` and naming the entry at
// fault.
std::shared_ptr<Camera> cameraFromOpenCv(const cv::Matx33d& K, const std::vector<double>& D, cv::Size size, bool fisheye,
                                         const std::string& source = "OpenCV calibration");

}  // namespace mdbrief
