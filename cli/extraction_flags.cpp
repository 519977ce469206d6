#include "cli/extraction_flags.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <locale>
#include <optional>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/storage_io.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/internal/base/io/input_file.hpp"
#include "mdbrief/internal/base/size_text.hpp"
#include "mdbrief/api/presets.hpp"
#include "mdbrief/camera/tangent_plane.hpp"
#include "toolkit/content_digest.hpp"
#include "toolkit/image_file.hpp"

namespace mdbrief::cli {
namespace {

using internal::sizeText;

// Below this share of the image the calibration leaves almost nothing to describe (a focal
// length of 1e-9 px puts every pixel at 90 degrees): the run gives few or no keypoints, so it says why.
constexpr double kFewPercentOfTheImage = 0.05;

// Whether the descriptor's tangent plane can be placed at p (within its incidence bound) and
// projects half a plane unit (about a pixel) around it: the Jacobian alone exists up to the
// edge of the model's domain (a focal length of 1e-9 px), where no footprint fits.
bool planeProjectsAround(const Camera& camera, const cv::Point2d& p, const DescriptorOptions& descriptor) {
  const auto frame = tangentPlaneAt(camera, p, descriptor.maxIncidenceDeg, descriptor.form == DistortionForm::Affine);
  if (!frame) return false;
  cv::Point2d pixel;
  for (const cv::Point2d offset :
       {cv::Point2d(0.5, 0), cv::Point2d(-0.5, 0), cv::Point2d(0, 0.5), cv::Point2d(0, -0.5)})
    if (!planeToPixel(camera, *frame, offset, pixel)) return false;
  return true;
}

// The share of a grid of at most 64 x 64 pixels where a keypoint can be described: valid for
// the camera and, for descriptors that use the camera model (`descriptor` given), where the
// descriptor's plane projects (planeProjectsAround).
double describableShare(const Camera& camera, const DescriptorOptions* descriptor) {
  const cv::Size size = camera.imageSize();
  const int nx = std::min(size.width, 64), ny = std::min(size.height, 64);
  int usable = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const cv::Point2d p((i + 0.5) * size.width / nx - 0.5, (j + 0.5) * size.height / ny - 0.5);
      usable += camera.isValid(p) && (!descriptor || planeProjectsAround(camera, p, *descriptor));
    }
  return static_cast<double>(usable) / (nx * ny);
}

void requireReadableFile(const std::string& path) {
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw InputError(path + ": " + problem);
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0) throw InputError(path + ": the file is empty");
}

}  // namespace

void addCameraFileFlags(CLI::App& cmd, CameraFileFlags& flags, const std::string& prefix,
                        const std::string& formatFlag) {
  flags.prefix = prefix;
  cmd.add_option(formatFlag.empty() ? prefix + "-format" : formatFlag, flags.format,
                 "Format of the calibration file; auto recognises it from the content (configs/cameras/README.md)")
      ->check(CLI::IsMember(namesOf(kCameraFormatNames)))
      ->capture_default_str();
  cmd.add_option(prefix + "-id", flags.id,
                 "The camera of a calibration file that holds several: Kalibr cam0, cam1, ...; basalt's index; "
                 "ORB-SLAM3 1 or 2; COLMAP's CAMERA_ID");
  cmd.add_option(prefix + "-size", flags.size,
                 "Image size WxH of a calibration file without one (a FileStorage with K and D)");
  cmd.add_option(prefix + "-opencv-model", flags.opencvModel,
                 "Which model four OpenCV distortion coefficients are when the file does not say: fisheye "
                 "(cv::fisheye's k1..k4) or standard (k1 k2 p1 p2)")
      ->check(CLI::IsMember(namesOf(kOpenCvModelNames)))
      ->capture_default_str();
}

bool CameraFileFlags::anyGiven() const {
  return !id.empty() || format != toString(CameraFormat::Auto) || !size.empty() ||
         opencvModel != toString(OpenCvModel::Unstated);
}

std::string CameraFileFlags::flagNames() const {
  return prefix + "-format, " + prefix + "-id, " + prefix + "-size and " + prefix + "-opencv-model";
}

CameraFileOptions cameraFileOptions(const CameraFileFlags& flags) {
  CameraFileOptions options{parseCameraFormat(flags.format), flags.id, std::nullopt,
                            parseOpenCvModel(flags.opencvModel)};
  if (!flags.size.empty()) {
    options.imageSize = internal::parseSizeText(flags.size);
    if (!options.imageSize)
      throw InputError(flags.prefix + "-size must be WxH, two integers in [1, 1000000], got '" + flags.size + "'");
  }
  return options;
}

CameraFile readCalibrationFile(const CameraFileFlags& flags) {
  requireReadableFile(flags.path);
  const CameraFileOptions options = cameraFileOptions(flags);
  try {
    return readCameraFile(flags.path, options);
  } catch (const std::exception& e) {
    const std::string what = e.what();
    // loadCamera's messages already start with the path.
    throw InputError(what.rfind(flags.path, 0) == 0 ? what : flags.path + ": " + what);
  }
}

