#pragma once
// A set of training patches and its HDF5 file.
//
// File layout (libhdf5 C API):
//   /patches      N x 32 x 32 uint8   the patches (pixel (x, y) at [n][y][x], keypoint at (16, 16))
//   /images       uint8: the M source image paths, each NUL-terminated
//   /image_digests uint8: imageDigest of each image, NUL-terminated (optional; "" = unreadable)
//   /image        N int32   index into /images
//   /x, /y        N float32 keypoint position, level-0 pixels
//   /scale        N float32 patch diameter in level-0 pixels (31 = ORB level 0 = step 1)
//   /angle        N float32 degrees, cv::KeyPoint convention (-1 = none), as compute() leaves
//                 it (re-measured when the placement re-measures it)
//   /response     N float32 detector response
//   /detector     N uint8   index into the root attribute "detectors" ("orb,akaze,surf")
//   /counterparts         Q x 32 x 32 uint8  optional: the same keypoints seen in changed views
//   /counterpart_of       Q int32            index into /patches of each counterpart
//   root attributes: string key/value pairs with the extraction settings.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mdbrief::train {

struct PatchRecord {
  int32_t image = 0;
  float x = 0, y = 0, scale = 0, angle = -1, response = 0;
  uint8_t detector = 0;
};

struct PatchSet {
  std::vector<uint8_t> pixels;            // count() x 1024
  std::vector<std::string> images;
  std::vector<std::string> imageDigests;  // one per image (image_digest.hpp), or empty (old files)
  std::vector<PatchRecord> records;
  std::vector<std::pair<std::string, std::string>> attributes;  // settings, in order
  // Stability data (patch_extraction.hpp, ExtractionOptions::counterparts): counterpartCount()
  // x 1024 pixels, and for each the index of its reference patch, ascending.
  std::vector<uint8_t> counterpartPixels;
  std::vector<int32_t> counterpartOf;

  size_t count() const { return records.size(); }
  // Sorted digests of the images that gave at least one patch (empty if the file has none).
  std::vector<std::string> usedImageDigests() const;
  size_t counterpartCount() const { return counterpartOf.size(); }
};

// Written atomically (temporary file in the same folder, then rename); no timestamps in the
// file. Throws std::runtime_error naming the path on failure (missing folder, write error).
void writePatchSet(const PatchSet& set, const std::filesystem::path& path);
// Throws std::runtime_error naming the path when writePatchSet could not write there (no such
// folder, not writable, not a regular file) or path is one of inputs under any name
// (internal::checkOutputsApart): for tools to check before extracting.
void checkPatchSetOutput(const std::filesystem::path& path, const std::vector<std::filesystem::path>& inputs = {});
// Throws std::runtime_error naming the path and the problem (not HDF5, missing dataset,
// inconsistent sizes, index out of range).
PatchSet readPatchSet(const std::filesystem::path& path);

}  // namespace mdbrief::train
