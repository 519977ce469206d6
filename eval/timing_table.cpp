#include "timing_table.hpp"

#include <algorithm>
#include <chrono>
#include <functional>

#include <opencv2/features2d.hpp>

#include "csv_table.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/match/matcher.hpp"
#include "mdbrief/api/presets.hpp"

namespace mdbrief::eval {
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Pipeline {
  std::string detector, descriptor;
  std::function<std::vector<cv::KeyPoint>(const cv::Mat&)> detect;
  // Describes in place (drops what cannot be described).
  std::function<void(const cv::Mat&, std::vector<cv::KeyPoint>&, cv::Mat&, cv::Mat&)> describe;
  std::function<void(const cv::Mat&, const cv::Mat&, const cv::Mat&, const cv::Mat&)> match;
};

std::vector<Pipeline> pipelines(const CameraPtr& camera, int n) {
  auto orb = cv::ORB::create(n);
  auto brisk = cv::BRISK::create();
  auto akaze = cv::AKAZE::create();
  auto sift = cv::SIFT::create(n);
  // modORB as the paper ran it (cv::ORB's pyramid); Hessian as the library's defaults run it.
  DetectorOptions paper = presetSettings(Preset::Paper).features.detector;
  paper.nfeatures = n;
  auto modOrb = std::make_shared<Detector>(camera, paper);
  DetectorOptions defaults;
  defaults.nfeatures = n;
  auto hessian = std::make_shared<Detector>(camera, defaults);
  auto extractor = [camera](DescriptorKind kind) {
    DescriptorOptions o;
    o.kind = kind;
    o.bits = 256;  // the paper's table uses the 256-bit variants
    return std::make_shared<DescriptorExtractor>(kind == DescriptorKind::Brief ? nullptr : camera, o);
  };
  auto brief = extractor(DescriptorKind::Brief), dbrief = extractor(DescriptorKind::DBrief),
       mdbrief = extractor(DescriptorKind::MdBrief);
  auto cvDetect = [](cv::Ptr<cv::Feature2D> f) {
    return [f](const cv::Mat& img) {
      std::vector<cv::KeyPoint> k;
      f->detect(img, k);
      return k;
    };
  };
  auto cvDescribe = [](cv::Ptr<cv::Feature2D> f) {
    return [f](const cv::Mat& img, std::vector<cv::KeyPoint>& k, cv::Mat& d, cv::Mat&) { f->compute(img, k, d); };
  };
  auto ours = [](std::shared_ptr<DescriptorExtractor> e) {
    return [e](const cv::Mat& img, std::vector<cv::KeyPoint>& k, cv::Mat& d, cv::Mat& m) { e->compute(img, k, d, m); };
  };
  auto cvMatch = [](int norm) {
    return [norm](const cv::Mat& a, const cv::Mat&, const cv::Mat& b, const cv::Mat&) {
      std::vector<cv::DMatch> m;
      cv::BFMatcher(norm).match(a, b, m);
    };
  };
  // Nearest neighbours, as cv::BFMatcher::match above.
  auto ourMatch = [](const cv::Mat& a, const cv::Mat&, const cv::Mat& b, const cv::Mat&) {
    matchBruteForce(a, b, nearestNeighbourOptions());
  };
  auto ourMaskedMatch = [](const cv::Mat& a, const cv::Mat& ma, const cv::Mat& b, const cv::Mat& mb) {
    matchBruteForceMasked(a, ma, b, mb, nearestNeighbourOptions());
  };
  auto modOrbDetect = [modOrb](const cv::Mat& img) { return modOrb->detect(img); };
  auto hessianDetect = [hessian](const cv::Mat& img) { return hessian->detect(img); };
  return {
      {"ORB", "ORB", cvDetect(orb), cvDescribe(orb), cvMatch(cv::NORM_HAMMING)},
      {"ORB", "BRIEF (ours)", cvDetect(orb), ours(brief), ourMatch},
      {"modORB", "dBRIEF", modOrbDetect, ours(dbrief), ourMatch},
      {"modORB", "mdBRIEF", modOrbDetect, ours(mdbrief), ourMaskedMatch},
      {"Hessian", "dBRIEF", hessianDetect, ours(dbrief), ourMatch},
      {"Hessian", "mdBRIEF", hessianDetect, ours(mdbrief), ourMaskedMatch},
      {"BRISK", "BRISK", cvDetect(brisk), cvDescribe(brisk), cvMatch(cv::NORM_HAMMING)},
      {"AKAZE", "AKAZE", cvDetect(akaze), cvDescribe(akaze), cvMatch(cv::NORM_HAMMING)},
      {"SIFT", "SIFT", cvDetect(sift), cvDescribe(sift), cvMatch(cv::NORM_L2)},
  };
}

}  // namespace

