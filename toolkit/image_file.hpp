#pragma once
// Reading image files for the tools: the grey decoding every tool uses, and the check OpenCV's
// decoders do not make: a truncated JPEG or PNG decodes "successfully" with its missing part
// filled in, which would silently corrupt training patches, evaluations and extracted features.
#include <filesystem>
#include <string>

#include <opencv2/core/mat.hpp>

namespace mdbrief {

// "" when the file looks complete, else why not: a JPEG (FF D8 ...) must end with its EOI marker
// FF D9 (trailing zero padding allowed), a PNG with its IEND chunk. Other formats are not
// checked (""). An unreadable file gives "cannot read the file".
std::string truncationProblem(const std::filesystem::path& path);

// "" unless libjpeg reports damage in a JPEG file (its warnings, e.g. "Corrupt JPEG data: bad
// Huffman code", or an error), else its message. OpenCV decodes such a file and prints libjpeg's
// warning without the file's name (issue 29: a complete JPEG with flipped bits gave half the
// keypoints under --strict, exit 0). "" for other formats.
std::string jpegDataProblem(const std::filesystem::path& path);

// "" unless the image size a PNG's or a JPEG's header declares is beyond what OpenCV decodes (its
// CV_IO_MAX_IMAGE_PIXELS, default 2^30 pixels, and CV_IO_MAX_IMAGE_WIDTH / _HEIGHT, default
// 2^20), else the size and the limit it exceeds: OpenCV itself only fails to decode it.
std::string imageSizeProblem(const std::filesystem::path& path);

// The file decoded as 8-bit grey (cv::IMREAD_GRAYSCALE), or an empty Mat when it is missing or
// no decoder reads it (decoder exceptions included). Check truncationProblem first where a
// partly decoded image matters.
cv::Mat decodeGreyImage(const std::filesystem::path& path);

// Writes image atomically (mdbrief/internal/base/io/atomic_file.hpp) in the format of path's extension.
// Throws std::runtime_error naming path when there is no encoder for it or writing fails.
void writeImageAtomically(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace mdbrief
