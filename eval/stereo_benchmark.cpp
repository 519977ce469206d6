#include "stereo_benchmark.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <tuple>

#include <tbb/parallel_for.h>

#include "csv_table.hpp"
#include "scenes/room_renderer.hpp"
#include "toolkit/image_file.hpp"

namespace mdbrief::eval {
namespace {

namespace fs = std::filesystem;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kLocalisationRadiusPx = 3.0;  // a rendered match is right within this of the truth

// The image names of an ASL folder's data.csv (#timestamp [ns],filename), in file order.
std::vector<std::string> aslImageNames(const fs::path& csv) {
  std::ifstream in(csv);
  if (!in) throw std::runtime_error(csv.string() + ": cannot read");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto comma = line.find(',');
    if (comma == std::string::npos) throw std::runtime_error(csv.string() + ": expected 'timestamp,filename': " + line);
    std::string name = line.substr(comma + 1);
    while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
    names.push_back(name);
  }
  return names;
}

cv::Mat readGrey(const std::string& path) {
  if (const std::string problem = truncationProblem(path); !problem.empty())
    throw std::runtime_error(path + ": " + problem);
  cv::Mat image = decodeGreyImage(path);
  if (image.empty()) throw std::runtime_error(path + ": not an image OpenCV decodes");
  return image;
}

double degrees(double radians) { return radians * 180.0 / CV_PI; }

double angleBetween(const cv::Vec3d& u, const cv::Vec3d& v) { return std::atan2(cv::norm(u.cross(v)), u.dot(v)); }

double rotationErrorDeg(const RelativePose& fit, const RelativePose& truth) {
  const cv::Matx33d d = fit.rotation.t() * truth.rotation;
  return degrees(std::acos(std::clamp((cv::trace(d) - 1.0) / 2.0, -1.0, 1.0)));
}

// The larger of the rotation's and the translation direction's angular errors, degrees.
double poseErrorDeg(const RelativePose& fit, const RelativePose& truth) {
  return std::max(rotationErrorDeg(fit, truth), degrees(angleBetween(fit.translation, truth.translation)));
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// One pair under one pipeline, at one ratio.
struct StereoPairResult {
  int keypointsA = 0, keypointsB = 0, matches = 0, right = 0, refined = 0;
  std::vector<double> rightResidualsPx;
  double rightSignedResidualSumPx = 0;
  std::vector<float> rightSizes;  // b's keypoint size, per right match
  std::vector<int> rightLevels;   // b's keypoint octave, per right match
  bool fitOk = false;
  int fitInliers = 0;
  double poseErrorDeg = kInf, rotationErrorDeg = kInf;
  std::vector<std::pair<int, double>> localisation;  // rendered pairs: (b's level, error px) per right match
  // With StereoOptions::writeMatches, at the residual's ratio: per right match a's and b's
  // bearings, b's pixels per radian and the signed residual, px.
  std::vector<cv::Vec<double, 8>> rightRows;
};

struct Keypoints {
  std::vector<std::optional<cv::Vec3d>> bearing;
  std::vector<double> scale;  // pixels per radian; 0 where the camera has none
};

Keypoints keypointRays(const Camera& camera, const std::vector<cv::KeyPoint>& kps) {
  Keypoints k;
  for (const auto& kp : kps) {
    cv::Vec3d b;
    const auto scale = pixelsPerRadian(camera, kp.pt);
    if (camera.pixelToBearing(kp.pt, b) && scale) {
      k.bearing.emplace_back(b);
      k.scale.push_back(*scale);
    } else {
      k.bearing.emplace_back();
      k.scale.push_back(0);
    }
  }
  return k;
}

// With pyramids, b's side of every match is refined (match_refinement.hpp) before it is scored,
// and a match the refinement fails on is dropped, as a tracker drops it: its patches do not fix
// the point (an edge, or views that do not align), and it is where the imprecise matches are
// (EuRoC: residual median 0.26 px against 0.12 px for the refined ones).
std::vector<StereoPairResult> scorePair(const Features& fa, const Features& fb, const Camera& cameraA,
                                        const Camera& cameraB, const StereoPair& pair, const RelativePose& truth,
                                        const StereoOptions& o, const ImagePyramid* pyramidA = nullptr,
                                        const ImagePyramid* pyramidB = nullptr) {
  const NeighbourTable table = nearestNeighbourTable(fa, fb);
  const Keypoints ra = keypointRays(cameraA, fa.keypoints), rb = keypointRays(cameraB, fb.keypoints);
  TwoViewOptions label = o.fit;
  label.maxPixels = o.rightPx;
  std::vector<StereoPairResult> out;
  for (const double ratio : o.ratios) {
    StereoPairResult r;
    r.keypointsA = static_cast<int>(fa.keypoints.size());
    r.keypointsB = static_cast<int>(fb.keypoints.size());
    std::vector<cv::Vec3d> a, b;
    std::vector<double> scale;
    std::vector<cv::DMatch> kept;
    std::vector<cv::Point2d> pointB;
    for (const auto& [qa, tb] : mutualRatioMatches(table, ratio)) {
      if (!ra.bearing[qa] || !rb.bearing[tb]) continue;
      a.push_back(*ra.bearing[qa]);
      b.push_back(*rb.bearing[tb]);
      scale.push_back(rb.scale[tb]);
      kept.emplace_back(qa, tb, 0.f);
      pointB.push_back(fb.keypoints[tb].pt);
    }
    if (pyramidA && pyramidB) {
      const auto refined = refineMatches(*pyramidA, cameraA, fa.keypoints, *pyramidB, cameraB, fb.keypoints, kept, o.refinement);
      size_t n = 0;
      for (size_t k = 0; k < kept.size(); ++k) {
        const auto s = refined[k].ok() ? pixelsPerRadian(cameraB, refined[k].pointB) : std::nullopt;
        if (!s) continue;
        a[n] = a[k], b[n] = refined[k].bearingB, scale[n] = *s, kept[n] = kept[k], pointB[n] = refined[k].pointB;
        ++n;
      }
      a.resize(n), b.resize(n), scale.resize(n), kept.resize(n), pointB.resize(n);
      r.refined = static_cast<int>(n);
    }
    if (pair.truthInB)
      for (size_t k = 0; k < kept.size(); ++k) {
        const auto truthB = pair.truthInB(fa.keypoints[kept[k].queryIdx].pt);
        if (!truthB) continue;
        const double error = cv::norm(pointB[k] - *truthB);
        if (error <= kLocalisationRadiusPx) r.localisation.emplace_back(fb.keypoints[kept[k].trainIdx].octave, error);
      }
    r.matches = static_cast<int>(a.size());
    const TwoViewResult known = checkKnownPose(a, b, truth, label, scale);
    const cv::Matx33d essential = essentialMatrix(RelativePose{truth.rotation, truth.translation / cv::norm(truth.translation)});
    for (size_t k = 0; k < a.size(); ++k)
      if (known.inliers[k]) {
        ++r.right;
        r.rightResidualsPx.push_back(known.residuals[k] * scale[k]);
        const double side = (essential.t() * a[k]).dot(b[k]);
        const double signedPx = side < 0 ? -r.rightResidualsPx.back() : r.rightResidualsPx.back();
        r.rightSignedResidualSumPx += signedPx;
        r.rightSizes.push_back(fb.keypoints[kept[k].trainIdx].size);
        r.rightLevels.push_back(fb.keypoints[kept[k].trainIdx].octave);
        if (o.writeMatches && std::abs(ratio - o.residualRatio) < 1e-9)
          r.rightRows.push_back({a[k][0], a[k][1], a[k][2], b[k][0], b[k][1], b[k][2], scale[k], signedPx});
      }
    const EssentialResult fit = fitEssential(a, b, o.fit, scale);
    r.fitOk = fit.ok();
    r.fitInliers = fit.inlierCount;
    if (fit.ok()) r.poseErrorDeg = poseErrorDeg(fit.pose, truth), r.rotationErrorDeg = rotationErrorDeg(fit.pose, truth);
    out.push_back(std::move(r));
  }
  return out;
}

StereoSet fromRig(const std::string& name, const CameraRig& rig) {
  return {name, rig.at(0).camera, rig.at(1).camera, rig.relativePose(0, 1), {}};
}

}  // namespace

std::vector<StereoSet> loadStereoSets(const std::string& data) {
  const fs::path root = fs::path(data) / "stereo";
  std::vector<StereoSet> sets;
  if (!fs::is_directory(root)) return sets;
  const fs::path euroc = root / "euroc-v1-01";
  if (fs::is_directory(euroc)) {
    StereoSet s = fromRig("euroc-v1-01", readCameraRig(std::vector<std::string>{(euroc / "cam0/sensor.yaml").string(),
                                                                             (euroc / "cam1/sensor.yaml").string()}));
    const auto left = aslImageNames(euroc / "cam0/data.csv"), right = aslImageNames(euroc / "cam1/data.csv");
    for (const auto& name : left)
      if (std::find(right.begin(), right.end(), name) != right.end())
        s.pairs.push_back({(euroc / "cam0/data" / name).string(), (euroc / "cam1/data" / name).string(), {}, {}, {}, {}});
    if (s.pairs.empty()) throw std::runtime_error(euroc.string() + ": no image in both cam0/data.csv and cam1/data.csv");
    sets.push_back(std::move(s));
  }
  const fs::path mynt = root / "mynteye-fisheye";
  if (fs::is_directory(mynt)) {
    StereoSet s = fromRig("mynteye-fisheye",
                          readCameraRig(std::vector<std::string>{(mynt / "left_sensor_fisheye.yaml").string(),
                                                                 (mynt / "right_sensor_fisheye.yaml").string()}));
    s.pairs.push_back({(mynt / "left_fisheye_img_0.png").string(), (mynt / "right_fisheye_img_0.png").string(), {}, {},
                       {}, {}});
    sets.push_back(std::move(s));
  }
  return sets;
}

StereoSet renderedStereoRig(const std::string& opencvDocDir, const CameraPtr& camera) {
  auto room = std::make_shared<RoomScene>();
  const char* photos[6] = {"building.jpg", "home.jpg", "aero1.jpg", "baboon.jpg", "fruits.jpg", "messi5.jpg"};
  for (int w = 0; w < 6; ++w) room->walls[w] = readGrey((fs::path(opencvDocDir) / photos[w]).string());
  StereoSet set{"rendered-rig", camera, camera, {}, {}};
  // Side-by-side pairs at several places and headings (tests/test_two_view_rendered_rig.cpp's
  // stereo placements): centre, heading and pitch of a, baseline along a's x, b's turn.
  struct Placement {
    cv::Vec3d centre;
    double headingDeg, pitchDeg, baseline, turnDeg;
  };
  const Placement placements[] = {{{0.0, 0.0, 0.0}, 0, 0, 0.12, 0},
                                  {{0.3, -0.2, 0.5}, 30, 10, 0.12, 5},
                                  {{-0.5, 0.2, -0.3}, -45, -10, 0.25, 10},
                                  {{0.6, 0.1, 1.0}, 150, 5, 0.40, 15}};
  for (size_t k = 0; k < std::size(placements); ++k) {
    const Placement& p = placements[k];
    CameraPose a, b;
    a.rotation = yawPitchRotation(p.headingDeg, p.pitchDeg);
    a.centre = p.centre;
    b.rotation = yawPitchRotation(p.turnDeg, 0) * a.rotation;
    b.centre = a.centre + a.rotation.t() * cv::Vec3d(p.baseline, 0, 0);
    StereoPair pair;
    pair.left = "rendered-" + std::to_string(k) + "-a";
    pair.right = "rendered-" + std::to_string(k) + "-b";
    pair.leftImage = simulateCapture(renderRoom(*set.left, a, *room, {2}), 1.0, 0.0, 2.0, 2 * k + 1);
    pair.rightImage = simulateCapture(renderRoom(*set.right, b, *room, {2}), 0.85, 12.0, 2.0, 2 * k + 2);
    // X_a = R X_b + t: X_world = R_b^T X_b + C_b, X_a = R_a (X_world - C_a).
    pair.pose = RelativePose{a.rotation * b.rotation.t(), a.rotation * (b.centre - a.centre)};
    const CameraPtr lens = set.left;
    pair.truthInB = [lens, room, a, b](const cv::Point2d& pixelA) -> std::optional<cv::Point2d> {
      cv::Vec3d ray;
      if (!lens->pixelToBearing(pixelA, ray)) return std::nullopt;
      const auto point = roomPointSeen(a, *room, ray);
      cv::Point2d pixel;
      if (!point || !lens->bearingToPixel(b.rotation * (*point - b.centre), pixel)) return std::nullopt;
      return pixel;
    };
    set.pairs.push_back(std::move(pair));
  }
  return set;
}

double poseAuc(std::vector<double> errorsDeg, double limit) {
  if (errorsDeg.empty()) return 0;
  std::sort(errorsDeg.begin(), errorsDeg.end());
  // The recall curve through (0, 0) and (error k, k / n), linear between them (as SuperGlue and
  // LoFTR report pose AUC), flat past the last error below the limit.
  const double n = static_cast<double>(errorsDeg.size());
  double area = 0, x = 0, y = 0;
  for (size_t k = 0; k < errorsDeg.size() && errorsDeg[k] < limit; ++k) {
    const double nx = errorsDeg[k], ny = static_cast<double>(k + 1) / n;
    area += (nx - x) * (y + ny) / 2;
    x = nx, y = ny;
  }
  area += (limit - x) * y;
  return area / limit;
}

std::vector<StereoSummary> runStereo(const std::vector<StereoSet>& sets, const std::vector<TrackerPipeline>& pipelines,
                                     const StereoOptions& o, const std::string& outDir) {
  CsvTable pairsCsv({"set", "image_a", "image_b", "pipeline", "ratio", "keypoints_a", "keypoints_b", "matches",
                     "refined", "right", "residual_median_px", "fit_ok", "fit_inliers", "pose_error_deg"});
  CsvTable summaryCsv({"set", "pipeline", "ratio", "shown", "pairs", "keypoints", "matches_per_pair",
                       "right_per_pair", "precision", "residual_median_px", "residual_p90_px",
                       "residual_signed_mean_px", "fits_ok", "auc5",
                       "auc10", "auc20", "median_pose_error_deg", "median_rotation_error_deg",
                       "localisation_rms_px"});
  CsvTable matchesCsv({"set", "image_a", "image_b", "pipeline", "ratio", "a_x", "a_y", "a_z", "b_x", "b_y", "b_z",
                       "b_px_per_radian", "residual_px"});
  CsvTable posesCsv({"set", "image_a", "image_b", "r00", "r01", "r02", "r10", "r11", "r12", "r20", "r21", "r22",
                     "t_x", "t_y", "t_z"});
  // Ten significant digits: a bearing's %.6g would round it by 0.0005 px.
  const auto precise = [](double v) { return cv::format("%.10g", v); };
  std::vector<StereoSummary> rows;
  // Each pipeline, and after a library pipeline that o.refined names its refined row.
  std::vector<std::pair<TrackerPipeline, bool>> scored;
  for (const auto& p : pipelines) {
    scored.emplace_back(p, false);
    if (p.kind == TrackerPipeline::Kind::Library &&
        std::any_of(o.refined.begin(), o.refined.end(), [&](const std::string& prefix) { return p.name.rfind(prefix, 0) == 0; }))
      scored.emplace_back(p, true);
  }
  for (const auto& set : sets) {
    const CameraPtr& cameraA = set.left;
    const CameraPtr& cameraB = set.right;
    std::vector<cv::Mat> left(set.pairs.size()), right(set.pairs.size());
    for (size_t i = 0; i < set.pairs.size(); ++i) {
      const StereoPair& pair = set.pairs[i];
      left[i] = pair.leftImage.empty() ? readGrey(pair.left) : pair.leftImage;
      right[i] = pair.rightImage.empty() ? readGrey(pair.right) : pair.rightImage;
    }
    if (o.writeMatches)
      for (const StereoPair& pair : set.pairs) {
        const RelativePose pose = pair.pose.value_or(set.pose);
        CsvTable& row = posesCsv.row()
                            .add(set.name)
                            .add(fs::path(pair.left).filename().string())
                            .add(fs::path(pair.right).filename().string());
        for (int c = 0; c < 9; ++c) row.add(precise(pose.rotation.val[c]));
        for (int c = 0; c < 3; ++c) row.add(precise(pose.translation[c]));
      }
    const bool rendered = !set.pairs.empty() && set.pairs.front().truthInB;
    std::printf("\nstereo %s (%zu pairs, %d keypoints per image; counts and pose at each pipeline's best ratio, the "
                "residual of right matches at ratio %.2f)\n",
                set.name.c_str(), set.pairs.size(), o.budget, o.residualRatio);
    std::printf("  %-36s %5s %8s %7s %7s %7s %7s %7s %6s %9s %9s %9s%s\n", "pipeline", "ratio", "right", "precis", "AUC@5",
                "AUC@10", "AUC@20", "fits", "R-med", "res-med", "res-p90", "res-side",
                rendered ? "  loc-RMS   per level of b (right matches)" : "");
    for (const auto& row : scored) {
      const TrackerPipeline& p = row.first;
      const bool refine = row.second;
      const std::string name = refine ? p.name + " + refine" : p.name;
      std::vector<std::vector<StereoPairResult>> results(set.pairs.size());
      tbb::parallel_for(size_t(0), set.pairs.size(), [&](size_t i) {
        const Features fa = trackerFeatures(p, left[i], cameraA, {}, o.budget);
        const Features fb = trackerFeatures(p, right[i], cameraB, {}, o.budget);
        const RelativePose truth = set.pairs[i].pose.value_or(set.pose);
        if (refine) {
          const ImagePyramid pa(left[i], p.options.detector.pyramid), pb(right[i], p.options.detector.pyramid);
          results[i] = scorePair(fa, fb, *cameraA, *cameraB, set.pairs[i], truth, o, &pa, &pb);
        } else {
          results[i] = scorePair(fa, fb, *cameraA, *cameraB, set.pairs[i], truth, o);
        }
      });
      std::vector<StereoSummary> perRatio;
      for (size_t r = 0; r < o.ratios.size(); ++r) {
        StereoSummary s;
        s.set = set.name;
        s.pipeline = name;
        s.ratio = o.ratios[r];
        s.pairs = static_cast<int>(set.pairs.size());
        long matches = 0, right = 0;
        int ok = 0;
        std::vector<double> residuals, errors, rotationErrors;
        std::vector<std::pair<float, double>> bySize;
        std::vector<std::vector<double>> byLevel;
        double squares = 0, signedSum = 0;
        int located = 0;
        std::vector<double> levelSquares;
        for (size_t i = 0; i < set.pairs.size(); ++i) {
          const StereoPairResult& t = results[i][r];
          s.keypoints += 0.5 * (t.keypointsA + t.keypointsB);
          matches += t.matches;
          right += t.right;
          ok += t.fitOk;
          residuals.insert(residuals.end(), t.rightResidualsPx.begin(), t.rightResidualsPx.end());
          signedSum += t.rightSignedResidualSumPx;
          for (size_t k = 0; k < t.rightResidualsPx.size(); ++k) {
            bySize.emplace_back(t.rightSizes[k], t.rightResidualsPx[k]);
            const int level = t.rightLevels[k];
            if (p.kind != TrackerPipeline::Kind::Library || level < 0) continue;
            if (static_cast<int>(byLevel.size()) <= level) byLevel.resize(level + 1);
            byLevel[level].push_back(t.rightResidualsPx[k]);
          }
          errors.push_back(t.poseErrorDeg);
          rotationErrors.push_back(t.rotationErrorDeg);
          for (const auto& [level, error] : t.localisation) {
            squares += error * error, ++located;
            if (p.kind != TrackerPipeline::Kind::Library) continue;
            if (static_cast<int>(s.rightPerLevel.size()) <= level)
              s.rightPerLevel.resize(level + 1, 0), levelSquares.resize(level + 1, 0.0);
            ++s.rightPerLevel[level];
            levelSquares[level] += error * error;
          }
          pairsCsv.row()
              .add(set.name)
              .add(fs::path(set.pairs[i].left).filename().string())
              .add(fs::path(set.pairs[i].right).filename().string())
              .add(p.name)
              .add(s.ratio)
              .add(t.keypointsA)
              .add(t.keypointsB)
              .add(t.matches)
              .add(t.refined)
              .add(t.right)
              .add(quantile(t.rightResidualsPx, 0.5))
              .add(t.fitOk ? 1 : 0)
              .add(t.fitInliers)
              .add(t.poseErrorDeg);
          for (const auto& m : t.rightRows) {
            CsvTable& row = matchesCsv.row()
                                .add(set.name)
                                .add(fs::path(set.pairs[i].left).filename().string())
                                .add(fs::path(set.pairs[i].right).filename().string())
                                .add(name)
                                .add(s.ratio);
            for (int c = 0; c < 8; ++c) row.add(precise(m[c]));
          }
        }
        const double n = std::max<double>(1, s.pairs);
        s.keypoints /= n;
        s.matchesPerPair = static_cast<double>(matches) / n;
        s.rightPerPair = static_cast<double>(right) / n;
        s.precision = matches ? static_cast<double>(right) / static_cast<double>(matches) : 0;
        s.residualMedianPx = quantile(residuals, 0.5);
        s.residualP90Px = quantile(residuals, 0.9);
        s.residualSignedMeanPx = residuals.empty() ? 0.0 : signedSum / static_cast<double>(residuals.size());
        std::sort(bySize.begin(), bySize.end());
        for (int q = 0; q < 4; ++q) {
          std::vector<double> band;
          for (size_t k = bySize.size() * q / 4; k < bySize.size() * (q + 1) / 4; ++k) band.push_back(bySize[k].second);
          s.residualBySizeQuarter.push_back({band.empty() ? 0.f : bySize[bySize.size() * q / 4].first,
                                             quantile(band, 0.5), quantile(band, 0.9), static_cast<int>(band.size())});
        }
        for (const auto& band : byLevel)
          s.residualByLevel.push_back({0.f, quantile(band, 0.5), quantile(band, 0.9), static_cast<int>(band.size())});
        s.fitsOk = static_cast<double>(ok) / n;
        s.auc5 = poseAuc(errors, 5), s.auc10 = poseAuc(errors, 10), s.auc20 = poseAuc(errors, 20);
        s.medianPoseErrorDeg = quantile(errors, 0.5);
        s.medianRotationErrorDeg = quantile(rotationErrors, 0.5);
        s.localisationRmsPx = located ? std::sqrt(squares / located) : 0.0;
        for (size_t level = 0; level < levelSquares.size(); ++level)
          s.localisationRmsPerLevel.push_back(s.rightPerLevel[level] ? std::sqrt(levelSquares[level] / s.rightPerLevel[level]) : 0.0);
        perRatio.push_back(s);
      }
      // Best AUC at 5 degrees, then at 10, then the most right matches.
      const auto best = std::max_element(perRatio.begin(), perRatio.end(), [](const auto& x, const auto& y) {
        return std::tie(x.auc5, x.auc10, x.rightPerPair) < std::tie(y.auc5, y.auc10, y.rightPerPair);
      });
      const auto atResidualRatio = std::find_if(perRatio.begin(), perRatio.end(),
                                                [&](const auto& x) { return std::abs(x.ratio - o.residualRatio) < 1e-9; });
      const StereoSummary& residual = atResidualRatio != perRatio.end() ? *atResidualRatio : *best;
      std::printf("  %-36s %5.2f %8.1f %7.3f %7.3f %7.3f %7.3f %6.0f%% %5.2f° %7.3fpx %7.3fpx %+7.3fpx", name.c_str(),
                  best->ratio, best->rightPerPair, best->precision, best->auc5, best->auc10, best->auc20,
                  100 * best->fitsOk, best->medianRotationErrorDeg, residual.residualMedianPx, residual.residualP90Px,
                  residual.residualSignedMeanPx);
      if (rendered) {
        std::printf(" %7.3fpx  ", residual.localisationRmsPx);
        for (size_t level = 0; level < residual.localisationRmsPerLevel.size(); ++level)
          if (residual.rightPerLevel[level]) std::printf(" L%zu %.3f (%d)", level, residual.localisationRmsPerLevel[level], residual.rightPerLevel[level]);
      }
      std::printf("\n     by b's size from");
      for (const auto& q : residual.residualBySizeQuarter)
        std::printf("  %.0fpx %.3f/%.3f", q.fromSize, q.medianPx, q.p90Px);
      if (!residual.residualByLevel.empty()) std::printf("\n     by b's level");
      for (size_t level = 0; level < residual.residualByLevel.size(); ++level)
        if (residual.residualByLevel[level].count)
          std::printf("  L%zu %.3f/%.3f (%d)", level, residual.residualByLevel[level].medianPx,
                      residual.residualByLevel[level].p90Px, residual.residualByLevel[level].count);
      std::printf("\n");
      for (const auto& s : perRatio) {
        summaryCsv.row()
            .add(s.set)
            .add(s.pipeline)
            .add(s.ratio)
            .add(&s == &*best ? 1 : 0)
            .add(s.pairs)
            .add(s.keypoints)
            .add(s.matchesPerPair)
            .add(s.rightPerPair)
            .add(s.precision)
            .add(s.residualMedianPx)
            .add(s.residualP90Px)
            .add(s.residualSignedMeanPx)
            .add(s.fitsOk)
            .add(s.auc5)
            .add(s.auc10)
            .add(s.auc20)
            .add(s.medianPoseErrorDeg)
            .add(s.medianRotationErrorDeg)
            .add(s.localisationRmsPx);
        rows.push_back(s);
      }
    }
  }
  pairsCsv.write((fs::path(outDir) / "stereo_pairs.csv").string());
  summaryCsv.write((fs::path(outDir) / "stereo_summary.csv").string());
  if (o.writeMatches) {
    matchesCsv.write((fs::path(outDir) / "stereo_matches.csv").string());
    posesCsv.write((fs::path(outDir) / "stereo_poses.csv").string());
  }
  return rows;
}

}  // namespace mdbrief::eval
