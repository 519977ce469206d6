#include "mdbrief/match/hamming.hpp"

#include <cstring>
#include <stdexcept>

#include "mdbrief/internal/base/popcount.hpp"

namespace mdbrief {

void validateDescriptorMatrix(const cv::Mat& m, const std::string& name) {
  if (m.rows == 0) return;  // no descriptors (0 x 0 or 0 x bytes); N x 0 is refused below
  if (m.type() != CV_8UC1) {
    throw std::invalid_argument(name + ": descriptors must be CV_8UC1, got " +
                                cv::typeToString(m.type()));
  }
  if (m.dims != 2 || m.cols < kMinDescriptorBytes || m.cols > kMaxDescriptorBytes ||
      m.cols % 4 != 0) {
    throw std::invalid_argument(name + ": descriptor width must be a multiple of 4 in [4, 64] "
                                       "bytes, got " + std::to_string(m.cols));
  }
}

int hammingDistance(const uint8_t* a, const uint8_t* b, int bytes) noexcept {
  int distance = 0;
  int i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t x, y;  // memcpy: rows need not be 8-byte aligned
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    distance += popcount64(x ^ y);
  }
  if (i < bytes) {  // widths like 36 bytes end with one 32-bit word
    uint32_t x, y;
    std::memcpy(&x, a + i, 4);
    std::memcpy(&y, b + i, 4);
    distance += popcount64(x ^ y);
  }
  return distance;
}

namespace {
void requireRow(const cv::Mat& m, const char* name) {
  if (m.empty()) throw std::invalid_argument(std::string(name) + ": empty descriptor");
  validateDescriptorMatrix(m, name);
  if (m.rows != 1) {
    throw std::invalid_argument(std::string(name) + ": expected a single row, got " +
                                std::to_string(m.rows) + " rows");
  }
}
}  // namespace

int hammingDistance(const cv::Mat& a, const cv::Mat& b) {
  requireRow(a, "a");
  requireRow(b, "b");
  if (a.cols != b.cols) {
    throw std::invalid_argument("b: width " + std::to_string(b.cols) +
                                " bytes differs from a's " + std::to_string(a.cols));
  }
  return hammingDistance(a.ptr<uint8_t>(0), b.ptr<uint8_t>(0), a.cols);
}

}  // namespace mdbrief
