#pragma once
// Descriptor files for mdbrief-train-vocabulary: NumPy .npy arrays (numpy.save) of dtype uint8
// and shape (N, B) in C order, N descriptors of B bytes (B a multiple of 4 in [4, 64]); one file
// per image, its masks in a second file of the same shape. The parser reads format versions 1 to
// 3 and checks every field and that the data fills the rest of the file exactly.
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief::vocab {

// N x B CV_8UC1. Throws FileFormatError (mdbrief/base/file_format_error.hpp) naming the file and the
// problem (not .npy, another dtype, Fortran order, a shape that is not (N, B), a size that
// differs from the shape's).
cv::Mat readDescriptorNpy(const std::string& path);

// The .npy bytes of an N x B CV_8UC1 matrix (version 1.0), for tests and tools that write them.
std::string descriptorNpyBytes(const cv::Mat& descriptors);

}  // namespace mdbrief::vocab
