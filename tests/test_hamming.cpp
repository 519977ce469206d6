// Plain and masked Hamming distances against bit-by-bit reference implementations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "mdbrief/match/hamming.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "test_data.hpp"

namespace {

bool bit(const cv::Mat& row, int d) { return (row.at<uint8_t>(0, d / 8) >> (d % 8)) & 1; }

int refHamming(const cv::Mat& a, const cv::Mat& b) {
  int count = 0;
  for (int d = 0; d < a.cols * 8; ++d) count += bit(a, d) != bit(b, d);
  return count;
}

// The paper's formula in double, scaled to bits (nbits / 2); an all-zero mask counts as ones.
double refMasked(const cv::Mat& di, const cv::Mat& li, const cv::Mat& dj, const cv::Mat& lj) {
  const int nbits = di.cols * 8;
  int oi = 0, oj = 0;
  for (int d = 0; d < nbits; ++d) {
    oi += bit(li, d);
    oj += bit(lj, d);
  }
  int a = 0, b = 0;
  for (int d = 0; d < nbits; ++d) {
    const bool x = bit(di, d) != bit(dj, d);
    a += x && (oi == 0 || bit(li, d));
    b += x && (oj == 0 || bit(lj, d));
  }
  const double hi = static_cast<double>(a) / (oi == 0 ? nbits : oi);
  const double hj = static_cast<double>(b) / (oj == 0 ? nbits : oj);
  return nbits / 2.0 * (hi + hj);
}

// Bound stated in masked_hamming.hpp: fixed-point error plus float rounding of the result.
double maskedTolerance(int nbits) { return nbits / std::ldexp(1.0, 22) + nbits * std::ldexp(1.0, -24); }

// A row with each bit set with probability p.
cv::Mat randomRow(int bytes, double p, std::mt19937& rng) {
  std::bernoulli_distribution coin(p);
  cv::Mat row(1, bytes, CV_8UC1, cv::Scalar(0));
  for (int d = 0; d < bytes * 8; ++d) {
    if (coin(rng)) row.at<uint8_t>(0, d / 8) |= static_cast<uint8_t>(1u << (d % 8));
  }
  return row;
}

// A row that starts at an odd address (ROI of a wider matrix), to exercise unaligned reads.
cv::Mat unalignedCopy(const cv::Mat& row) {
  cv::Mat wide(1, row.cols + 1, CV_8UC1, cv::Scalar(0xAB));
  cv::Mat roi = wide.colRange(1, row.cols + 1);
  row.copyTo(roi);
  return roi;
}

template <typename F>
void expectInvalid(F&& f, const std::string& expectedInMessage) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning '" << expectedInMessage << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(expectedInMessage), std::string::npos) << e.what();
  }
}

TEST(Hamming, MatchesBitByBitReferenceForAllWidths) {
  std::mt19937 rng(1234);
  for (int bytes = 4; bytes <= 64; bytes += 4) {
    for (int trial = 0; trial < 50; ++trial) {
      const double p = (trial % 5) / 4.0;  // includes all-zero and all-one rows
      const cv::Mat a = randomRow(bytes, p, rng);
      const cv::Mat b = randomRow(bytes, 0.5, rng);
      const int expected = refHamming(a, b);
      EXPECT_EQ(mdbrief::hammingDistance(a, b), expected) << "bytes " << bytes;
      EXPECT_EQ(mdbrief::hammingDistance(unalignedCopy(a), b), expected) << "bytes " << bytes;
      EXPECT_EQ(mdbrief::hammingDistance(b, a), expected);
    }
  }
}

TEST(Hamming, ExtremesAndTail) {
  // 36 bytes = four 64-bit words + a 32-bit tail; only the tail differs.
  cv::Mat a(1, 36, CV_8UC1, cv::Scalar(0));
  cv::Mat b = a.clone();
  b.at<uint8_t>(0, 35) = 0x81;
  b.at<uint8_t>(0, 32) = 0x01;
  EXPECT_EQ(mdbrief::hammingDistance(a, b), 3);
  EXPECT_EQ(mdbrief::hammingDistance(a, cv::Mat(1, 36, CV_8UC1, cv::Scalar(255))), 288);
  EXPECT_EQ(mdbrief::hammingDistance(a, a), 0);
}

TEST(MaskedHamming, MaskWeight) {
  for (int nbits = 32; nbits <= 512; nbits += 32) {
    EXPECT_EQ(mdbrief::maskWeight(nbits, nbits), 1u << 21) << "all ones is exact";
    EXPECT_EQ(mdbrief::maskWeight(0, nbits), 1u << 21) << "all zeros acts as all ones";
    for (int ones = 1; ones <= nbits; ++ones) {
      const double exact = std::ldexp(1.0, 21) * nbits / ones;
      EXPECT_LE(std::abs(mdbrief::maskWeight(ones, nbits) - exact), 0.5) << nbits << " " << ones;
    }
  }
}

