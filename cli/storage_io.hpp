#pragma once
// Reading and writing the CLI's files: OpenCV FileStorage files (format by extension: .yml,
// .yaml, .json, .xml, optionally .gz) and images. Writes are atomic: a temporary file in the
// target folder renamed over the target, so a failed run never leaves a half-written output.
// Every failure is an InputError naming the file.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include "cli/extraction_flags.hpp"

namespace mdbrief::cli {

// Throws InputError if the folder of path does not exist or the extension is not a
// FileStorage one.
void checkStorageOutput(const std::filesystem::path& path);
// The same for an image cv::imencode can write (by extension).
void checkImageOutput(const std::filesystem::path& path);

// internal::checkOutputsApart as an InputError: no output may be an input (under any name) or
// another output. Empty paths are skipped.
void checkOutputsApart(const std::vector<std::filesystem::path>& inputs,
                       const std::vector<std::filesystem::path>& outputs);

void writeStorageAtomically(const std::filesystem::path& path, const std::function<void(cv::FileStorage&)>& write);
void writeImageAtomically(const std::filesystem::path& path, const cv::Mat& image);

// The largest text StorageReader parses, by parser: a yaml-cpp node takes far more memory than
// an OpenCV one, so YAML and JSON are held to less than XML and .gz (whose decompressed text
// counts). Above the limit the file is refused before it is parsed (docs/RESULTS.md
// "Input size limits").
inline constexpr std::uintmax_t kMaxYamlCppTextBytes = std::uintmax_t{8} << 20;
inline constexpr std::uintmax_t kMaxOpenCvTextBytes = std::uintmax_t{256} << 20;

// An existing FileStorage file opened for reading its top-level nodes. OpenCV 4.6's YAML parser
// loops forever on some damaged files (fuzz/regressions/keypoints), so YAML and JSON never reach
// it: they are parsed by yaml-cpp (JSON is YAML) after two checks, no NUL byte and nesting at
// most internal::kMaxNesting deep (yaml-cpp recurses once per level). XML and .gz files go to
// cv::FileStorage, their text (decompressed) checked for the same nesting first (OpenCV's
// parsers recurse too). Text over the limits above is refused unparsed. Every failure is an
// InputError naming the file and the node.
class StorageReader {
 public:
  explicit StorageReader(const std::string& path);
  ~StorageReader();
  StorageReader(const StorageReader&) = delete;
  StorageReader& operator=(const StorageReader&) = delete;

  // True if the top-level node exists and is not empty.
  bool has(const std::string& key) const;
  // A keypoint list as cv::write stores it: a sequence of (x, y, size, angle, response,
  // octave, class_id) sequences, or the same 7 numbers per keypoint in one flat sequence. A
  // position that is not finite is an InputError naming the keypoint.
  std::vector<cv::KeyPoint> keypoints(const std::string& key) const;
  // A single-channel 2-D matrix as cv::FileStorage stores it (opencv-matrix: rows, cols, dt in
  // u, c, w, s, i, f, d, and rows x cols values in data).
  cv::Mat matrix(const std::string& key) const;
  // A scalar node as text, "" when it is missing.
  std::string text(const std::string& key) const;

 private:
  struct Parsed;
  std::string path_;
  std::unique_ptr<Parsed> parsed_;
};

// features[i] into paths[i], nodes `keypoints` (cv::write), `descriptors` (N x bytes CV_8U),
// when not empty `masks` (N x bytes CV_8U), and the provenance: `test_set`, `test_set_digest`
// and, with a calibration, `camera_digest`. The files are replaced as one set: a failure leaves
// every previous file.
void writeFeatureFiles(const std::vector<std::filesystem::path>& paths, const std::vector<Features>& features);
// Reads a file written by writeFeatureFiles; `keypoints` and `masks` are optional, descriptors
// required. Checks types and that the rows agree.
Features readFeatureFile(const std::string& path);

}  // namespace mdbrief::cli
