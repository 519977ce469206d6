#pragma once
// Patch extraction for the trainer: images -> keypoints -> a budget of 32x32 patches spread
// over the images and over keypoint strengths, reproducible from the seed.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "patchextract/image_digest.hpp"
#include "patchextract/keypoint_detectors.hpp"
#include "patchextract/patch_set.hpp"
#include "patchextract/view_change.hpp"

namespace mdbrief::train {

// The largest detector budget per image (the upper bound of its field in
// extractionOptionFields()): the detectors reserve room for the whole budget up front, and no
// image has more corners than this.
inline constexpr int kMaxKeypointsPerImage = 1'000'000;

struct ExtractionOptions {
  std::vector<std::filesystem::path> imageDirs;  // searched recursively
  DetectorKind detector = DetectorKind::Orb;
  size_t patches = 20000;        // budget; fewer when the images do not have that many keypoints
  uint32_t seed = 1;             // drives the choice of keypoints within each image
  std::string cameraPath;        // calibration (mdbrief/camera/io.hpp); empty = perspective
  CameraFormat cameraFormat = CameraFormat::Auto;  // its format; auto: recognised from the content
  std::string cameraId;          // the camera of a file that holds several (CameraFileOptions::cameraId)
  int keypointsPerImage = 1000;  // detector budget per image, the pool patches are drawn from; 1..kMaxKeypointsPerImage
  // Fisheye training without fisheye photos: each image becomes the texture of a
  // fronto-parallel plane seen through the camera (renderPlane, 2x2 supersampling), its width
  // spanning +-renderHalfFovDeg, and keypoints are detected on that rendering. Needs cameraPath.
  bool renderThroughCamera = false;
  double renderHalfFovDeg = 60.0;
  // Stability data: each image is also seen in `counterparts` random view changes
  // (view_change.hpp); the detector runs on every view, and a keypoint is kept only if some view
  // has a keypoint where the change puts it, at the size the change predicts. Its patch then has
  // one counterpart patch per such view, sampled at the view keypoint's own position, size and
  // angle: the errors a detector really makes. 0 = reference patches only (the paper's data).
  int counterparts = 0;
  ViewChangeOptions viewChange;
  // A view keypoint matches when it lies within this many pixels of the predicted position, in
  // units of the keypoint's sampling step (size / 31), and its size within this ratio of the
  // predicted one: one pyramid level of ORB (1.2) plus the zoom's in-between values.
  double matchRadius = 2.5;
  double matchSizeRatio = 1.3;
  // How patches are placed and sampled: the descriptor the set is learned for
  // (patchextract/patch_sampler.hpp). The defaults are compute()'s defaults (mdBRIEF, Affine
  // form, orientation re-measured on the tangent plane), so the sets are learned on the patches
  // they are used on; images without cameraPath go through the photo camera.
  DescriptorOptions placement;
  // Images never to train on (by content digest): the shipped evaluations' images
  // (shippedHeldOutImages()) plus any a caller adds. They are skipped and reported.
  HeldOutImages heldOut = shippedHeldOutImages();
};

// At most this many changed views per image: each one is a full rendering and detection.
inline constexpr int kMaxCounterparts = 8;

// The fields of ExtractionOptions that users set (mdbrief/base/option_fields.hpp); heldOut, the
// rendering's field of view and the match tolerances are not options.
const OptionTable<ExtractionOptions>& extractionOptionFields();
// Throws OptionError naming the first option out of its range.
void validate(const ExtractionOptions& options);

struct SkippedImage {
  std::string path;
  std::string reason;
  bool heldOut = false;     // an evaluation uses it
  bool otherSize = false;   // its size does not match the camera's (nor its aspect ratio)
};

struct ExtractionReport {
  size_t imagesFound = 0;
  size_t imagesUsed = 0;          // images that gave at least one patch
  std::vector<SkippedImage> skipped;  // includes the held-out ones
  size_t heldOut = 0;                 // images skipped because an evaluation uses them
  size_t usableKeypoints = 0;     // keypoints whose whole patch could be sampled (and, with
                                  // counterparts, that were found again in a view)
  size_t detectedInViews = 0;     // with counterparts: usable keypoints before the view check
  double seconds = 0;
};

// Image files (png, jpg, jpeg, pgm, ppm, bmp, tif, tiff; any case) under the folders, sorted.
// Throws std::invalid_argument naming the folder if one does not exist or none holds images.
std::vector<std::filesystem::path> listImages(const std::vector<std::filesystem::path>& dirs);

// How many patches each image gives: as equal a share of the budget as the images allow (an
// image with fewer usable keypoints gives all of them, the rest is shared by the others).
std::vector<size_t> allocatePatches(const std::vector<size_t>& available, size_t budget);

// stage: "detect" or "sample"; called from worker threads (must be thread-safe).
using ExtractionProgress = std::function<void(const char* stage, size_t done, size_t total)>;

// Throws std::invalid_argument (bad folders, unknown camera file: std::runtime_error from
// loadCamera). Unreadable images and images without usable keypoints are skipped and reported.
// Within an image, the chosen keypoints are evenly spaced over the strength ranks with a
// random (seeded) phase. Records and patches are ordered by image, then strength.
PatchSet extractPatches(const ExtractionOptions& options, ExtractionReport& report,
                        const ExtractionProgress& progress = {});

}  // namespace mdbrief::train
