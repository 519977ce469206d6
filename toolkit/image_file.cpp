#include "toolkit/image_file.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "mdbrief/internal/atomic_file.hpp"

namespace mdbrief {

std::string truncationProblem(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return "cannot read the file";
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const auto startsWith = [&](std::initializer_list<unsigned char> sig) {
    return bytes.size() >= sig.size() && std::equal(sig.begin(), sig.end(), bytes.begin());
  };
  if (startsWith({0xFF, 0xD8})) {
    size_t end = bytes.size();
    while (end > 2 && bytes[end - 1] == 0) --end;  // some writers pad after EOI
    return end >= 4 && bytes[end - 2] == 0xFF && bytes[end - 1] == 0xD9
               ? ""
               : "truncated JPEG (no end-of-image marker): only part of it can be decoded";
  }
  if (startsWith({0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A})) {
    static const std::array<unsigned char, 12> iend{0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    return bytes.size() >= 8 + iend.size() && std::equal(iend.begin(), iend.end(), bytes.end() - iend.size())
               ? ""
               : "truncated PNG (no IEND chunk): only part of it can be decoded";
  }
  return "";
}

cv::Mat decodeGreyImage(const std::filesystem::path& path) {
  try {
    return cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception&) {
    return {};  // some decoders throw on damaged files instead of returning nothing
  }
}

void writeImageAtomically(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  bool encoded = false;
  try {
    encoded = cv::imencode(path.extension().string(), image, bytes);
  } catch (const cv::Exception&) {
  }
  if (!encoded) throw std::runtime_error(path.string() + ": cannot encode the image in this format");
  internal::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

}  // namespace mdbrief