std::vector<TimingRow> measureTimingTable(const std::vector<cv::Mat>& images, const CameraPtr& camera,
                                          const TimingOptions& o) {
  std::vector<TimingRow> rows;
  for (const auto& p : pipelines(camera, o.keypoints)) {
    std::vector<double> det, desc, match, count;
    for (int r = 0; r < o.repeats; ++r) {
      double tDet = 0, tDesc = 0, tMatch = 0, nKp = 0, nPairs = 0;
      std::vector<cv::Mat> d(images.size()), m(images.size());
      for (size_t i = 0; i < images.size(); ++i) {
        auto t0 = Clock::now();
        auto kps = p.detect(images[i]);
        tDet += secondsSince(t0);
        const double detected = static_cast<double>(kps.size());
        t0 = Clock::now();
        p.describe(images[i], kps, d[i], m[i]);
        tDesc += secondsSince(t0);
        nKp += detected;
      }
      for (size_t i = 0; i + 1 < images.size(); ++i) {
        const auto t0 = Clock::now();
        p.match(d[i], m[i], d[i + 1], m[i + 1]);
        tMatch += secondsSince(t0);
        nPairs += static_cast<double>(d[i].rows) * d[i + 1].rows;
      }
      det.push_back(nKp > 0 ? tDet / nKp * 1e6 : 0.0);
      desc.push_back(nKp > 0 ? tDesc / nKp * 1e6 : 0.0);
      match.push_back(nPairs > 0 ? tMatch / nPairs * 1e9 : 0.0);
      count.push_back(nKp / images.size());
    }
    TimingRow row{p.detector, p.descriptor, median(det), median(desc), median(match), 0, median(count)};
    row.totalUs = row.detectionUs + row.descriptionUs;
    rows.push_back(row);
  }
  return rows;
}

void writeTimingTable(const std::vector<TimingRow>& rows, const std::string& path) {
  CsvTable t({"detector", "descriptor", "keypoints", "detection_us", "description_us", "matching_ns", "total_us",
              "detection_ratio", "description_ratio", "matching_ratio", "total_ratio"});
  const TimingRow* orb = nullptr;
  for (const auto& r : rows)
    if (r.detector == "ORB" && r.descriptor == "ORB") orb = &r;
  auto ratio = [](double a, double b) { return b > 0 ? a / b : 0.0; };
  for (const auto& r : rows) {
    t.row().add(r.detector).add(r.descriptor).add(r.keypoints).add(r.detectionUs).add(r.descriptionUs).add(r.matchingNs)
        .add(r.totalUs);
    if (orb)
      t.add(ratio(r.detectionUs, orb->detectionUs)).add(ratio(r.descriptionUs, orb->descriptionUs))
          .add(ratio(r.matchingNs, orb->matchingNs)).add(ratio(r.totalUs, orb->totalUs));
    else
      t.add(0.0).add(0.0).add(0.0).add(0.0);
  }
  t.write(path);
}

}  // namespace mdbrief::eval
