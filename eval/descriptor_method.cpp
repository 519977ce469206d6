#include "descriptor_method.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "mdbrief/match/matcher.hpp"
#include "mdbrief/match/masked_hamming.hpp"
#include "mdbrief/match/hamming.hpp"

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

bool isMasked(const MethodSpec& method) {
  return method.family == MethodFamily::Library && hasMasks(method.options.kind);
}

bool isDistorted(const MethodSpec& method) {
  return method.family == MethodFamily::Library && usesCamera(method.options.kind);
}

Features describe(const MethodSpec& m, const cv::Mat& image, const CameraPtr& camera,
                  std::vector<cv::KeyPoint> keypoints, int maxKeypoints, const cv::Mat& validMask,
                  const PyramidOptions& pyramid) {
  switch (m.family) {
    case MethodFamily::Library: {
      const DescriptorExtractor ex(isDistorted(m) ? camera : nullptr, m.options);
      Features f;
      f.bits = m.options.bits;
      f.keypoints = std::move(keypoints);
      ex.compute(image, f.keypoints, f.descriptors, f.masks, pyramid);
      return f;
    }
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

Features describeOwnKeypoints(const MethodSpec& m, const cv::Mat& image, std::vector<cv::KeyPoint> keypoints) {
  if (m.family == MethodFamily::Akaze) return describeOpenCv(cv::AKAZE::create(), image, std::move(keypoints), 486);
  if (m.family == MethodFamily::Sift) return describeOpenCv(cv::SIFT::create(), image, std::move(keypoints), 128);
  return describe(m, image, nullptr, std::move(keypoints));
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
    return matchBruteForceMasked(query.descriptors, query.masks, train.descriptors, train.masks,
                                 nearestNeighbourOptions());
  return matchBruteForce(query.descriptors, train.descriptors, nearestNeighbourOptions());
}

MethodSpec briefFamilyMethod(const std::string& name, DescriptorKind kind, int bits, bool oriented,
                             DistortionForm form, double maskDeg, const std::string& pattern) {
  MethodSpec m;
  m.name = name;
  m.options.kind = kind;
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
