#pragma once
// Reading and writing the CLI's files: OpenCV FileStorage files (format by extension: .yml,
// .yaml, .json, .xml, optionally .gz) and images. Writes are atomic: a temporary file in the
// target folder renamed over the target, so a failed run never leaves a half-written output.
// Every failure is an InputError naming the file.
#include <filesystem>
#include <functional>
#include <string>

#include <opencv2/core.hpp>

#include "cli/extraction_flags.hpp"

namespace mdbrief::cli {

// Throws InputError if the folder of path does not exist or the extension is not a
// FileStorage one.
void checkStorageOutput(const std::filesystem::path& path);
// The same for an image cv::imencode can write (by extension).
void checkImageOutput(const std::filesystem::path& path);

void writeStorageAtomically(const std::filesystem::path& path, const std::function<void(cv::FileStorage&)>& write);
void writeImageAtomically(const std::filesystem::path& path, const cv::Mat& image);

// Opens an existing FileStorage file for reading. OpenCV 4.6's YAML parser loops forever on some
// malformed files (fuzz/regressions/keypoints), so text files are checked before it sees them:
// none may hold a NUL byte, and YAML and JSON files must parse as YAML (yaml-cpp; JSON is YAML)
// with flow brackets nested at most 64 deep. XML and .gz files go to OpenCV unchecked.
cv::FileStorage openStorageForReading(const std::string& path);

// Nodes `keypoints` (cv::write), `descriptors` (N x bytes CV_8U) and, when not empty, `masks`
// (N x bytes CV_8U).
void writeFeatureFile(const std::filesystem::path& path, const Features& features);
// Reads a file written by writeFeatureFile; `keypoints` and `masks` are optional, descriptors
// required. Checks types and that the rows agree.
Features readFeatureFile(const std::string& path);

}  // namespace mdbrief::cli
