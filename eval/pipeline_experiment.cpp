#include "pipeline_experiment.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "csv_table.hpp"
#include "mdbrief/detect/detector.hpp"

namespace mdbrief::eval {
namespace {

// The detector's own descriptor (same OpenCV object convention as descriptor_method.cpp).
MethodSpec ownDescriptor(KeypointSource detector) {
  switch (detector) {
    case KeypointSource::Orb: return opencvMethod("ORB", MethodFamily::Orb);
    case KeypointSource::Akaze: return opencvMethod("MLDB", MethodFamily::Akaze);
    case KeypointSource::Brisk: return opencvMethod("BRISK", MethodFamily::Brisk);
    case KeypointSource::Sift: return opencvMethod("SIFT", MethodFamily::Sift);
    case KeypointSource::ModOrb:
    case KeypointSource::Hessian: break;
  }
  throw std::logic_error("ownDescriptor: the library's detectors have no descriptor of their own");
}

MethodSpec mdBriefAt(double supportScale) {
  MethodSpec m = briefFamilyMethod("mdBRIEF-256", DescriptorKind::MdBrief, 256, true);
  m.options.supportScale = supportScale;
  return m;
}

// A detector's own descriptor sees its keypoints as detectAndCompute would.
Features describeKeypoints(const PipelineSpec& p, const cv::Mat& image, const CameraPtr& camera,
                           const std::vector<cv::KeyPoint>& keypoints, int budget, const cv::Mat& mask,
                           const PyramidOptions& pyramid) {
  const bool own = (p.detector == KeypointSource::Akaze && p.descriptor.family == MethodFamily::Akaze) ||
                   (p.detector == KeypointSource::Sift && p.descriptor.family == MethodFamily::Sift);
  return own ? describeOwnKeypoints(p.descriptor, image, keypoints)
             : describe(p.descriptor, image, camera, keypoints, budget, mask, pyramid);
}

}  // namespace

std::vector<PipelineSpec> standardPipelines() {
  const auto mod = KeypointSource::ModOrb;
  std::vector<PipelineSpec> p{
      {"modORB+mdBRIEF-256", mod, briefFamilyMethod("mdBRIEF-256", DescriptorKind::MdBrief, 256, true)},
      {"modORB+dBRIEF-256", mod, briefFamilyMethod("dBRIEF-256", DescriptorKind::DBrief, 256, true)},
      {"modORB+BRIEF-256", mod, briefFamilyMethod("BRIEF-256", DescriptorKind::Brief, 256, true)},
      {"Hessian+mdBRIEF-256", KeypointSource::Hessian, briefFamilyMethod("mdBRIEF-256", DescriptorKind::MdBrief, 256, true)},
      {"Hessian+dBRIEF-256", KeypointSource::Hessian, briefFamilyMethod("dBRIEF-256", DescriptorKind::DBrief, 256, true)},
      {"Hessian+BRIEF-256", KeypointSource::Hessian, briefFamilyMethod("BRIEF-256", DescriptorKind::Brief, 256, true)}};
  for (const auto& [name, source] : {std::pair{"ORB", KeypointSource::Orb}, std::pair{"AKAZE", KeypointSource::Akaze},
                                     std::pair{"BRISK", KeypointSource::Brisk}, std::pair{"SIFT", KeypointSource::Sift}})
    p.push_back({std::string(name) + "+" + ownDescriptor(source).name, source, ownDescriptor(source)});
  p.push_back({"AKAZE+mdBRIEF-256", KeypointSource::Akaze, mdBriefAt(10.0)});
  p.push_back({"SIFT+mdBRIEF-256", KeypointSource::Sift, mdBriefAt(12.0)});
  return p;
}

std::pair<int, int> repeatedKeypoints(const std::vector<cv::KeyPoint>& a, const std::vector<cv::KeyPoint>& b,
                                      const GroundTruthMap& map, cv::Size bSize, const cv::Mat& bMask,
                                      double radius) {
  int repeated = 0, candidates = 0;
  for (const auto& kp : a) {
    const auto t = map(cv::Point2d(kp.pt));
    if (!t || !(t->x >= 0 && t->y >= 0 && t->x <= bSize.width - 1 && t->y <= bSize.height - 1)) continue;
    if (!bMask.empty() && !bMask.at<uchar>(cvRound(t->y), cvRound(t->x))) continue;
    ++candidates;
    repeated += std::any_of(b.begin(), b.end(),
                            [&](const cv::KeyPoint& k) { return cv::norm(cv::Point2d(k.pt) - *t) <= radius; });
  }
  return {repeated, candidates};
}

void runPipelines(const std::vector<EvalGroup>& groups, const std::vector<PipelineSpec>& pipelines,
                  const PipelineOptions& o) {
  std::filesystem::create_directories(o.outDir);
  CsvTable summary({"group", "budget", "pipeline", "repeatability", "auc", "recall_at_0.1", "keypoints",
                    "described", "pairs"});
  for (const auto& g : groups) {
    if (g.sequences.empty()) continue;
    for (int budget : o.budgets) {
      std::fprintf(stderr, "pipelines: group %s, %d keypoints (%zu sequences)\n", g.name.c_str(), budget,
                   g.sequences.size());
      for (const auto& p : pipelines) {
        std::vector<PairMatches> matches;
        long repeated = 0, candidates = 0;
        double detected = 0, described = 0;
        int images = 0;
        for (const auto& seq : g.sequences) {
          const CameraPtr detectorCamera = seq.cameraIsModel ? seq.camera : nullptr;
          std::vector<std::vector<cv::KeyPoint>> kps;
          std::vector<cv::Mat> masks;
          std::vector<Features> f;
          for (const auto& img : seq.images) {
            masks.push_back(seq.cameraIsModel ? validAreaMask(*seq.camera, img.size()) : cv::Mat());
            kps.push_back(detectKeypoints(p.detector, img, detectorCamera, masks.back(), budget, o.library));
            f.push_back(describeKeypoints(p, img, seq.camera, kps.back(), budget, masks.back(), o.library.pyramid));
            detected += static_cast<double>(kps.back().size());
            described += static_cast<double>(f.back().keypoints.size());
            ++images;
          }
          for (const auto& pair : seq.pairs) {
            const auto [r, c] = repeatedKeypoints(kps[pair.first], kps[pair.second], pair.map,
                                                  seq.images[pair.second].size(), masks[pair.second], o.radiusPx);
            repeated += r;
            candidates += c;
            matches.push_back(matchPair(f[pair.first], f[pair.second], pair.map, o.radiusPx));
          }
        }
        const PrSummary s = summarize(meanCurve(matches, o.curveSteps));
        summary.row().add(g.name).add(budget).add(p.name)
            .add(candidates ? static_cast<double>(repeated) / static_cast<double>(candidates) : 0.0)
            .add(s.auc).add(s.recallAt01).add(detected / std::max(1, images)).add(described / std::max(1, images))
            .add(static_cast<int>(matches.size()));
      }
    }
  }
  summary.write((std::filesystem::path(o.outDir) / "pipelines_summary.csv").string());
}

}  // namespace mdbrief::eval
