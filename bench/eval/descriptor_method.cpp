#include "descriptor_method.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "mdbrief/matcher.hpp"
#include "mdbrief/masked_hamming.hpp"
#include "mdbrief/hamming.hpp"

namespace mdbrief::eval {
namespace {

// The library's matcher wants widths that are a multiple of 4 bytes; zero padding leaves
// Hamming distances unchanged (AKAZE's 61 bytes become 64).
cv::Mat padToWords(const cv::Mat& d) {
  const int bytes = (d.cols + 3) / 4 * 4;
  if (bytes == d.cols || d.empty()) return d;
  cv::Mat out(d.rows, bytes, CV_8U, cv::Scalar(0));
  d.copyTo(out.colRange(0, d.cols));
  return out;
}

// BOLD-like masks without distortion: BRIEF at the keypoint angle and at +/- delta; a test is
// stable when all three outcomes agree. The library's BRIEF has no masks, so this is built
// from three BRIEF extractions through the public API (keypoint angle offset by +/- delta).
Features describeMaskedBrief(const MethodSpec& m, const cv::Mat& image, std::vector<cv::KeyPoint> kps) {
  DescriptorOptions o = m.options;
  o.kind = DescriptorKind::Brief;
  const bool oriented = o.useOrientation;
  o.useOrientation = true;  // the offsets are applied through the keypoint angle
  const DescriptorExtractor ex(nullptr, o);
  // Tag keypoints by index so the three extractions can be intersected.
  std::vector<int> originalClass(kps.size());
  for (size_t i = 0; i < kps.size(); ++i) {
    originalClass[i] = kps[i].class_id;
    kps[i].class_id = static_cast<int>(i);
  }
  int levels = 1;
  for (const auto& kp : kps) levels = std::max(levels, kp.octave + 1);
  const ImagePyramid pyramid(image, o.pyramid, levels);
  const double deltas[3] = {0.0, m.options.maskRotationDeg, -m.options.maskRotationDeg};
  std::vector<cv::KeyPoint> out[3];
  cv::Mat desc[3];
  for (int r = 0; r < 3; ++r) {
    out[r] = kps;
    for (auto& kp : out[r]) {
      const double base = oriented && kp.angle >= 0.f ? kp.angle : 0.0;
      kp.angle = static_cast<float>(std::fmod(base + deltas[r] + 720.0, 360.0));
    }
    ex.compute(pyramid, out[r], desc[r]);
  }
  std::vector<int> row1(kps.size(), -1), row2(kps.size(), -1);
  for (size_t j = 0; j < out[1].size(); ++j) row1[out[1][j].class_id] = static_cast<int>(j);
  for (size_t j = 0; j < out[2].size(); ++j) row2[out[2][j].class_id] = static_cast<int>(j);
  Features f;
  f.bits = o.bits;
  const int bytes = o.bits / 8;
  for (size_t i = 0; i < out[0].size(); ++i) {
    const int id = out[0][i].class_id, a = row1[id], b = row2[id];
    if (a < 0 || b < 0) continue;
    cv::Mat maskRow(1, bytes, CV_8U);
    for (int k = 0; k < bytes; ++k)
      maskRow.at<uchar>(k) = static_cast<uchar>(~((desc[0].at<uchar>(static_cast<int>(i), k) ^ desc[1].at<uchar>(a, k)) |
                                                  (desc[0].at<uchar>(static_cast<int>(i), k) ^ desc[2].at<uchar>(b, k))));
    cv::KeyPoint kp = kps[id];
    kp.class_id = originalClass[id];
    f.keypoints.push_back(kp);
    f.descriptors.push_back(desc[0].row(static_cast<int>(i)));
    f.masks.push_back(maskRow);
  }
  return f;
}

// compute() may drop keypoints it cannot describe; the kept ones keep their fields, so rows
// stay aligned with f.keypoints.
Features describeOpenCv(const cv::Ptr<cv::Feature2D>& f2d, const cv::Mat& image,
                        std::vector<cv::KeyPoint> kps, int bits) {
  Features f;
  f.bits = bits;
  f2d->compute(image, kps, f.descriptors);
  f.keypoints = std::move(kps);
  if (f.descriptors.type() == CV_8U) f.descriptors = padToWords(f.descriptors);
  return f;
}

}  // namespace

bool ownsKeypoints(MethodFamily family) { return family == MethodFamily::Akaze; }

bool isMasked(MethodFamily family) {
  return family == MethodFamily::MdBrief || family == MethodFamily::MaskedBrief;
}

Features describe(const MethodSpec& m, const cv::Mat& image, const CameraPtr& camera,
                  std::vector<cv::KeyPoint> keypoints, int maxKeypoints, const cv::Mat& validMask) {
  switch (m.family) {
    case MethodFamily::Brief:
    case MethodFamily::DBrief:
    case MethodFamily::MdBrief: {
      DescriptorOptions o = m.options;
      o.kind = m.family == MethodFamily::Brief ? DescriptorKind::Brief
               : m.family == MethodFamily::DBrief ? DescriptorKind::DBrief
                                                  : DescriptorKind::MdBrief;
      const DescriptorExtractor ex(m.family == MethodFamily::Brief ? nullptr : camera, o);
      Features f;
      f.bits = o.bits;
      f.keypoints = std::move(keypoints);
      ex.compute(image, f.keypoints, f.descriptors, &f.masks);
      return f;
    }
    case MethodFamily::MaskedBrief:
      return describeMaskedBrief(m, image, std::move(keypoints));
    case MethodFamily::Orb: {
      // Without an angle cv::ORB would rotate by -1 degree; 0 is its "upright".
      for (auto& kp : keypoints)
        if (kp.angle < 0.f) kp.angle = 0.f;
      return describeOpenCv(cv::ORB::create(std::max(1, static_cast<int>(keypoints.size()))), image,
                            std::move(keypoints), 256);
    }
    case MethodFamily::Brisk:
      return describeOpenCv(cv::BRISK::create(), image, std::move(keypoints), 512);
    case MethodFamily::Sift:
      for (auto& kp : keypoints) {
        if (kp.angle < 0.f) kp.angle = 0.f;
        // cv::SIFT reads `octave` as its own packed octave/layer code: 0 = the full-resolution
        // octave. Its descriptor window is about 6x `size` wide; size / 6 makes it cover the
        // same 31-pixel (times scale) patch as the binary descriptors.
        kp.octave = 0;
        kp.size /= 6.f;
      }
      return describeOpenCv(cv::SIFT::create(), image, std::move(keypoints), 128);
    case MethodFamily::Akaze: {
      Features f;
      f.bits = 486;
      auto akaze = cv::AKAZE::create();
      std::vector<cv::KeyPoint> kps;
      akaze->detect(image, kps, validMask);
      cv::KeyPointsFilter::retainBest(kps, maxKeypoints);
      // retainBest keeps ties beyond the limit; cut exactly, strongest first, deterministic.
      std::stable_sort(kps.begin(), kps.end(),
                       [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
      if (static_cast<int>(kps.size()) > maxKeypoints) kps.resize(maxKeypoints);
      akaze->compute(image, kps, f.descriptors);
      f.keypoints = std::move(kps);
      f.descriptors = padToWords(f.descriptors);
      return f;
    }
  }
  throw std::logic_error("describe: unknown method family");
}

double descriptorDistance(const Features& a, int i, const Features& b, int j) {
  if (a.descriptors.type() == CV_32F) return cv::norm(a.descriptors.row(i), b.descriptors.row(j), cv::NORM_L2);
  const int bytes = a.descriptors.cols;
  const uint8_t* di = a.descriptors.ptr<uint8_t>(i);
  const uint8_t* dj = b.descriptors.ptr<uint8_t>(j);
  if (!a.masks.empty() && !b.masks.empty())
    return maskedFixedToBits(maskedHammingFixed(di, a.masks.ptr<uint8_t>(i), dj, b.masks.ptr<uint8_t>(j), bytes));
  return hammingDistance(di, dj, bytes);
}

std::vector<cv::DMatch> nearestNeighbours(const Features& query, const Features& train) {
  if (query.descriptors.empty() || train.descriptors.empty()) return {};
  if (query.descriptors.type() == CV_32F) {
    std::vector<cv::DMatch> out;
    cv::BFMatcher(cv::NORM_L2).match(query.descriptors, train.descriptors, out);
    return out;
  }
  if (!query.masks.empty() && !train.masks.empty())
    return matchBruteForceMasked(query.descriptors, query.masks, train.descriptors, train.masks);
  return matchBruteForce(query.descriptors, train.descriptors);
}

MethodSpec briefFamilyMethod(const std::string& name, MethodFamily family, int bits, bool oriented,
                             DistortionForm form, double maskDeg, const std::string& pattern) {
  MethodSpec m;
  m.name = name;
  m.family = family;
  m.options.bits = bits;
  m.options.useOrientation = oriented;
  m.options.form = form;
  m.options.maskRotationDeg = maskDeg;
  m.options.pattern = pattern;
  return m;
}

MethodSpec opencvMethod(const std::string& name, MethodFamily family) {
  MethodSpec m;
  m.name = name;
  m.family = family;
  return m;
}

}  // namespace mdbrief::eval
