#pragma once
// Patch extraction for the trainer: images -> keypoints -> a budget of 32x32 patches spread
// over the images and over keypoint strengths, reproducible from the seed.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "patchextract/keypoint_detectors.hpp"
#include "patchextract/patch_set.hpp"

namespace mdbrief::train {

struct ExtractionOptions {
  std::vector<std::filesystem::path> imageDirs;  // searched recursively
  DetectorKind detector = DetectorKind::Orb;
  size_t patches = 20000;        // budget; fewer when the images do not have that many keypoints
  uint32_t seed = 1;             // drives the choice of keypoints within each image
  std::string cameraPath;        // calibration (mdbrief/camera_io.hpp); empty = perspective
  int keypointsPerImage = 1000;  // detector budget per image, the pool patches are drawn from
  // Fisheye training without fisheye photos: each image becomes the texture of a
  // fronto-parallel plane seen through the camera (renderPlane, 2x2 supersampling), its width
  // spanning +-renderHalfFovDeg, and keypoints are detected on that rendering. Needs cameraPath.
  bool renderThroughCamera = false;
  double renderHalfFovDeg = 60.0;
};

struct SkippedImage {
  std::string path;
  std::string reason;
};

struct ExtractionReport {
  size_t imagesFound = 0;
  size_t imagesUsed = 0;          // images that gave at least one patch
  std::vector<SkippedImage> skipped;
  size_t usableKeypoints = 0;     // keypoints whose whole patch could be sampled
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
