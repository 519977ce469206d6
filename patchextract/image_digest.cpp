#include "patchextract/image_digest.hpp"

#include <sstream>
#include <stdexcept>

#include "mdbrief/internal/base/io/input_file.hpp"
#include "toolkit/content_digest.hpp"
#include "toolkit/image_file.hpp"

namespace mdbrief::train {

// The text of configs/held-out-images.txt, generated into the build tree by CMake.
extern const char* const kShippedHeldOutText;

std::string imageDigest(const cv::Mat& grey) {
  if (grey.empty() || grey.type() != CV_8UC1) throw std::invalid_argument("imageDigest: need a non-empty 8UC1 image");
  uint8_t size[8];  // width and height, 4 bytes each, little-endian
  for (int b = 0; b < 4; ++b) {
    size[b] = static_cast<uint8_t>(static_cast<uint32_t>(grey.cols) >> (8 * b));
    size[4 + b] = static_cast<uint8_t>(static_cast<uint32_t>(grey.rows) >> (8 * b));
  }
  ContentDigest digest;
  digest.add(size, sizeof size);
  for (int y = 0; y < grey.rows; ++y) digest.add(grey.ptr<uint8_t>(y), grey.cols);
  return digest.hex();
}

std::string imageFileDigest(const std::filesystem::path& path) {
  const cv::Mat grey = decodeGreyImage(path);
  return grey.empty() ? std::string() : imageDigest(grey);
}

HeldOutImages parseHeldOutImages(const std::string& text, const std::string& source) {
  HeldOutImages out;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::string digest, label;
    if (!(fields >> digest)) continue;
    std::getline(fields >> std::ws, label);
    if (digest.size() != 16 || digest.find_first_not_of("0123456789abcdef") != std::string::npos)
      throw std::runtime_error(source + ":" + std::to_string(number) + ": '" + digest +
                               "' is not a digest (16 lower-case hex digits)");
    out.emplace(digest, label.empty() ? digest : label);
  }
  return out;
}

HeldOutImages readHeldOutImages(const std::filesystem::path& path) {
  // 64 MiB hold about two million lines; /dev/zero or a FIFO is refused, not read without end.
  return parseHeldOutImages(internal::readInputFile(path, std::uintmax_t{64} << 20, "held-out list"), path.string());
}

const HeldOutImages& shippedHeldOutImages() {
  static const HeldOutImages images = parseHeldOutImages(kShippedHeldOutText, "configs/held-out-images.txt");
  return images;
}

}  // namespace mdbrief::train