void addExtractionFlags(CLI::App& cmd, ExtractionFlags& flags) {
  cmd.add_option("--camera", flags.camera.path, "Calibration file (configs/cameras/README.md); required for dbrief/mdbrief")
      ->check(inputFileCheck());
  addCameraFileFlags(cmd, flags.camera, "--camera");
  cmd.add_option("--preset", flags.preset,
                 "Start from this preset's options (mdbrief/api/presets.hpp); the flags below change them")
      ->check(CLI::IsMember(namesOf(kPresetNames)))
      ->capture_default_str();
  flags.options.add(cmd, mdBriefOptionFields());
  cmd.add_flag("--allow-size-mismatch", flags.allowSizeMismatch,
               "Rescale the calibration to the image size instead of rejecting a different size");
  cmd.add_flag("--strict", flags.strict,
               "Reject a truncated (partly decodable) JPEG or PNG, or a JPEG with damaged data, instead of warning "
               "and describing what decodes");
}

MdBriefOptions extractionOptions(const ExtractionFlags& flags) {
  try {
    return flags.options.apply(presetSettings(parsePreset(flags.preset)).features,
                               [](const MdBriefOptions& o) { validate(o); });
  } catch (const OptionError& e) {
    throw InputError(e.what());
  }
}

CameraPtr loadCalibration(const ExtractionFlags& flags) {
  // The options first: a bad flag is reported before any file is read.
  const MdBriefOptions options = extractionOptions(flags);
  const DescriptorKind kind = options.descriptor.kind;
  const bool modelled = usesCamera(kind);
  if (flags.camera.path.empty()) {
    if (flags.camera.anyGiven())
      throw InputError(flags.camera.flagNames() + " need --camera (the calibration file they describe)");
    if (modelled) throw InputError("--camera is required for --descriptor " + toString(kind));
    // The library ignores the option without a camera: the output would be that of a run without it.
    if (options.detector.conformal)
      throw InputError("--conformal needs --camera (the stereographic view is the camera's)");
    return nullptr;
  }
  const CameraPtr camera = readCalibrationFile(flags.camera).camera;
  const double maxIncidenceDeg = options.descriptor.maxIncidenceDeg;
  if (const double share = describableShare(*camera, modelled ? &options.descriptor : nullptr);
      share < kFewPercentOfTheImage) {
    std::ostringstream percent;
    percent << std::fixed << std::setprecision(1) << 100.0 * share;
    std::ostringstream text;
    text << "warning: " << flags.camera.path << ": keypoints can be described on " << percent.str() << " % of the "
         << sizeText(camera->imageSize()) << " image (the camera's valid area";
    if (modelled)
      text << ", rays within " << maxIncidenceDeg << " degrees of the optical axis where the descriptor's plane projects";
    text << "); expect few or no keypoints\n";
    std::cerr << text.str();
  }
  return camera;
}

cv::Mat loadImage(const std::string& path, bool strict) {
  requireReadableFile(path);
  const std::string truncation = truncationProblem(path);
  if (!truncation.empty() && strict) throw InputError(path + ": " + truncation + " (--strict)");
  // Damage inside a complete JPEG, which OpenCV decodes with only libjpeg's unnamed warning:
  // refused under --strict before OpenCV runs, else named once the image decoded.
  const std::string damage = truncation.empty() ? jpegDataProblem(path) : "";
  if (!damage.empty() && strict) throw InputError(path + ": damaged JPEG: " + damage + " (--strict)");
  const cv::Mat image = decodeGreyImage(path);
  // One message for a failure (a truncated file said "describing the decodable part", then
  // "cannot decode"), naming an image too large to decode as such.
  if (image.empty()) {
    if (!truncation.empty())  // "truncated PNG (no IEND chunk)", without the claim that a part decodes
      throw InputError(path + ": cannot decode the image: " + truncation.substr(0, truncation.find(':')));
    if (const std::string size = imageSizeProblem(path); !size.empty())
      throw InputError(path + ": cannot decode the image: " + size);
    throw InputError(path + ": cannot decode the image (unsupported format or damaged file)");
  }
  if (!truncation.empty()) std::cerr << "warning: " << path << ": " << truncation << "; describing the decodable part\n";
  if (!damage.empty()) std::cerr << "warning: " << path << ": damaged JPEG: " << damage << "; describing what decodes\n";
  return image;
}

std::vector<cv::KeyPoint> loadKeypoints(const std::string& path) {
  requireReadableFile(path);
  const StorageReader storage(path);
  if (!storage.has("keypoints")) throw InputError(path + ": no node 'keypoints'");
  const std::vector<cv::KeyPoint> keypoints = storage.keypoints("keypoints");
  // The library drops such keypoints silently; a file that holds them is reported instead (the
  // reader refuses positions that are not finite).
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const cv::KeyPoint& k = keypoints[i];
    if (!(k.size > 0.f) || !std::isfinite(k.size))
      throw InputError(path + ": keypoint " + std::to_string(i) + " at (" + std::to_string(k.pt.x) + ", " +
                       std::to_string(k.pt.y) + ") with size " + std::to_string(k.size) +
                       ": a keypoint needs a positive finite size");
  }
  return keypoints;
}

