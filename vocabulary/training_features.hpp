#pragma once
// The features a vocabulary is trained on and evaluated with, computed exactly as the run time
// computes them: a preset's MdBrief (detectAndComputeWithMasks, any descriptor length), or
// cv::ORB for the comparison with ORB vocabularies. And the training images: image files by
// folder, each identified by its digest and refused when an evaluation holds it out.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "mdbrief/camera/camera.hpp"
#include "mdbrief/api/presets.hpp"
#include "mdbrief/detect/detector.hpp"
#include "patchextract/image_digest.hpp"
#include "vocabulary/vocabulary_training.hpp"

namespace mdbrief::vocab {

enum class FeatureKind { MdBrief, Orb };
inline constexpr EnumName<FeatureKind> kFeatureKindNames[] = {{FeatureKind::MdBrief, "mdbrief"}, {FeatureKind::Orb, "orb"}};

struct FeatureOptions {
  FeatureKind kind = FeatureKind::MdBrief;
  Preset preset = Preset::Tracking;  // MdBrief: the preset's features
  int bits = 0;                      // MdBrief: 0 = the preset's length, else 32..512 in steps of 32
  int nfeatures = DetectorOptions{}.nfeatures;  // keypoints per image at most (MdBrief: detector.nfeatures)
};

// The preset's options with bits and nfeatures applied. Throws OptionError for bad values.
MdBriefOptions mdBriefOptions(const FeatureOptions& options);

// Features of one grey image: descriptors (N x bytes CV_8UC1) and, for mdBRIEF, masks. camera:
// the image's (MdBrief); null takes the photo camera of the image's size (scenes/photo_camera.hpp).
// region: empty or where keypoints may be (CV_8UC1 of the image's size).
TrainingImage describeImage(const cv::Mat& grey, const FeatureOptions& options, const CameraPtr& camera,
                            const cv::Mat& region = {});

// The image files of `paths`: a folder gives its images (png, jpg, jpeg, pgm, ppm, bmp, tif,
// tiff, any depth), a file itself; sorted, without repeats. Throws std::invalid_argument naming
// a path that does not exist or a folder without images.
std::vector<std::filesystem::path> imageFiles(const std::vector<std::string>& paths);

// The image decoded grey with its digest set. Throws std::invalid_argument naming the file when
// it cannot be decoded, is truncated, or is held out (heldOut: digest -> what uses it).
cv::Mat readTrainingImage(const std::filesystem::path& path, const train::HeldOutImages& heldOut, uint64_t& digest);

// A digest (16 hex digits) as the number the vocabulary records.
uint64_t digestNumber(const std::string& digest);

}  // namespace mdbrief::vocab
