#include "pr_experiment.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "csv_table.hpp"
#include <opencv2/features2d.hpp>

#include "mdbrief/detect/detector.hpp"
#include "mdbrief/describe/patterns.hpp"

namespace mdbrief::eval {

namespace {

MethodSpec withOrientation(MethodSpec m, OrientationSource source) {
  m.options.orientation = source;
  return m;
}

}  // namespace

std::vector<MethodSpec> standardPrMethods(bool withStudies) {
  const auto af = DistortionForm::Affine;
  std::vector<MethodSpec> m{
      opencvMethod("ORB-256", MethodFamily::Orb),
      opencvMethod("BRISK-512", MethodFamily::Brisk),
      opencvMethod("AKAZE-MLDB-486", MethodFamily::Akaze),
      opencvMethod("SIFT", MethodFamily::Sift),
      briefFamilyMethod("BRIEF-256", DescriptorKind::Brief, 256, true),
      briefFamilyMethod("mBRIEF-256", DescriptorKind::MaskedBrief, 256, true, af),
      briefFamilyMethod("dBRIEF-128", DescriptorKind::DBrief, 128, true, af),
      briefFamilyMethod("dBRIEF-256", DescriptorKind::DBrief, 256, true, af),
      briefFamilyMethod("dBRIEF-512", DescriptorKind::DBrief, 512, true, af),
      briefFamilyMethod("mdBRIEF-128", DescriptorKind::MdBrief, 128, true, af),
      briefFamilyMethod("mdBRIEF-256", DescriptorKind::MdBrief, 256, true, af),
      briefFamilyMethod("mdBRIEF-512", DescriptorKind::MdBrief, 512, true, af),
      briefFamilyMethod("dBRIEF-256-paper", DescriptorKind::DBrief, 256, true, DistortionForm::Paper),
      briefFamilyMethod("mdBRIEF-256-paper", DescriptorKind::MdBrief, 256, true, DistortionForm::Paper),
      // The detector's angle instead of the one re-measured on the tangent plane.
      withOrientation(briefFamilyMethod("dBRIEF-256-kp", DescriptorKind::DBrief, 256, true, af), OrientationSource::Keypoint),
      withOrientation(briefFamilyMethod("mdBRIEF-256-kp", DescriptorKind::MdBrief, 256, true, af), OrientationSource::Keypoint),
      // Without orientation (the paper's fig. "Ignoring patch orientation").
      briefFamilyMethod("BRIEF-256-noori", DescriptorKind::Brief, 256, false),
      briefFamilyMethod("mBRIEF-256-noori", DescriptorKind::MaskedBrief, 256, false, af),
      briefFamilyMethod("dBRIEF-128-noori", DescriptorKind::DBrief, 128, false, af),
      briefFamilyMethod("dBRIEF-256-noori", DescriptorKind::DBrief, 256, false, af),
      briefFamilyMethod("dBRIEF-512-noori", DescriptorKind::DBrief, 512, false, af),
      briefFamilyMethod("mdBRIEF-128-noori", DescriptorKind::MdBrief, 128, false, af),
      briefFamilyMethod("mdBRIEF-256-noori", DescriptorKind::MdBrief, 256, false, af),
      briefFamilyMethod("mdBRIEF-512-noori", DescriptorKind::MdBrief, 512, false, af)};
  if (!withStudies) return m;
  // Length study with the default set.
  for (int bits : {32, 64})
    m.push_back(briefFamilyMethod("dBRIEF-" + std::to_string(bits), DescriptorKind::DBrief, bits, true, af));
  const auto study = comparisonSetStudyMethods(builtinComparisonSetNames());
  m.insert(m.end(), study.begin(), study.end());
  return m;
}

std::vector<MethodSpec> comparisonSetStudyMethods(const std::vector<std::string>& testSets) {
  std::vector<MethodSpec> m;
  for (const auto& set : testSets) {
    const int size = static_cast<int>(resolveComparisonSet(set).tests.size());
    const std::string label = std::filesystem::path(set).extension() == ".json" ? std::filesystem::path(set).stem().string() : set;
    for (const auto& [prefix, kind] : {std::pair{"dBRIEF-", DescriptorKind::DBrief}, std::pair{"mdBRIEF-", DescriptorKind::MdBrief}})
      for (int bits : {128, 256, 512})
        if (bits <= size)
          m.push_back(briefFamilyMethod(prefix + std::to_string(bits) + "@" + label, kind, bits, true,
                                        DistortionForm::Affine, DescriptorOptions{}.maskRotationDeg, set));
  }
  return m;
}

std::vector<MethodSpec> supportScaleStudyMethods(const std::vector<double>& scales) {
  std::vector<MethodSpec> m;
  for (double scale : scales)
    for (const auto& [prefix, kind] : {std::pair{"dBRIEF-256-s", DescriptorKind::DBrief}, std::pair{"mdBRIEF-256-s", DescriptorKind::MdBrief}}) {
      char label[32];
      std::snprintf(label, sizeof label, "%s%g", prefix, scale);
      MethodSpec spec = briefFamilyMethod(label, kind, 256, true);
      spec.options.supportScale = scale;
      m.push_back(spec);
    }
  return m;
}

std::vector<cv::KeyPoint> detectKeypoints(KeypointSource source, const cv::Mat& image, const CameraPtr& camera,
                                          const cv::Mat& mask, int count, DetectorOptions o) {
  if (source == KeypointSource::ModOrb || source == KeypointSource::Hessian) {
    o.method = source == KeypointSource::Hessian ? DetectorMethod::Hessian : DetectorMethod::ModOrb;
    o.nfeatures = count;
    return Detector(camera, o).detect(image);
  }
  cv::Ptr<cv::Feature2D> detector;
  switch (source) {
    case KeypointSource::Orb: detector = cv::ORB::create(count); break;
    case KeypointSource::Akaze: detector = cv::AKAZE::create(); break;
    case KeypointSource::Brisk: detector = cv::BRISK::create(); break;
    case KeypointSource::Sift: detector = cv::SIFT::create(count); break;
    case KeypointSource::ModOrb:
    case KeypointSource::Hessian: break;
  }
  std::vector<cv::KeyPoint> kps;
  detector->detect(image, kps, mask);
  std::stable_sort(kps.begin(), kps.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  if (static_cast<int>(kps.size()) > count) kps.resize(count);
  return kps;
}

void runPrecisionRecall(const std::vector<EvalGroup>& groups, const std::vector<MethodSpec>& methods,
                        const PrOptions& o) {
  std::filesystem::create_directories(o.outDir);
  CsvTable summary({"group", "sequence", "method", "auc", "recall_at_0.1", "recall_at_0.2", "pairs",
                    "mean_ground_truth"});
  for (const auto& g : groups) {
    if (g.sequences.empty()) continue;
    std::fprintf(stderr, "eval: group %s (%zu sequences)\n", g.name.c_str(), g.sequences.size());
    // Keypoints once per image (shared by all methods).
    std::vector<std::vector<std::vector<cv::KeyPoint>>> kps(g.sequences.size());
    std::vector<std::vector<cv::Mat>> masks(g.sequences.size());
    for (size_t s = 0; s < g.sequences.size(); ++s) {
      const auto& seq = g.sequences[s];
      for (const auto& img : seq.images) {
        masks[s].push_back(seq.cameraIsModel ? validAreaMask(*seq.camera, img.size()) : cv::Mat());
        kps[s].push_back(detectKeypoints(o.keypointSource, img, seq.cameraIsModel ? seq.camera : nullptr,
                                         masks[s].back(), o.keypoints, o.library));
        if (o.commonKeypoints && !methods.empty())
          kps[s].back() =
              describe(methods.back(), img, seq.camera, kps[s].back(), o.keypoints, masks[s].back(), o.library.pyramid)
                  .keypoints;
      }
    }
    CsvTable curves({"method", "threshold", "one_minus_precision", "recall"});
    for (const auto& m : methods) {
      std::vector<PairMatches> all;
      for (size_t s = 0; s < g.sequences.size(); ++s) {
        const auto& seq = g.sequences[s];
        std::vector<Features> f;
        for (size_t i = 0; i < seq.images.size(); ++i)
          f.push_back(describe(m, seq.images[i], seq.camera, kps[s][i], o.keypoints, masks[s][i], o.library.pyramid));
        std::vector<PairMatches> mine;
        for (const auto& p : seq.pairs) mine.push_back(matchPair(f[p.first], f[p.second], p.map, o.radiusPx));
        const PrSummary ss = summarize(meanCurve(mine, o.curveSteps));
        double gt = 0;
        for (const auto& pm : mine) gt += pm.groundTruth;
        summary.row().add(g.name).add(seq.name).add(m.name).add(ss.auc).add(ss.recallAt01).add(ss.recallAt02)
            .add(static_cast<int>(mine.size())).add(gt / std::max<size_t>(1, mine.size()));
        all.insert(all.end(), mine.begin(), mine.end());
      }
      const PrCurve c = meanCurve(all, o.curveSteps);
      const PrSummary s = summarize(c);
      double gt = 0;
      for (const auto& pm : all) gt += pm.groundTruth;
      summary.row().add(g.name).add(std::string("ALL")).add(m.name).add(s.auc).add(s.recallAt01).add(s.recallAt02)
          .add(static_cast<int>(all.size())).add(gt / std::max<size_t>(1, all.size()));
      for (size_t i = 0; i < c.recall.size(); ++i)
        curves.row().add(m.name).add(c.threshold[i]).add(c.oneMinusPrecision[i]).add(c.recall[i]);
    }
    curves.write((std::filesystem::path(o.outDir) / ("eval_" + g.name + "_curves.csv")).string());
  }
  summary.write((std::filesystem::path(o.outDir) / "eval_summary.csv").string());
}

}  // namespace mdbrief::eval
