#include "cli/extraction_flags.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>

#include <opencv2/imgcodecs.hpp>

#include "cli/commands.hpp"
#include "cli/storage_io.hpp"
#include "mdbrief/camera_io.hpp"
#include "mdbrief/internal/input_file.hpp"
#include "mdbrief/internal/size_text.hpp"
#include "toolkit/image_file.hpp"

namespace mdbrief::cli {
namespace {

using internal::sizeText;

void requireReadableFile(const std::string& path) {
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw InputError(path + ": " + problem);
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0) throw InputError(path + ": the file is empty");
}

}  // namespace

void addExtractionFlags(CLI::App& cmd, ExtractionFlags& flags) {
  cmd.add_option("--camera", flags.camera, "Calibration file (configs/cameras/README.md); required for dbrief/mdbrief");
  cmd.add_option("--descriptor", flags.descriptor, "Descriptor kind")
      ->check(CLI::IsMember(namesOf(kDescriptorKindNames)))
      ->capture_default_str();
  cmd.add_option("--bits", flags.bits, "Descriptor length in bits: 32..512, a multiple of 32")
      ->check(CLI::Range(32, 512))
      ->capture_default_str();
  cmd.add_flag("--no-orientation", flags.noOrientation, "Do not rotate the tests by the keypoint angle");
  cmd.add_option("--orientation", flags.orientation,
                 "dbrief/mdbrief: measure the angle on the tangent plane, or take the detector's")
      ->check(CLI::IsMember(namesOf(kOrientationSourceNames)))
      ->capture_default_str();
  cmd.add_option("--features", flags.features, "Maximum number of keypoints per image")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd.add_option("--detector", flags.detector,
                 "Keypoint detector: modorb (FAST corners, ORB's scheme) or hessian (scale-space blobs)")
      ->check(CLI::IsMember(namesOf(kDetectorMethodNames)))
      ->capture_default_str();
  cmd.add_flag("--conformal", flags.conformal,
               "Detect on the camera's stereographic (conformal) view and map the keypoints back (needs --camera)");
  cmd.add_option("--form", flags.form, "How dBRIEF/mdBRIEF distort the tests: affine (fast) or paper (eq. 8-11)")
      ->check(CLI::IsMember(namesOf(kDistortionFormNames)))
      ->capture_default_str();
  cmd.add_option("--pattern", flags.pattern, "Test set: a built-in name or a JSON file (default: the built-in default)");
  cmd.add_option("--support-scale", flags.supportScale,
                 "The tests' 31-pixel diameter spans this times the keypoint size (1 = cv::ORB's convention)")
      ->check(CLI::Range(0.1, 20.0))
      ->capture_default_str();
  cmd.add_flag("--allow-size-mismatch", flags.allowSizeMismatch,
               "Rescale the calibration to the image size instead of rejecting a different size");
  cmd.add_flag("--strict", flags.strict,
               "Reject a truncated (partly decodable) JPEG or PNG instead of warning and describing what decodes");
}

CameraPtr loadCalibration(const ExtractionFlags& flags) {
  if (flags.camera.empty()) {
    if (usesCamera(parseDescriptorKind(flags.descriptor)))
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

cv::Mat loadImage(const std::string& path, bool strict) {
  requireReadableFile(path);
  if (const std::string problem = truncationProblem(path); !problem.empty()) {
    if (strict) throw InputError(path + ": " + problem + " (--strict)");
    std::cerr << "warning: " << path << ": " << problem << "; describing the decodable part\n";
  }
  const cv::Mat image = decodeGreyImage(path);
  if (image.empty()) throw InputError(path + ": cannot decode the image (unsupported format or truncated file)");
  return image;
}

std::vector<cv::KeyPoint> loadKeypoints(const std::string& path) {
  requireReadableFile(path);
  const StorageReader storage(path);
  if (!storage.has("keypoints")) throw InputError(path + ": no node 'keypoints'");
  const std::vector<cv::KeyPoint> keypoints = storage.keypoints("keypoints");
  // The library drops such keypoints silently; a file that holds them is reported instead.
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::KeyPoint& k = keypoints[i];
    if (!std::isfinite(k.pt.x) || !std::isfinite(k.pt.y) || !(k.size > 0.f) || !std::isfinite(k.size))
      throw InputError(path + ": keypoint " + std::to_string(i) + " at (" + std::to_string(k.pt.x) + ", " +
                       std::to_string(k.pt.y) + ") with size " + std::to_string(k.size) +
                       ": a keypoint needs a finite position and a positive finite size");
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
  options.detector.method = parseDetectorMethod(flags.detector);
  options.detector.conformal = flags.conformal;
  options.descriptor.kind = parseDescriptorKind(flags.descriptor);
  options.descriptor.bits = flags.bits;
  options.descriptor.useOrientation = !flags.noOrientation;
  options.descriptor.orientation = parseOrientationSource(flags.orientation);
  options.descriptor.form = parseDistortionForm(flags.form);
  options.descriptor.pattern = flags.pattern;
  options.descriptor.supportScale = flags.supportScale;
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
    // E.g. an image the calibration does not fit.
    throw InputError(imagePath + ": " + e.what());
  }
  return f;
}

}  // namespace mdbrief::cli
