#include "cli/extraction_flags.hpp"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "cli/commands.hpp"
#include "mdbrief/camera_io.hpp"

namespace mdbrief::cli {
namespace {

std::string sizeText(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

void requireReadableFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
  if (std::filesystem::file_size(path, ec) == 0) throw InputError(path + ": the file is empty");
}

}  // namespace

void addExtractionFlags(CLI::App& cmd, ExtractionFlags& flags) {
  cmd.add_option("--camera", flags.camera, "Calibration file (configs/cameras/README.md); required for dbrief/mdbrief");
  cmd.add_option("--descriptor", flags.descriptor, "Descriptor kind")
      ->check(CLI::IsMember({"brief", "dbrief", "mdbrief", "mbrief"}))
      ->capture_default_str();
  cmd.add_option("--bits", flags.bits, "Descriptor length in bits: 32..512, a multiple of 32")
      ->check(CLI::Range(32, 512))
      ->capture_default_str();
  cmd.add_flag("--no-orientation", flags.noOrientation, "Do not rotate the tests by the keypoint angle");
  cmd.add_option("--orientation", flags.orientation,
                 "dbrief/mdbrief: measure the angle on the tangent plane, or take the detector's")
      ->check(CLI::IsMember({"tangent-plane", "keypoint"}))
      ->capture_default_str();
  cmd.add_option("--features", flags.features, "Maximum number of keypoints per image")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd.add_option("--form", flags.form, "How dBRIEF/mdBRIEF distort the tests: affine (fast) or paper (eq. 8-11)")
      ->check(CLI::IsMember({"affine", "paper"}))
      ->capture_default_str();
  cmd.add_option("--pattern", flags.pattern, "Test set: a built-in name or a JSON file (default: the built-in default)");
  cmd.add_flag("--allow-size-mismatch", flags.allowSizeMismatch,
               "Rescale the calibration to the image size instead of rejecting a different size");
}

CameraPtr loadCalibration(const ExtractionFlags& flags) {
  if (flags.camera.empty()) {
    if (flags.descriptor != "brief" && flags.descriptor != "mbrief")
      throw InputError("--camera is required for --descriptor " + flags.descriptor);
    return nullptr;
  }
  requireReadableFile(flags.camera);
  try {
    return loadCamera(flags.camera);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    // loadCamera's messages already start with the path.
    throw InputError(what.rfind(flags.camera, 0) == 0 ? what : flags.camera + ": " + what);
  }
}

cv::Mat loadImage(const std::string& path) {
  requireReadableFile(path);
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    image.release();
  }
  if (image.empty()) throw InputError(path + ": cannot decode the image (unsupported format or truncated file)");
  return image;
}

std::vector<cv::KeyPoint> loadKeypoints(const std::string& path) {
  requireReadableFile(path);
  std::vector<cv::KeyPoint> keypoints;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) throw InputError(path + ": cannot open as an OpenCV FileStorage file");
    const cv::FileNode node = fs["keypoints"];
    if (node.empty()) throw InputError(path + ": no node 'keypoints'");
    cv::read(node, keypoints);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot parse the keypoints: " + e.err);
  }
  return keypoints;
}

cv::Ptr<MdBrief> makeFeature(const ExtractionFlags& flags, const CameraPtr& calibration,
                             const std::string& imagePath, cv::Size imageSize) {
  CameraPtr camera = calibration;
  if (camera && camera->imageSize() != imageSize) {
    if (!flags.allowSizeMismatch)
      throw InputError(imagePath + ": image size " + sizeText(imageSize) + " differs from the calibration " +
                       flags.camera + " (" + sizeText(camera->imageSize()) +
                       "); pass --allow-size-mismatch to rescale the calibration");
    camera = camera->resized(imageSize);
  }
  MdBriefOptions options;
  options.detector.nfeatures = flags.features;
  options.descriptor.kind = parseDescriptorKind(flags.descriptor);
  options.descriptor.bits = flags.bits;
  options.descriptor.useOrientation = !flags.noOrientation;
  options.descriptor.orientation = parseOrientationSource(flags.orientation);
  options.descriptor.form = parseDistortionForm(flags.form);
  options.descriptor.pattern = flags.pattern;
  try {
    return MdBrief::create(camera, options);
  } catch (const std::exception& e) {
    // Bad --bits (not a multiple of 32) or an unusable --pattern.
    throw InputError(std::string("invalid descriptor options: ") + e.what());
  }
}

Features extractFeatures(const ExtractionFlags& flags, const CameraPtr& calibration, const std::string& imagePath,
                         const cv::Mat& image, const std::optional<std::vector<cv::KeyPoint>>& given) {
  const cv::Ptr<MdBrief> feature = makeFeature(flags, calibration, imagePath, image.size());
  Features f;
  if (given) f.keypoints = *given;
  try {
    feature->detectAndComputeWithMasks(image, cv::noArray(), f.keypoints, f.descriptors, f.masks, given.has_value());
  } catch (const std::invalid_argument& e) {
    // E.g. a given keypoint whose octave the pyramid does not have.
    throw InputError(imagePath + ": " + e.what());
  }
  return f;
}

}  // namespace mdbrief::cli
