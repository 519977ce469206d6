#pragma once
// The detection/description flags shared by `extract` and `draw`, and the input loading both
// need (images, calibration, keypoint files), each failing with an InputError naming the file.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "toolkit/option_flags.hpp"

namespace mdbrief::cli {

// A calibration file, its format, the camera of a multi-camera file, the image size of a file
// without one and the model of four OpenCV coefficients (camera/io.hpp CameraFileOptions).
struct CameraFileFlags {
  std::string path;
  std::string format = toString(CameraFormat::Auto);
  std::string id;
  std::string size;                                       // WxH; empty: the file's
  std::string opencvModel = toString(OpenCvModel::Unstated);
  // The flags' common start on this command: "--camera" names --camera-id, --camera-size, ...;
  // a second image's camera has its own ("--camera-b").
  std::string prefix = "--camera";
  // Whether any of the flags besides the path was given.
  bool anyGiven() const;
  // "--camera-format, --camera-id, --camera-size and --camera-opencv-model", for messages.
  std::string flagNames() const;
};

// Adds <prefix>-id, <prefix>-size and <prefix>-opencv-model, and the format option (formatFlag;
// empty: <prefix>-format), bound to flags, whose prefix becomes `prefix`.
void addCameraFileFlags(CLI::App& cmd, CameraFileFlags& flags, const std::string& prefix,
                        const std::string& formatFlag = "");

// The options the flags give the file's reader (all but the path). InputError for a bad size.
CameraFileOptions cameraFileOptions(const CameraFileFlags& flags);

// The calibration of flags.path. InputError naming the file and the problem (loadCamera's
// messages, which start with the path).
CameraFile readCalibrationFile(const CameraFileFlags& flags);

// The detection and description options are MdBriefOptions' field table (mdBriefOptionFields()):
// every field's flag, doc, range and default come from there.
struct ExtractionFlags {
  CameraFileFlags camera;             // --camera (required except for --descriptor brief / mbrief), --camera-format, --camera-id
  std::string preset = "tracking";    // the options the flags start from (mdbrief/api/presets.hpp)
  OptionFlags<MdBriefOptions> options;
  bool allowSizeMismatch = false;     // rescale the calibration to the image instead of failing
  bool strict = false;                // a truncated image file is an error, not a warning
};

// Adds --camera, --camera-format, --camera-id, --preset, every MdBriefOptions flag (--nfeatures, --detector, --descriptor,
// --bits, ...), --allow-size-mismatch and --strict to cmd, bound to flags (which must outlive the parse and
// stay in place).
void addExtractionFlags(CLI::App& cmd, ExtractionFlags& flags);

// The preset's options with the flags applied, validated. InputError "<flag> must be in [...],
// got <value>".
MdBriefOptions extractionOptions(const ExtractionFlags& flags);

// The calibration of flags.camera.path, or null when none is given (allowed for brief and mbrief,
// without --conformal). Checks the option flags first (extractionOptions). Warns on stderr,
// naming the file, when the camera leaves a few percent of the image or less where keypoints
// can be described.
CameraPtr loadCalibration(const ExtractionFlags& flags);

// Decoded 8UC1 image. InputError for a missing, empty or undecodable file. A truncated JPEG or
// PNG (decoded only partly) gives a warning naming the file on stderr, or with `strict` an
// InputError.
cv::Mat loadImage(const std::string& path, bool strict);

// The keypoints of node `keypoints` of an OpenCV FileStorage file. InputError naming the file and
// the keypoint for a non-finite position or a size that is not a positive finite number.
std::vector<cv::KeyPoint> loadKeypoints(const std::string& path);

// What a feature file's descriptors were made with, so that match can refuse files it cannot
// compare: two test sets, or --inliers --camera naming another lens, would go unnoticed; and what
// `match --refine` needs to rebuild the pyramid the keypoints' octaves index, from the same image.
// Empty in files written before it was recorded, which are still read.
struct Provenance {
  std::string testSet;        // the test set's name
  std::string testSetDigest;  // contentDigest of its tests as used (the first bits of them)
  std::string cameraDigest;   // cameraDigest of the calibration given; "" without one
  std::string pyramid;        // pyramidText of the detection's pyramid options
  std::string imageSize;      // "WxH" of the image described
  std::string imageDigest;    // imageDigest of it
};

struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  cv::Mat masks;  // mdBRIEF only
  Provenance provenance;
};

// The content digest (toolkit/content_digest.hpp) of the camera's project YAML (cameraToYaml): the same lens gives the same digest
// whatever file format it came from.
std::string cameraDigest(const Camera& camera);
// contentDigest of a decoded image's pixels: the same picture in another file or format is the
// same image, another picture of the same size is not.
std::string imageDigest(const cv::Mat& image);

// Pyramid options as "levels=8 scale_factor=1.2 ..." (pyramidOptionFields()' keywords, reals to
// 17 digits so that they read back exactly), and back. pyramidFromText starts from the defaults
// (a key added in a later version keeps its default in older files) and throws InputError
// naming `where` for an unknown key, a value that is no number or one out of its range.
std::string pyramidText(const PyramidOptions& options);
PyramidOptions pyramidFromText(const std::string& text, const std::string& where);

// contentDigest of a descriptor matrix, its shape included: match records each side's, so that
// draw can tell whether its images, described with its flags, are the ones that were matched.
std::string descriptorDigest(const cv::Mat& descriptors);

// Detects and describes the image at imagePath (or describes `given` keypoints) with the
// flags; the calibration must match the image size unless flags.allowSizeMismatch.
Features extractFeatures(const ExtractionFlags& flags, const CameraPtr& calibration, const std::string& imagePath,
                         const cv::Mat& image, const std::optional<std::vector<cv::KeyPoint>>& given);

// The descriptor extractor extractFeatures would use (for drawing test positions).
cv::Ptr<MdBrief> makeFeature(const ExtractionFlags& flags, const CameraPtr& calibration,
                             const std::string& imagePath, cv::Size imageSize);

}  // namespace mdbrief::cli
