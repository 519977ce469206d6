#pragma once
// Identity of an image by its content, for keeping training and evaluation images apart: the
// same photo under another name (opencv-doc's graf1.png is Oxford graf img1.png) or format
// has the same digest, a file name does not matter.
#include <filesystem>
#include <map>
#include <string>

#include <opencv2/core.hpp>

namespace mdbrief::train {

// The content digest (toolkit/content_digest.hpp) of the width and the height (4 bytes each,
// little-endian) and the grey pixels row by row (as cv::IMREAD_GRAYSCALE decodes the file). Throws std::invalid_argument for an empty or non-8UC1 image.
std::string imageDigest(const cv::Mat& grey);
// Decodes the file grey; "" if it cannot be decoded.
std::string imageFileDigest(const std::filesystem::path& path);

// digest -> what uses the image (e.g. "oxford-affine/graf/img1.png").
using HeldOutImages = std::map<std::string, std::string>;

// The images every shipped evaluation uses (configs/held-out-images.txt, compiled into the tools).
const HeldOutImages& shippedHeldOutImages();

// A held-out list: one "<digest> <label>" per line; '#' starts a comment. Throws
// std::runtime_error naming the file and line for a malformed digest.
HeldOutImages parseHeldOutImages(const std::string& text, const std::string& source);
HeldOutImages readHeldOutImages(const std::filesystem::path& path);

}  // namespace mdbrief::train