cv::Ptr<MdBrief> makeFeature(const ExtractionFlags& flags, const CameraPtr& calibration,
                             const std::string& imagePath, cv::Size imageSize) {
  CameraPtr camera = calibration;
  if (camera && camera->imageSize() != imageSize) {
    if (!flags.allowSizeMismatch)
      throw InputError(imagePath + ": image size " + sizeText(imageSize) + " differs from the calibration " +
                       flags.camera.path + " (" + sizeText(camera->imageSize()) +
                       "); pass --allow-size-mismatch to rescale the calibration");
    // Another aspect ratio (752x480 against 480x752, a rotated image) stretches the lens, which
    // must be said. Rounding the sides may differ by a pixel.
    const cv::Size from = camera->imageSize();
    const double sx = static_cast<double>(imageSize.width) / from.width;
    const double sy = static_cast<double>(imageSize.height) / from.height;
    if (std::abs(sx - sy) * std::max(from.width, from.height) > 1.0)
      std::cerr << "warning: " << imagePath << ": image size " << sizeText(imageSize)
                << " has another aspect ratio than the calibration " << flags.camera.path << " (" << sizeText(from)
                << "): --allow-size-mismatch stretches it by " << sx << " across and " << sy << " down\n";
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

std::string cameraDigest(const Camera& camera) {
  const std::string yaml = cameraToYaml(camera);
  return contentDigest(yaml.data(), yaml.size());
}

std::string imageDigest(const cv::Mat& image) {
  const cv::Mat pixels = image.isContinuous() ? image : image.clone();
  return contentDigest(pixels.data, pixels.total() * pixels.elemSize());
}

std::string pyramidText(const PyramidOptions& options) {
  std::ostringstream text;
  text.imbue(std::locale::classic());
  text << std::setprecision(17);
  for (const OptionField<PyramidOptions>& f : pyramidOptionFields()) {
    const FieldValue value = f.get(options);
    text << (text.tellp() > 0 ? " " : "") << f.keyword << "=";
    if (const auto* i = std::get_if<long long>(&value)) text << *i;
    else text << std::get<double>(value);  // the table holds numbers only
  }
  return text.str();
}

PyramidOptions pyramidFromText(const std::string& text, const std::string& where) {
  const OptionTable<PyramidOptions>& table = pyramidOptionFields();
  PyramidOptions options;
  std::istringstream words(text);
  try {
    for (std::string word; words >> word;) {
      const std::size_t equals = word.find('=');
      const std::string key = word.substr(0, equals);
      const std::size_t field = findField(table, key, &OptionField<PyramidOptions>::keyword);
      if (equals == std::string::npos || field == table.size())
        throw InputError(where + ": '" + word + "' is no pyramid option (key=value of " + pyramidText({}) + ")");
      std::istringstream number(word.substr(equals + 1));
      number.imbue(std::locale::classic());
      double value = 0;
      if (!(number >> value) || !number.eof())
        throw InputError(where + ": " + key + " must be a number, got '" + word.substr(equals + 1) + "'");
      setField(table, field, options, value, key);
    }
    validate(options);
  } catch (const OptionError& e) {
    throw InputError(where + ": " + table.at(e.field()).keyword + " " + e.problem());
  }
  return options;
}

std::string descriptorDigest(const cv::Mat& descriptors) {
  // No descriptors are one value however they were stored (0 x 0 or 0 x bytes).
  const cv::Mat rows = descriptors.rows == 0    ? cv::Mat()
                       : descriptors.isContinuous() ? descriptors
                                                    : descriptors.clone();
  std::string bytes = std::to_string(rows.rows) + " x " + std::to_string(rows.cols) + " " +
                      std::to_string(rows.type()) + "\n";
  bytes.append(reinterpret_cast<const char*>(rows.data), rows.total() * rows.elemSize());
  return contentDigest(bytes.data(), bytes.size());
}

Features extractFeatures(const ExtractionFlags& flags, const CameraPtr& calibration, const std::string& imagePath,
                         const cv::Mat& image, const std::optional<std::vector<cv::KeyPoint>>& given) {
  const cv::Ptr<MdBrief> feature = makeFeature(flags, calibration, imagePath, image.size());
  Features f;
  const ComparisonSet& tests = feature->extractor().comparisonSet();
  f.provenance = {tests.name,
                  contentDigest(tests.tests.data(), tests.tests.size() * sizeof(ComparisonPair)),
                  calibration ? cameraDigest(*calibration) : "",
                  pyramidText(feature->options().detector.pyramid),
                  sizeText(image.size()),
                  imageDigest(image)};
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
