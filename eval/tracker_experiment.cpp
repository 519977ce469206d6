#include "tracker_experiment.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <tuple>

#include <opencv2/features2d.hpp>
#include <tbb/parallel_for.h>

#include "csv_table.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/api/presets.hpp"

namespace mdbrief::eval {
namespace {

// The `budget` strongest of an OpenCV detector inside `region`, ties cut deterministically.
std::vector<cv::KeyPoint> strongest(const cv::Ptr<cv::Feature2D>& detector, const cv::Mat& image, const cv::Mat& region,
                                    int budget) {
  std::vector<cv::KeyPoint> kps;
  detector->detect(image, kps, region);
  std::stable_sort(kps.begin(), kps.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  if (static_cast<int>(kps.size()) > budget) kps.resize(budget);
  return kps;
}

// The library's matcher wants a width that is a multiple of 4 bytes (descriptor_method.cpp).
Features opencvFeatures(const cv::Ptr<cv::Feature2D>& f2d, const cv::Mat& image, std::vector<cv::KeyPoint> kps, int bits) {
  Features f;
  f.bits = bits;
  f2d->compute(image, kps, f.descriptors);
  f.keypoints = std::move(kps);
  if (f.descriptors.type() == CV_8U && f.descriptors.cols % 4) {
    cv::Mat padded(f.descriptors.rows, (f.descriptors.cols + 3) / 4 * 4, CV_8U, cv::Scalar(0));
    f.descriptors.copyTo(padded.colRange(0, f.descriptors.cols));
    f.descriptors = padded;
  }
  return f;
}

struct PairRecord {
  int sequence = 0, pair = 0;
  PairEvidence evidence;
  std::vector<TrackerResult> results;  // per ratio
};

double share(int count, int total) { return total ? static_cast<double>(count) / total : 0.0; }

TrackerSummary summarise(const std::string& group, const TrackerPipeline& p, size_t r, double ratio,
                         const std::vector<PairRecord>& records, double keypoints) {
  TrackerSummary s;
  s.group = group;
  s.pipeline = p.name;
  s.ratio = ratio;
  s.pairs = static_cast<int>(records.size());
  s.keypoints = keypoints;
  long repeated = 0, candidates = 0, matches = 0, correct = 0;
  int h3 = 0, h1 = 0, e3 = 0, e1 = 0, eCount = 0;
  double hInliers = 0, eInliers = 0;
  std::vector<PairMatches> nearest;
  for (const auto& rec : records) {
    const TrackerResult& t = rec.results[r];
    s.meanAp += rec.evidence.averagePrecision;
    repeated += rec.evidence.repeated;
    candidates += rec.evidence.repeatCandidates;
    matches += t.matches;
    correct += t.correct;
    h3 += t.homographyErrorPx <= 3.0;
    h1 += t.homographyErrorPx <= 1.0;
    hInliers += t.homographyInliers;
    if (t.essentialChecked) {
      ++eCount;
      e3 += t.essentialErrorPx <= 3.0;
      e1 += t.essentialErrorPx <= 1.0;
      eInliers += t.essentialInliers;
    }
    nearest.push_back(rec.evidence.nearest);
  }
  const double n = std::max<size_t>(1, records.size());
  s.meanAp /= n;
  s.prAuc = summarize(meanCurve(nearest)).auc;
  s.repeatability = candidates ? static_cast<double>(repeated) / static_cast<double>(candidates) : 0.0;
  s.correctPerPair = static_cast<double>(correct) / n;
  s.precision = matches ? static_cast<double>(correct) / static_cast<double>(matches) : 0.0;
  s.homographyRight3 = share(h3, s.pairs);
  s.homographyRight1 = share(h1, s.pairs);
  s.homographyInliers = hInliers / n;
  s.essential = eCount > 0;
  s.essentialRight3 = share(e3, eCount);
  s.essentialRight1 = share(e1, eCount);
  s.essentialInliers = eCount ? eInliers / eCount : 0.0;
  return s;
}

void printTable(const std::vector<TrackerSummary>& rows) {
  std::string group;
  for (const auto& s : rows) {
    if (s.group != group) {
      group = s.group;
      std::printf("\n%s (%d pairs)\n", group.c_str(), s.pairs);
      std::printf("  %-28s %5s %7s %7s %7s %8s %7s %7s %7s %7s %7s %7s\n", "pipeline", "ratio", "meanAP", "PR-AUC",
                  "repeat", "correct", "precis", "H<=3px", "H<=1px", "H-inl", "E<=3px", "E<=1px");
    }
    std::printf("  %-28s %5.2f %7.3f %7.3f %7.3f %8.1f %7.3f %6.0f%% %6.0f%% %7.1f", s.pipeline.c_str(), s.ratio,
                s.meanAp, s.prAuc, s.repeatability, s.correctPerPair, s.precision, 100 * s.homographyRight3,
                100 * s.homographyRight1, s.homographyInliers);
    if (s.essential)
      std::printf(" %6.0f%% %6.0f%%\n", 100 * s.essentialRight3, 100 * s.essentialRight1);
    else
      std::printf(" %7s %7s\n", "-", "-");
  }
}

}  // namespace

std::vector<TrackerPipeline> standardTrackerPipelines() {
  std::vector<TrackerPipeline> p;
  // The presets at their own ratios; the paper's has none, so it is shown at its best.
  for (const Preset preset : {Preset::Tracking, Preset::Matching, Preset::Paper}) {
    const PresetSettings s = presetSettings(preset);
    TrackerPipeline q;
    q.name = "mdbrief " + toString(preset) + (preset == Preset::Tracking ? " (defaults)" : "");
    q.options = s.features;
    if (s.matching.ratio) q.ratio = *s.matching.ratio;
    p.push_back(q);
  }
  // The defaults with the random set instead of the learned one (docs/RESULTS.md "Learned vs random test sets").
  TrackerPipeline random = p.front();
  random.name = "mdbrief tracking @brief_random_512";
  random.options.descriptor.pattern = "brief_random_512";
  p.push_back(random);
  for (const auto& [name, kind] : {std::pair{"ORB", TrackerPipeline::Kind::Orb}, std::pair{"AKAZE", TrackerPipeline::Kind::Akaze},
                                   std::pair{"SIFT", TrackerPipeline::Kind::Sift}, std::pair{"BRISK", TrackerPipeline::Kind::Brisk}}) {
    TrackerPipeline q;
    q.name = name;
    q.kind = kind;
    p.push_back(q);
  }
  return p;
}

Features trackerFeatures(const TrackerPipeline& p, const cv::Mat& image, const CameraPtr& camera, const cv::Mat& region,
                         int budget) {
  switch (p.kind) {
    case TrackerPipeline::Kind::Library: {
      MdBriefOptions o = p.options;
      o.detector.nfeatures = budget;
      const auto f2d = MdBrief::create(camera, o);
      Features f;
      f.bits = o.descriptor.bits;
      f2d->detectAndComputeWithMasks(image, region, f.keypoints, f.descriptors, f.masks);
      return f;
    }
    case TrackerPipeline::Kind::Orb: {
      // cv::ORB chooses its `budget` keypoints itself (its per-level shares and Harris ranking).
      const auto orb = cv::ORB::create(budget);
      Features f;
      f.bits = 256;
      orb->detectAndCompute(image, region, f.keypoints, f.descriptors);
      return f;
    }
    case TrackerPipeline::Kind::Akaze: {
      const auto akaze = cv::AKAZE::create();
      return opencvFeatures(akaze, image, strongest(akaze, image, region, budget), 486);
    }
    case TrackerPipeline::Kind::Sift: {
      const auto sift = cv::SIFT::create(budget);
      Features f;
      f.bits = 128;
      sift->detectAndCompute(image, region, f.keypoints, f.descriptors);
      return f;
    }
    case TrackerPipeline::Kind::Brisk: {
      const auto brisk = cv::BRISK::create();
      return opencvFeatures(brisk, image, strongest(brisk, image, region, budget), 512);
    }
  }
  throw std::logic_error("trackerFeatures: unknown pipeline kind");
}

std::vector<TrackerSummary> runTracker(const std::vector<EvalGroup>& groups, const std::vector<TrackerPipeline>& pipelines,
                                       const TrackerExperimentOptions& o) {
  std::filesystem::create_directories(o.outDir);
  CsvTable pairsCsv({"group", "sequence", "image_a", "image_b", "pipeline", "ratio", "keypoints_a", "keypoints_b",
                     "repeated", "repeat_candidates", "ground_truth", "average_precision", "nn_correct", "matches",
                     "correct", "homography_inliers", "homography_error_px", "essential_inliers", "essential_error_px",
                     "local_scale", "scale_error_log2", "orientation_error_deg"});
  CsvTable summaryCsv({"group", "pipeline", "ratio", "shown", "pairs", "keypoints", "mean_ap", "pr_auc", "repeatability",
                       "correct_per_pair", "precision", "homography_right_3px", "homography_right_1px",
                       "homography_inliers", "essential_right_3px", "essential_right_1px", "essential_inliers"});
  std::vector<TrackerSummary> table;
  for (const auto& g : groups) {
    if (g.sequences.empty()) continue;
    // Where keypoints are sought, and the ground-truth grid of every pair: shared by the pipelines.
    std::vector<std::vector<cv::Mat>> regions(g.sequences.size());
    std::vector<std::pair<int, int>> pairIndex;  // (sequence, pair)
    for (size_t s = 0; s < g.sequences.size(); ++s) {
      const auto& seq = g.sequences[s];
      for (size_t i = 0; i < seq.images.size(); ++i)
        regions[s].push_back(!seq.regions.empty() ? seq.regions[i]
                             : seq.cameraIsModel  ? validAreaMask(*seq.camera, seq.images[i].size())
                                                  : cv::Mat());
      for (size_t p = 0; p < seq.pairs.size(); ++p) pairIndex.emplace_back(static_cast<int>(s), static_cast<int>(p));
    }
    std::vector<GroundTruthGrid> grids(pairIndex.size());
    tbb::parallel_for(size_t(0), pairIndex.size(), [&](size_t k) {
      const auto& seq = g.sequences[pairIndex[k].first];
      const auto& pair = seq.pairs[pairIndex[k].second];
      grids[k] = groundTruthGrid(*seq.camera, pair.map, seq.images[pair.first].size(), regions[pairIndex[k].first][pair.first],
                                 o.gridStep);
    });
    std::fprintf(stderr, "tracker: %s, %zu pairs\n", g.name.c_str(), pairIndex.size());
    for (const auto& p : pipelines) {
      std::vector<std::vector<Features>> features(g.sequences.size());
      double keypoints = 0;
      int images = 0;
      for (size_t s = 0; s < g.sequences.size(); ++s)
        for (size_t i = 0; i < g.sequences[s].images.size(); ++i) {
          features[s].push_back(trackerFeatures(p, g.sequences[s].images[i], g.sequences[s].camera, regions[s][i], o.budget));
          keypoints += static_cast<double>(features[s].back().keypoints.size());
          ++images;
        }
      std::vector<PairRecord> records(pairIndex.size());
      tbb::parallel_for(size_t(0), pairIndex.size(), [&](size_t k) {
        const auto [s, pi] = pairIndex[k];
        const auto& seq = g.sequences[s];
        const auto& pair = seq.pairs[pi];
        const Features& fa = features[s][pair.first];
        const Features& fb = features[s][pair.second];
        PairRecord& rec = records[k];
        rec.sequence = s;
        rec.pair = pi;
        rec.evidence = pairEvidence(fa, fb, *seq.camera, pair.map, regions[s][pair.second], seq.images[pair.second].size(),
                                    o.tracker);
        for (double ratio : o.ratios)
          rec.results.push_back(trackerResult(fb, rec.evidence, ratio, *seq.camera, grids[k], false, o.tracker));
      });
      std::vector<TrackerSummary> sweep;
      for (size_t r = 0; r < o.ratios.size(); ++r)
        sweep.push_back(summarise(g.name, p, r, o.ratios[r], records, keypoints / std::max(1, images)));
      // The row shown: the pipeline's own ratio when it has one in the sweep, else the best.
      size_t shown = 0;
      for (size_t r = 1; r < sweep.size(); ++r) {
        const auto key = [](const TrackerSummary& s) {
          return std::make_tuple(s.homographyRight3, s.homographyRight1, s.correctPerPair);
        };
        if (key(sweep[r]) > key(sweep[shown])) shown = r;
      }
      if (p.ratio)
        for (size_t r = 0; r < sweep.size(); ++r)
          if (std::abs(sweep[r].ratio - *p.ratio) < 1e-6) shown = r;  // a float ratio (MatchOptions)
      // The essential matrix at the shown ratio only: its 5-point RANSAC costs most of the run.
      tbb::parallel_for(size_t(0), pairIndex.size(), [&](size_t k) {
        const auto& seq = g.sequences[pairIndex[k].first];
        if (!seq.baseline) return;
        const Features& fb = features[pairIndex[k].first][seq.pairs[pairIndex[k].second].second];
        records[k].results[shown] =
            trackerResult(fb, records[k].evidence, o.ratios[shown], *seq.camera, grids[k], true, o.tracker);
      });
      sweep[shown] = summarise(g.name, p, shown, o.ratios[shown], records, keypoints / std::max(1, images));
      for (const auto& rec : records) {
        const auto& seq = g.sequences[rec.sequence];
        const auto& pair = seq.pairs[rec.pair];
        const auto& e = rec.evidence;
        int nnCorrect = 0;
        for (char c : e.nearest.correct) nnCorrect += c;
        for (size_t r = 0; r < o.ratios.size(); ++r) {
          const auto& t = rec.results[r];
          pairsCsv.row().add(g.name).add(seq.name).add(pair.first + 1).add(pair.second + 1).add(p.name).add(o.ratios[r])
              .add(static_cast<int>(features[rec.sequence][pair.first].keypoints.size()))
              .add(static_cast<int>(features[rec.sequence][pair.second].keypoints.size()))
              .add(e.repeated).add(e.repeatCandidates).add(e.nearest.groundTruth).add(e.averagePrecision).add(nnCorrect)
              .add(t.matches).add(t.correct).add(t.homographyInliers).add(t.homographyErrorPx)
              .add(t.essentialChecked ? t.essentialInliers : -1).add(t.essentialChecked ? t.essentialErrorPx : -1.0)
              .add(e.localScale).add(e.scaleErrorLog2).add(e.orientationErrorDeg);
        }
      }
      for (size_t r = 0; r < sweep.size(); ++r) {
        const auto& s = sweep[r];
        summaryCsv.row().add(s.group).add(s.pipeline).add(s.ratio).add(r == shown ? 1 : 0).add(s.pairs).add(s.keypoints)
            .add(s.meanAp).add(s.prAuc).add(s.repeatability).add(s.correctPerPair).add(s.precision)
            .add(s.homographyRight3).add(s.homographyRight1).add(s.homographyInliers)
            .add(s.essential ? s.essentialRight3 : -1.0).add(s.essential ? s.essentialRight1 : -1.0)
            .add(s.essential ? s.essentialInliers : -1.0);
      }
      table.push_back(sweep[shown]);
      std::fprintf(stderr, "tracker: %s: %s done\n", g.name.c_str(), p.name.c_str());
    }
  }
  pairsCsv.write((std::filesystem::path(o.outDir) / "tracker_pairs.csv").string());
  summaryCsv.write((std::filesystem::path(o.outDir) / "tracker_summary.csv").string());
  printTable(table);
  return table;
}

}  // namespace mdbrief::eval
