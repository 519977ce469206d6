#include "detect/gaussian_smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "detect/smoothing_kernels.hpp"

namespace mdbrief {

namespace detail {
namespace {

static_assert(2 * smoothing_kernels::kMaxRadius + 1 == kMaxSmoothingTaps);

// The Gaussian's weights for offsets 0..radius (symmetric) in units of 2^-bits: each its scaled
// value rounded down or up, the largest remainders rounded up, so that they sum to one exactly
// and none is negative however coarse the units are against the kernel.
std::vector<uint32_t> fixedWeights(int taps, double sigma, int bits) {
  const int radius = taps / 2;
  const cv::Mat g = cv::getGaussianKernel(taps, sigma, CV_64F);
  std::vector<uint32_t> w(radius + 1);
  std::vector<std::pair<double, int>> remainders;  // (fraction, offset) of the side weights
  int64_t left = int64_t{1} << bits;
  for (int k = 0; k <= radius; ++k) {
    const double scaled = std::ldexp(g.at<double>(radius + k), bits);
    w[k] = static_cast<uint32_t>(std::floor(scaled));
    left -= (k == 0 ? 1 : 2) * int64_t{w[k]};
    if (k > 0) remainders.emplace_back(scaled - w[k], k);
  }
  // A side weight counts twice, so the centre takes an odd unit; the fractions sum below
  // taps, so the sides' units never outnumber them.
  if (left % 2 != 0) ++w[0], --left;
  std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (size_t i = 0; left > 0 && i < remainders.size(); ++i, left -= 2) ++w[remainders[i].second];
  return w;
}

void checkSmoothing(const cv::Mat& level8u, int taps, double sigma) {
  if (level8u.type() != CV_8UC1 || level8u.empty())
    throw std::invalid_argument("gaussianSmoothing: needs a non-empty 8UC1 image");
  if (taps < 1 || taps % 2 == 0 || taps > kMaxSmoothingTaps || !(sigma > 0.0))
    throw std::invalid_argument("gaussianSmoothing: needs an odd width of at most 49 taps and a positive sigma");
}

}  // namespace

GaussianRowSmoother::GaussianRowSmoother(const cv::Mat& level8u, int taps, double sigma) : level_(level8u) {
  checkSmoothing(level8u, taps, sigma);
  rows_ = level8u.rows, cols_ = level8u.cols, radius_ = taps / 2;
  rowWeights_ = fixedWeights(taps, sigma, 8), columnWeights_ = fixedWeights(taps, sigma, 16);
  const int slots = radius_ + 1;
  ring_.resize(static_cast<size_t>(slots) * 2 * cols_);
  for (int i = 0; i < 2 * slots; ++i) slots_.push_back(&ring_[static_cast<size_t>(i % slots) * 2 * cols_]);
  padded_.resize(2 * static_cast<size_t>(cols_ + 2 * radius_));
  leftColumn_.resize(radius_ + 1), rightColumn_.resize(radius_ + 1);
  for (int i = 1; i <= radius_; ++i) {
    leftColumn_[i] = cv::borderInterpolate(-i, cols_, cv::BORDER_REFLECT_101);
    rightColumn_[i] = cv::borderInterpolate(cols_ - 1 + i, cols_, cv::BORDER_REFLECT_101);
  }
  // Rows y - radius .. y + radius reflected, for the rows that reflect; the others read 2 radius
  // + 1 rows in a run, from an even or an odd row.
  std::vector<int> read(taps);
  const auto reflects = [&](int y) { return y < radius_ || y + radius_ >= rows_; };
  int reflecting = 0;
  for (int y = 0; y < rows_; ++y) reflecting += reflects(y);
  terms_.reserve(reflecting + 2);
  for (int parity = 0; parity < 2; ++parity) {
    for (int k = 0; k < taps; ++k) read[k] = parity + k;
    terms_.push_back(foldTerms(read.data(), 0));
  }
  termsOfRow_.resize(rows_);
  for (int y = 0; y < rows_; ++y) {
    if (!reflects(y)) {
      termsOfRow_[y] = &terms_[(y - radius_) & 1];
      continue;
    }
    for (int k = 0; k < taps; ++k) read[k] = cv::borderInterpolate(y - radius_ + k, rows_, cv::BORDER_REFLECT_101);
    terms_.push_back(foldTerms(read.data(), std::max(0, y - radius_) / 2));
    termsOfRow_[y] = &terms_.back();
  }
  for (const RowTerms& t : terms_) termCount_ = std::max(termCount_, t.count);
  termPairs_.resize(termCount_), termWeights_.resize(termCount_);
  kernels_ = smoothing_kernels::activeSmoothingKernels();
}

GaussianRowSmoother::RowTerms GaussianRowSmoother::foldTerms(const int* read, int first) const {
  // The rows read lie in [max(0, y - radius), min(rows - 1, y + radius)]: radius + 1 pairs at most.
  uint32_t lanes[2 * (smoothing_kernels::kMaxRadius + 1)] = {};
  for (int k = 0; k <= 2 * radius_; ++k) lanes[read[k] - 2 * first] += columnWeights_[std::abs(k - radius_)];
  // A weight above 32767 (all of them sum to 65536) takes several terms: two more in all at most.
  RowTerms terms;
  for (int q = 0; q <= radius_; ++q)
    for (uint32_t upper = lanes[2 * q], lower = lanes[2 * q + 1]; upper || lower;) {
      const uint32_t u = std::min(upper, 32767u), l = std::min(lower, 32767u);
      terms.offsets[terms.count] = q, terms.weights[terms.count++] = u | l << 16;
      upper -= u, lower -= l;
    }
  return terms;
}

void GaussianRowSmoother::smoothPair(int pair) {
  const int width = cols_ + 2 * radius_;
  for (int half = 0; half < 2; ++half) {
    // A level of odd height pairs its last row with itself; no term weighs the copy.
    const uint8_t* in = level_.ptr<uint8_t>(std::min(2 * pair + half, rows_ - 1));
    uint16_t* padded = &padded_[static_cast<size_t>(half) * width];
    kernels_.widen(in, cols_, padded + radius_);
    for (int i = 1; i <= radius_; ++i) {
      padded[radius_ - i] = in[leftColumn_[i]];
      padded[radius_ + cols_ - 1 + i] = in[rightColumn_[i]];
    }
  }
  kernels_.rowPair(padded_.data() + radius_, padded_.data() + width + radius_, cols_, rowWeights_.data(), radius_,
                   &ring_[static_cast<size_t>(pair % (radius_ + 1)) * 2 * cols_]);
}

void GaussianRowSmoother::next(uint8_t* bytes, float* floats) {
  if (y_ >= rows_) throw std::out_of_range("GaussianRowSmoother::next: past the last row");
  for (const int needed = std::min(rows_ - 1, y_ + radius_) / 2; smoothedPairs_ <= needed; ++smoothedPairs_)
    smoothPair(smoothedPairs_);
  const RowTerms& terms = *termsOfRow_[y_];
  const int first = (std::max(0, y_ - radius_) / 2) % (radius_ + 1);
  for (int t = 0; t < termCount_; ++t) {
    const bool used = t < terms.count;
    termPairs_[t] = slots_[first + (used ? terms.offsets[t] : 0)], termWeights_[t] = used ? terms.weights[t] : 0;
  }
  kernels_.columns(termPairs_.data(), termWeights_.data(), termCount_, cols_, bytes, floats);
  ++y_;
}

int threeSigmaTaps(double sigma) { return 2 * static_cast<int>(std::ceil(3.0 * sigma)) + 1; }

Smoothing gaussianSmoothing(const cv::Mat& level8u, int taps, double sigma, bool withFloats) {
  GaussianRowSmoother smoother(level8u, taps, sigma);
  Smoothing out{cv::Mat(level8u.rows, level8u.cols, CV_8U),
                withFloats ? cv::Mat(level8u.rows, level8u.cols, CV_32F) : cv::Mat()};
  for (int y = 0; y < level8u.rows; ++y)
    smoother.next(out.bytes.ptr<uint8_t>(y), withFloats ? out.floats.ptr<float>(y) : nullptr);
  return out;
}

GaussianBlockSmoother::GaussianBlockSmoother(const cv::Mat& level8u, int taps, double sigma) : level_(level8u) {
  checkSmoothing(level8u, taps, sigma);
  rows_ = level8u.rows, cols_ = level8u.cols, radius_ = taps / 2;
  rowWeights_ = fixedWeights(taps, sigma, 8), columnWeights_ = fixedWeights(taps, sigma, 16);
  kernels_ = smoothing_kernels::activeSmoothingKernels();
}

void GaussianBlockSmoother::prefetch(int cx, int cy) const {
  const int left = cx - radius_ - 2, top = cy - radius_ - 2, span = 2 * radius_ + 5;
  if (left < 0 || top < 0 || left + span > cols_ || top + span > rows_) return;
  for (int t = 0; t < span; ++t) {
    const uint8_t* row = level_.ptr<uint8_t>(top + t) + left;
    __builtin_prefetch(row);
    __builtin_prefetch(row + span - 1);
  }
}

void GaussianBlockSmoother::block(int cx, int cy, float* out) const {
  constexpr int kMaxSpan = 2 * smoothing_kernels::kMaxRadius + 5;
  const int span = 2 * radius_ + 5, readable = 2 * radius_ + smoothing_kernels::kBlockSlack;
  const int left = cx - radius_ - 2, top = cy - radius_ - 2;
  const auto reflect = [](int i, int n) {
    return static_cast<unsigned>(i) < static_cast<unsigned>(n) ? i : cv::borderInterpolate(i, n, cv::BORDER_REFLECT_101);
  };
  // Rows in place where the kernel's reads stay inside them; otherwise copies, reflected.
  const bool inside = left >= 0 && left + readable <= cols_;
  const uint8_t* rows[kMaxSpan];
  uint8_t copies[kMaxSpan][kMaxSpan + smoothing_kernels::kBlockSlack];
  for (int t = 0; t < span; ++t) {
    const uint8_t* row = level_.ptr<uint8_t>(reflect(top + t, rows_));
    if (inside) {
      rows[t] = row + left;
      continue;
    }
    for (int u = 0; u < readable; ++u) copies[t][u] = u < span ? row[reflect(left + u, cols_)] : 0;
    rows[t] = copies[t];
  }
  uint32_t fixed[25];
  kernels_.block5(rows, radius_, rowWeights_.data(), columnWeights_.data(), fixed);
  for (int i = 0; i < 25; ++i) out[i] = static_cast<float>(static_cast<int>(fixed[i])) * smoothing_kernels::kFixedToUnit;
}

}  // namespace detail
}  // namespace mdbrief