TEST(MaskedHamming, MatchesDoubleReferenceForAllWidths) {
  std::mt19937 rng(42);
  for (int bytes = 4; bytes <= 64; bytes += 4) {
    const int nbits = bytes * 8;
    for (int trial = 0; trial < 60; ++trial) {
      const cv::Mat di = randomRow(bytes, 0.5, rng);
      const cv::Mat dj = randomRow(bytes, 0.5, rng);
      // Mask densities from empty through sparse (a single bit is likely) to full.
      const double densities[] = {0.0, 0.02, 0.3, 0.7, 0.95, 1.0};
      const cv::Mat li = randomRow(bytes, densities[trial % 6], rng);
      const cv::Mat lj = randomRow(bytes, densities[(trial / 6) % 6], rng);
      const double expected = refMasked(di, li, dj, lj);
      const float got = mdbrief::maskedHammingDistance(di, li, dj, lj);
      EXPECT_NEAR(got, expected, maskedTolerance(nbits)) << "bytes " << bytes << " trial " << trial;
      EXPECT_GE(got, 0.f);
      EXPECT_LE(got, nbits);
      // Symmetric exactly, also with unaligned rows.
      EXPECT_EQ(mdbrief::maskedHammingDistance(dj, lj, unalignedCopy(di), unalignedCopy(li)), got);
    }
  }
}

TEST(MaskedHamming, AllOnesMasksGivePlainHammingExactly) {
  std::mt19937 rng(7);
  for (int bytes = 4; bytes <= 64; bytes += 4) {
    const cv::Mat ones(1, bytes, CV_8UC1, cv::Scalar(255));
    const cv::Mat zeros(1, bytes, CV_8UC1, cv::Scalar(0));
    for (int trial = 0; trial < 20; ++trial) {
      const cv::Mat di = randomRow(bytes, 0.5, rng);
      const cv::Mat dj = randomRow(bytes, 0.5, rng);
      const float plain = static_cast<float>(mdbrief::hammingDistance(di, dj));
      EXPECT_EQ(mdbrief::maskedHammingDistance(di, ones, dj, ones), plain);
      // An all-zero mask is an all-ones mask.
      EXPECT_EQ(mdbrief::maskedHammingDistance(di, zeros, dj, ones), plain);
      EXPECT_EQ(mdbrief::maskedHammingDistance(di, zeros, dj, zeros), plain);
    }
  }
}

TEST(MaskedHamming, MaskedOutBitsDoNotCount) {
  // 32 bits; descriptors differ in bits 0..7; mask i keeps bits 0..15 (o = 16), mask j keeps
  // bits 16..31 (o = 16): H = 8/16 + 0/16 = 0.5 -> 0.5 * 32 / 2 = 8 bits.
  cv::Mat di(1, 4, CV_8UC1, cv::Scalar(0));
  cv::Mat dj = di.clone();
  dj.at<uint8_t>(0, 0) = 0xFF;
  const cv::Mat li = (cv::Mat_<uint8_t>(1, 4) << 0xFF, 0xFF, 0, 0);
  const cv::Mat lj = (cv::Mat_<uint8_t>(1, 4) << 0, 0, 0xFF, 0xFF);
  EXPECT_EQ(mdbrief::maskedHammingDistance(di, li, dj, lj), 8.f);
}

TEST(Hamming, InvalidInputsThrow) {
  const cv::Mat a(1, 32, CV_8UC1, cv::Scalar(0));
  expectInvalid([&] { mdbrief::hammingDistance(cv::Mat(1, 32, CV_32F), a); }, "a: descriptors must be CV_8UC1");
  expectInvalid([&] { mdbrief::hammingDistance(a, cv::Mat(1, 8, CV_8UC3)); }, "b: descriptors must be CV_8UC1");
  expectInvalid([&] { mdbrief::hammingDistance(a, cv::Mat(1, 30, CV_8UC1)); }, "b: descriptor width");
  expectInvalid([&] { mdbrief::hammingDistance(cv::Mat(1, 68, CV_8UC1), a); }, "a: descriptor width");
  expectInvalid([&] { mdbrief::hammingDistance(a, cv::Mat(1, 16, CV_8UC1)); }, "b: width 16");
  expectInvalid([&] { mdbrief::hammingDistance(cv::Mat(2, 32, CV_8UC1), a); }, "a: expected a single row");
  expectInvalid([&] { mdbrief::hammingDistance(cv::Mat(), a); }, "a: empty");
}

TEST(MaskedHamming, InvalidInputsThrow) {
  const cv::Mat d(1, 32, CV_8UC1, cv::Scalar(0));
  const cv::Mat shortMask(1, 28, CV_8UC1, cv::Scalar(0));
  expectInvalid([&] { mdbrief::maskedHammingDistance(d, shortMask, d, d); }, "li: width 28");
  expectInvalid([&] { mdbrief::maskedHammingDistance(d, d, d, shortMask); }, "lj: width 28");
  expectInvalid([&] { mdbrief::maskedHammingDistance(d, d, cv::Mat(1, 32, CV_16U), d); }, "dj: descriptors must be CV_8UC1");
  expectInvalid([&] { mdbrief::maskedHammingDistance(d, d, d, cv::Mat()); }, "lj: empty");
}

}  // namespace
