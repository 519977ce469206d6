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
  flags.options.add(cmd, mdBriefOptionFields());
  cmd.add_flag("--allow-size-mismatch", flags.allowSizeMismatch,
               "Rescale the calibration to the image size instead of rejecting a different size");
  cmd.add_flag("--strict", flags.strict,
               "Reject a truncated (partly decodable) JPEG or PNG instead of warning and describing what decodes");
}

MdBriefOptions extractionOptions(const ExtractionFlags& flags) {
  try {
    return flags.options.apply(MdBriefOptions{}, [](const MdBriefOptions& o) { validate(o); });
  } catch (const OptionError& e) {
    throw InputError(e.what());
  }
}

CameraPtr loadCalibration(const ExtractionFlags& flags) {
  // The options first: a bad flag is reported before any file is read.
  const DescriptorKind kind = extractionOptions(flags).descriptor.kind;
  if (flags.camera.empty()) {
    if (usesCamera(kind)) throw InputError("--camera is required for --descriptor " + toString(kind));
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
  const MdBriefOptions options = extractionOptions(flags);
  try {
    return MdBrief::create(camera, options);
  } catch (const std::exception& e) {
    // An unusable --pattern.
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
