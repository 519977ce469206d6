#include "mdbrief/match/masked_hamming.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include "mdbrief/match/hamming.hpp"
#include "mdbrief/internal/base/popcount.hpp"

namespace mdbrief {

namespace {
// An all-zero mask acts as all ones (masked_hamming.hpp), so the word is replaced accordingly.
inline uint64_t effectiveMask(uint64_t word, bool allZero) { return allZero ? ~uint64_t{0} : word; }

int countOnes(const uint8_t* mask, int bytes) {
  int ones = 0;
  for (int i = 0; i < bytes; i += 4) {
    uint32_t w;
    std::memcpy(&w, mask + i, 4);
    ones += popcount64(w);
  }
  return ones;
}
}  // namespace

uint32_t maskedHammingFixed(const uint8_t* di, const uint8_t* li, const uint8_t* dj,
                            const uint8_t* lj, int bytes) noexcept {
  const int nbits = bytes * 8;
  const int oi = countOnes(li, bytes);
  const int oj = countOnes(lj, bytes);
  uint32_t a = 0, b = 0;
  // 32-bit words keep the loop free of a tail case; this form is not the matcher's hot path.
  for (int k = 0; k < bytes; k += 4) {
    uint32_t x1, x2, m1, m2;
    std::memcpy(&x1, di + k, 4);
    std::memcpy(&x2, dj + k, 4);
    std::memcpy(&m1, li + k, 4);
    std::memcpy(&m2, lj + k, 4);
    const uint64_t x = x1 ^ x2;
    a += popcount64(x & effectiveMask(m1, oi == 0));
    b += popcount64(x & effectiveMask(m2, oj == 0));
  }
  return a * maskWeight(oi, nbits) + b * maskWeight(oj, nbits);
}

namespace {
void requireRow(const cv::Mat& m, const char* name, int cols) {
  if (m.empty()) throw std::invalid_argument(std::string(name) + ": empty row");
  validateDescriptorMatrix(m, name);
  if (m.rows != 1) {
    throw std::invalid_argument(std::string(name) + ": expected a single row, got " +
                                std::to_string(m.rows) + " rows");
  }
  if (cols >= 0 && m.cols != cols) {
    throw std::invalid_argument(std::string(name) + ": width " + std::to_string(m.cols) +
                                " bytes differs from di's " + std::to_string(cols));
  }
}
}  // namespace

float maskedHammingDistance(const cv::Mat& di, const cv::Mat& li, const cv::Mat& dj,
                            const cv::Mat& lj) {
  requireRow(di, "di", -1);
  requireRow(li, "li", di.cols);
  requireRow(dj, "dj", di.cols);
  requireRow(lj, "lj", di.cols);
  return maskedFixedToBits(maskedHammingFixed(di.ptr<uint8_t>(0), li.ptr<uint8_t>(0),
                                              dj.ptr<uint8_t>(0), lj.ptr<uint8_t>(0), di.cols));
}

}  // namespace mdbrief
