#include "simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "csv_table.hpp"
#include "descriptor_method.hpp"
#include "eval_datasets.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/describe/patterns.hpp"
#include "mdbrief/api/presets.hpp"
#include "plane_geometry.hpp"
#include "toolkit/image_file.hpp"

namespace mdbrief::eval {
namespace {

constexpr double kDistance = 1.0;        // camera - plane distance of the reference view
constexpr double kSmallTexel = 0.001;    // projected experiment: graf1 spans 0.8 x 0.64 units
constexpr double kLargeTexel = 0.004;    // detected experiment: 3.2 x 2.56 units, fills the view
constexpr int kMarginPx = 24;            // the descriptor patch must fit (detector's border margin)

// An output file in o.outDir, which is created if missing.
std::string path(const SimOptions& o, const std::string& file) {
  std::filesystem::create_directories(o.outDir);
  return (std::filesystem::path(o.outDir) / file).string();
}

bool validWithMargin(const Camera& cam, const cv::Point2d& p) {
  return cam.isValid(p) && cam.isValid(p + cv::Point2d(kMarginPx, 0)) && cam.isValid(p - cv::Point2d(kMarginPx, 0)) &&
         cam.isValid(p + cv::Point2d(0, kMarginPx)) && cam.isValid(p - cv::Point2d(0, kMarginPx));
}

// Longest translation along X (step 0.01) for which the whole texture border stays in the
// camera's valid area: the path runs the plane from the image centre to the image edge (rim).
double pathLength(const Camera& cam, const PlaneScene& scene) {
  const double hw = scene.texture.cols * scene.texelSize / 2, hh = scene.texture.rows * scene.texelSize / 2;
  std::vector<cv::Point2d> border;
  for (int i = 0; i <= 40; ++i) {
    const double s = -1.0 + i / 20.0;
    border.insert(border.end(), {{s * hw, -hh}, {s * hw, hh}, {-hw, s * hh}, {hw, s * hh}});
  }
  double x = 0.0;
  for (double next = 0.01; next < 10.0; next += 0.01) {
    CameraPose pose;
    pose.centre = {next, 0, -kDistance};
    for (const auto& b : border) {
      cv::Point2d px;
      if (!projectPlanePoint(cam, pose, b, px) || !validWithMargin(cam, px)) return x;
    }
    x = next;
  }
  return x;
}

Features selectRows(const Features& f, const std::vector<int>& rows) {
  Features out;
  out.bits = f.bits;
  for (int r : rows) {
    out.keypoints.push_back(f.keypoints[r]);
    out.descriptors.push_back(f.descriptors.row(r));
    if (!f.masks.empty()) out.masks.push_back(f.masks.row(r));
  }
  return out;
}

std::map<int, int> rowsById(const Features& f) {
  std::map<int, int> m;
  for (size_t i = 0; i < f.keypoints.size(); ++i) m[f.keypoints[i].class_id] = static_cast<int>(i);
  return m;
}

void histogramAdd(std::vector<double>& h, double d) {
  const int b = std::clamp(static_cast<int>(std::floor(d)), 0, static_cast<int>(h.size()) - 1);
  h[b] += 1.0;
}

// The pairs 1-1, 1-4, 1-7, 1-10 of a 10-view sequence, scaled to other lengths.
std::vector<int> distributionPairs(int views) {
  std::vector<int> p;
  for (int i = 0; i < 4; ++i) p.push_back(static_cast<int>(std::lround((views - 1) * i / 3.0)));
  return p;
}

std::vector<MethodSpec> projectedMethods(const SimOptions& o) {
  return {briefFamilyMethod("BRIEF", DescriptorKind::Brief, o.bits, false),
          briefFamilyMethod("dBRIEF", DescriptorKind::DBrief, o.bits, false, DistortionForm::Paper),
          briefFamilyMethod("dBRIEF-affine", DescriptorKind::DBrief, o.bits, false, DistortionForm::Affine),
          briefFamilyMethod("mBRIEF", DescriptorKind::MaskedBrief, o.bits, false, DistortionForm::Affine, o.maskDeg),
          briefFamilyMethod("mdBRIEF", DescriptorKind::MdBrief, o.bits, false, DistortionForm::Paper, o.maskDeg),
          briefFamilyMethod("mdBRIEF-affine", DescriptorKind::MdBrief, o.bits, false, DistortionForm::Affine, o.maskDeg)};
}

// Descriptors of the projected plane points in one view, per method.
std::vector<Features> describeProjected(const SimCamera& sc, const PlaneScene& scene, const CameraPose& pose,
                                        const std::vector<cv::Point2d>& planePoints,
                                        const std::vector<MethodSpec>& methods, cv::Mat* imageOut = nullptr) {
  const cv::Mat image = renderPlane(*sc.camera, pose, scene);
  if (imageOut) *imageOut = image;
  std::vector<cv::KeyPoint> kps;
  for (size_t i = 0; i < planePoints.size(); ++i) {
    cv::Point2d px;
    if (projectPlanePoint(*sc.camera, pose, planePoints[i], px) && sc.camera->isValid(px))
      kps.emplace_back(cv::Point2f(px), 31.f, -1.f, 1.f, 0, static_cast<int>(i));
  }
  std::vector<Features> out;
  for (const auto& m : methods) out.push_back(describe(m, image, sc.camera, kps));
  return out;
}

// Plane-point ids described by every method in every view.
std::vector<int> commonIds(const std::vector<std::vector<Features>>& views) {
  std::set<int> common;
  bool first = true;
  for (const auto& perMethod : views)
    for (const auto& f : perMethod) {
      std::set<int> ids;
      for (const auto& kp : f.keypoints) ids.insert(kp.class_id);
      if (first) {
        common = ids;
        first = false;
      } else {
        std::set<int> both;
        std::set_intersection(common.begin(), common.end(), ids.begin(), ids.end(), std::inserter(both, both.begin()));
        common = both;
      }
    }
  return {common.begin(), common.end()};
}

}  // namespace

double bhattacharyya(const std::vector<double>& p, const std::vector<double>& q) {
  double sp = 0, sq = 0;
  for (double v : p) sp += v;
  for (double v : q) sq += v;
  if (sp <= 0 || sq <= 0) return 0.0;
  double bc = 0;
  for (size_t i = 0; i < std::min(p.size(), q.size()); ++i) bc += std::sqrt(p[i] / sp * q[i] / sq);
  return bc;
}

double maxRadialDisplacement(const Camera& radial, const Camera& pinhole) {
  const cv::Size s = radial.imageSize();
  double best = 0.0;
  auto visit = [&](double u, double v) {
    cv::Vec3d b;
    cv::Point2d p;
    if (radial.pixelToBearing({u, v}, b) && pinhole.bearingToPixel(b, p)) best = std::max(best, std::hypot(p.x - u, p.y - v));
  };
  for (int u = 0; u < s.width; ++u) visit(u, 0), visit(u, s.height - 1);
  for (int v = 0; v < s.height; ++v) visit(0, v), visit(s.width - 1, v);
  return best;
}

SimSummary runProjectedSimulation(const SimCamera& sc, double xEnd, const SimOptions& o) {
  PlaneScene scene{loadEvaluationImage(o.texturePath), kSmallTexel};
  std::vector<cv::KeyPoint> corners;
  cv::ORB::create(o.keypoints)->detect(scene.texture, corners);
  std::vector<cv::Point2d> planePoints;
  for (const auto& kp : corners) planePoints.push_back(texelToPlane(scene, kp.pt));
  const auto methods = projectedMethods(o);
  const size_t nm = methods.size();

  auto poseAt = [&](int k, int n) {
    CameraPose p;
    p.centre = {n > 1 ? xEnd * k / (n - 1) : 0.0, 0, -kDistance};
    return p;
  };

  // 1. Distance evolution over `views` positions.
  std::vector<std::vector<Features>> evo;
  std::vector<cv::Mat> shown;
  for (int k = 0; k < o.views; ++k) {
    cv::Mat img;
    evo.push_back(describeProjected(sc, scene, poseAt(k, o.views), planePoints, methods, &img));
    if (k == 0 || k == o.views / 2 || k == o.views - 1) {
      // The texture repeats mirrored over the whole plane: the keypoints show where it is.
      cv::cvtColor(img, img, cv::COLOR_GRAY2BGR);
      for (const auto& kp : evo.back()[0].keypoints) cv::circle(img, kp.pt, 3, cv::Scalar(0, 0, 255), -1);
      shown.push_back(img);
    }
  }
  cv::Mat strip;
  cv::hconcat(shown, strip);
  writeImageAtomically(path(o, "sim_" + sc.name + "_views.png"), strip);
  const std::vector<int> ids = commonIds(evo);
  if (ids.empty()) throw std::runtime_error("simulation " + sc.name + ": no keypoint is visible in every view");
  // The patch nearest the texture centre: it travels from the image centre to the edge.
  int patch = ids.front();
  for (int id : ids)
    if (cv::norm(planePoints[id]) < cv::norm(planePoints[patch])) patch = id;

  SimSummary summary;
  summary.camera = sc.name;
  summary.commonKeypoints = static_cast<int>(ids.size());
  for (const auto& m : methods) summary.methods.push_back(m.name);
  CsvTable evoCsv({"view", "method", "patch_distance", "mean_distance"});
  summary.patchDistanceLast.assign(nm, 0.0);
  summary.meanMatchingDistance.assign(nm, 0.0);
  for (size_t m = 0; m < nm; ++m) {
    const auto rows0 = rowsById(evo[0][m]);
    for (int k = 0; k < o.views; ++k) {
      const auto rowsK = rowsById(evo[k][m]);
      double mean = 0;
      for (int id : ids) mean += descriptorDistance(evo[0][m], rows0.at(id), evo[k][m], rowsK.at(id));
      mean /= ids.size();
      if (k > 0) summary.meanMatchingDistance[m] += mean / (o.views - 1);
      const double pd = descriptorDistance(evo[0][m], rows0.at(patch), evo[k][m], rowsK.at(patch));
      evoCsv.row().add(k + 1).add(methods[m].name).add(pd).add(mean);
      if (k == o.views - 1) summary.patchDistanceLast[m] = pd;
    }
  }
  evoCsv.write(path(o, "sim_" + sc.name + "_hamming_evolution.csv"));

  // 2./3. Recognition rate and distance distributions over `recognitionViews` views.
  std::vector<std::vector<Features>> rec;
  for (int k = 0; k < o.recognitionViews; ++k)
    rec.push_back(describeProjected(sc, scene, poseAt(k, o.recognitionViews), planePoints, methods));
  const std::vector<int> rids = commonIds(rec);
  CsvTable recCsv({"view", "method", "recognition_rate", "keypoints"});
  CsvTable distCsv({"pair", "method", "distance", "match_frequency", "nonmatch_frequency"});
  CsvTable bcCsv({"pair", "method", "bhattacharyya", "mean_match", "mean_nonmatch"});
  summary.recognitionAtLast.assign(nm, 0.0);
  summary.bhattacharyyaLast.assign(nm, 0.0);
  const std::vector<int> pairs = distributionPairs(o.recognitionViews);
  for (size_t m = 0; m < nm; ++m) {
    std::vector<Features> sel;
    for (int k = 0; k < o.recognitionViews; ++k) {
      const auto rows = rowsById(rec[k][m]);
      std::vector<int> r;
      for (int id : rids) r.push_back(rows.at(id));
      sel.push_back(selectRows(rec[k][m], r));
    }
    for (int k = 0; k < o.recognitionViews; ++k) {
      const auto nn = nearestNeighbours(sel[0], sel[k]);
      int correct = 0;
      for (const auto& d : nn) correct += d.queryIdx == d.trainIdx;
      const double rate = rids.empty() ? 0.0 : static_cast<double>(correct) / rids.size();
      recCsv.row().add(k + 1).add(methods[m].name).add(rate).add(static_cast<int>(rids.size()));
      if (k == o.recognitionViews - 1) summary.recognitionAtLast[m] = rate;
    }
    for (int k : pairs) {
      std::vector<double> hm(sel[0].bits + 1, 0.0), hn(sel[0].bits + 1, 0.0);
      double sm = 0, sn = 0;
      const int n = static_cast<int>(rids.size());
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double d = descriptorDistance(sel[0], i, sel[k], j);
          histogramAdd(i == j ? hm : hn, d);
          (i == j ? sm : sn) += d;
        }
      const std::string pairName = "1-" + std::to_string(k + 1);
      const double bc = bhattacharyya(hm, hn);
      bcCsv.row().add(pairName).add(methods[m].name).add(bc).add(sm / std::max(1, n)).add(sn / std::max(1, n * (n - 1)));
      if (k == pairs.back()) summary.bhattacharyyaLast[m] = bc;
      const double tm = std::max(1, n), tn = std::max(1, n * (n - 1));
      for (size_t b = 0; b < hm.size(); ++b)
        if (hm[b] > 0 || hn[b] > 0)
          distCsv.row().add(pairName).add(methods[m].name).add(static_cast<int>(b)).add(hm[b] / tm).add(hn[b] / tn);
    }
  }
  recCsv.write(path(o, "sim_" + sc.name + "_recognition.csv"));
  distCsv.write(path(o, "sim_" + sc.name + "_distributions.csv"));
  bcCsv.write(path(o, "sim_" + sc.name + "_bhattacharyya.csv"));
  return summary;
}

namespace {

void runDetectedVariant(const SimCamera& sc, const SimOptions& o, const std::string& variant, double rollDeg,
                        bool oriented) {
  PlaneScene scene{loadEvaluationImage(o.texturePath), kLargeTexel};
  const double defaultMask = DescriptorOptions{}.maskRotationDeg;
  std::vector<MethodSpec> methods{
      briefFamilyMethod("BRIEF", DescriptorKind::Brief, o.bits, oriented),
      briefFamilyMethod("mBRIEF", DescriptorKind::MaskedBrief, o.bits, oriented, DistortionForm::Affine, defaultMask),
      briefFamilyMethod("dBRIEF-paper", DescriptorKind::DBrief, o.bits, oriented, DistortionForm::Paper),
      briefFamilyMethod("dBRIEF-affine", DescriptorKind::DBrief, o.bits, oriented, DistortionForm::Affine)};
  for (const DistortionForm form : {DistortionForm::Paper, DistortionForm::Affine})
    for (double a : o.maskAngles) {
      char name[64];
      std::snprintf(name, sizeof name, "mdBRIEF-%s-%g", toString(form).c_str(), a);
      methods.push_back(briefFamilyMethod(name, DescriptorKind::MdBrief, o.bits, oriented, form, a));
    }
  if (oriented) {
    // The same descriptors with the detector's angle (measured on a disc of the distorted
    // image) instead of the one re-measured on the tangent plane.
    for (MethodSpec m : {methods[3], briefFamilyMethod("mdBRIEF-affine", DescriptorKind::MdBrief, o.bits, true,
                                                       DistortionForm::Affine, defaultMask)}) {
      m.name += m.options.kind == DescriptorKind::MdBrief ? "-" + std::to_string(static_cast<int>(defaultMask)) + "-kp" : "-kp";
      m.options.orientation = OrientationSource::Keypoint;
      methods.push_back(m);
    }
  }
  const size_t nm = methods.size();
  // The paper's detector: modORB on cv::ORB's pyramid.
  DetectorOptions dopt = presetSettings(Preset::Paper).features.detector;
  dopt.nfeatures = o.detectedKeypoints;
  const Detector detector(sc.camera, dopt);

  // Reference view faces the plane; the last view is translated, yawed, pitched and rolled so
  // the reference view's centre is seen close to the rim (about 78 degrees off-axis).
  auto poseAt = [&](int k) {
    const double t = o.detectedViews > 1 ? static_cast<double>(k) / (o.detectedViews - 1) : 0.0;
    CameraPose p;
    p.centre = {1.4 * t, 0.4 * t, -kDistance};
    p.rotation = cameraRotation(25.0 * t, -10.0 * t, rollDeg * t);
    return p;
  };
  struct View {
    CameraPose pose;
    std::vector<Features> f;  // per method, restricted to keypoints every method described
  };
  std::vector<View> views;
  std::vector<cv::Mat> shown;
  for (int k = 0; k < o.detectedViews; ++k) {
    View v;
    v.pose = poseAt(k);
    const cv::Mat image = renderPlane(*sc.camera, v.pose, scene);
    if (k == 0 || k == o.detectedViews - 1) shown.push_back(image);
    std::vector<cv::KeyPoint> kps;
    for (auto kp : detector.detect(image)) {
      const auto plane = pixelToPlane(*sc.camera, v.pose, kp.pt);
      if (!plane || !onTexture(scene, *plane)) continue;  // the mirrored continuation repeats texture
      kp.class_id = static_cast<int>(kps.size());
      kps.push_back(kp);
    }
    std::vector<Features> all;
    for (const auto& m : methods) all.push_back(describe(m, image, sc.camera, kps));
    const std::vector<int> ids = commonIds({all});
    for (auto& f : all) {
      const auto rows = rowsById(f);
      std::vector<int> r;
      for (int id : ids) r.push_back(rows.at(id));
      v.f.push_back(selectRows(f, r));
    }
    views.push_back(std::move(v));
  }
  cv::Mat strip;
  cv::hconcat(shown, strip);
  const std::string stem = "sim_detected_" + sc.name + "_" + variant;
  writeImageAtomically(path(o, stem + "_views.png"), strip);

  CsvTable perView({"view", "method", "ground_truth", "recognition_rate", "mean_match_distance"});
  // Averages over the views with enough true matches; "last" = the last such view.
  CsvTable summary({"method", "form", "orientation", "mask_deg", "views_used", "mean_recognition", "rim_recognition", "last_view",
                    "last_recognition", "bhattacharyya_last", "mean_match_distance_last"});
  const View& ref = views[0];
  for (size_t m = 0; m < nm; ++m) {
    // Views with fewer true matches than this (the plane leaving a narrower lens) are left out
    // of the averages: their rates are noise.
    constexpr int kMinGroundTruth = 20;
    double sumRate = 0, sumRim = 0, lastRate = 0, lastBc = 0, lastMatch = 0;
    int used = 0, rimCount = 0, lastView = 0;
    for (int k = 1; k < o.detectedViews; ++k) {
      const View& v = views[k];
      const Features& q = ref.f[m];
      const Features& t = v.f[m];
      // Projected true position of every reference keypoint in view k.
      std::vector<cv::Point2d> truePos(q.keypoints.size());
      std::vector<int> gt(q.keypoints.size(), -1);
      for (size_t i = 0; i < q.keypoints.size(); ++i) {
        const auto plane = pixelToPlane(*sc.camera, ref.pose, q.keypoints[i].pt);
        cv::Point2d px;
        if (!plane || !projectPlanePoint(*sc.camera, v.pose, *plane, px)) continue;
        truePos[i] = px;
        double best = o.matchRadiusPx;
        for (size_t j = 0; j < t.keypoints.size(); ++j) {
          const double d = cv::norm(cv::Point2d(t.keypoints[j].pt) - px);
          if (d <= best) best = d, gt[i] = static_cast<int>(j);
        }
      }
      const auto nn = nearestNeighbours(q, t);
      int nGt = 0, correct = 0;
      double matchSum = 0;
      std::vector<double> hm(q.bits + 1, 0.0), hn(q.bits + 1, 0.0);
      for (const auto& d : nn) {
        const int i = d.queryIdx;
        if (gt[i] < 0) continue;
        ++nGt;
        correct += cv::norm(cv::Point2d(t.keypoints[d.trainIdx].pt) - truePos[i]) <= o.matchRadiusPx;
        matchSum += descriptorDistance(q, i, t, gt[i]);
        for (size_t j = 0; j < t.keypoints.size(); ++j) {
          const bool near = cv::norm(cv::Point2d(t.keypoints[j].pt) - truePos[i]) <= o.matchRadiusPx;
          if (static_cast<int>(j) == gt[i] || !near)
            histogramAdd(near ? hm : hn, descriptorDistance(q, i, t, static_cast<int>(j)));
        }
      }
      const double rate = nGt ? static_cast<double>(correct) / nGt : 0.0;
      const double meanMatch = nGt ? matchSum / nGt / q.bits : 0.0;
      perView.row().add(k + 1).add(methods[m].name).add(nGt).add(rate).add(meanMatch);
      if (nGt < kMinGroundTruth) continue;
      sumRate += rate, ++used;
      if (2 * k >= o.detectedViews) sumRim += rate, ++rimCount;
      lastView = k + 1, lastRate = rate, lastBc = bhattacharyya(hm, hn), lastMatch = meanMatch;
    }
    const auto& opt = methods[m].options;
    // BRIEF and masked BRIEF always use the keypoint's angle (OrientationSource::TangentPlane
    // applies to the distorted kinds only).
    const bool distorted = isDistorted(methods[m]);
    const std::string orientation =
        !oriented ? "none" : toString(distorted ? opt.orientation : OrientationSource::Keypoint);
    summary.row()
        .add(methods[m].name)
        .add(distorted ? toString(opt.form) : std::string("none"))
        .add(orientation)
        .add(isMasked(methods[m]) ? opt.maskRotationDeg : 0.0)
        .add(used)
        .add(used ? sumRate / used : 0.0)
        .add(rimCount ? sumRim / rimCount : 0.0)
        .add(lastView)
        .add(lastRate)
        .add(lastBc)
        .add(lastMatch);
  }
  perView.write(path(o, stem + ".csv"));
  summary.write(path(o, stem + "_summary.csv"));
}

}  // namespace

void runDetectedSimulation(const SimCamera& sc, const SimOptions& o) {
  runDetectedVariant(sc, o, "rolled", 45.0, true);
  runDetectedVariant(sc, o, "upright", 0.0, false);
  // Separates the effect of the detector's orientation from that of the roll.
  runDetectedVariant(sc, o, "upright_oriented", 0.0, true);
}

void runSimulation(const std::vector<SimCamera>& cameras, const SimOptions& o) {
  std::filesystem::create_directories(o.outDir);
  CsvTable info({"camera", "key", "value"});
  const PlaneScene scene{loadEvaluationImage(o.texturePath), kSmallTexel};
  double shared = -1.0;
  for (const auto& c : cameras)
    if (c.name == o.sharedPathCamera) shared = pathLength(*c.camera, scene);
  for (const auto& c : cameras) {
    double xEnd = c.pathLength > 0 ? c.pathLength : pathLength(*c.camera, scene);
    if (c.pathLength == 0.0 && shared > 0) xEnd = shared;
    info.row().add(c.name).add(std::string("path_length_x")).add(xEnd);
    if (o.runProjected) {
      std::fprintf(stderr, "sim: projected keypoints, camera %s\n", c.name.c_str());
      const SimSummary s = runProjectedSimulation(c, xEnd, o);
      info.row().add(c.name).add(std::string("common_keypoints")).add(s.commonKeypoints);
    }
    // One detected experiment per lens (the *_rim entries repeat a lens with another path).
    const bool rimVariant = c.pathLength < 0;
    if (o.runDetected && !rimVariant) {
      std::fprintf(stderr, "sim: detected keypoints, tilted poses, camera %s\n", c.name.c_str());
      runDetectedSimulation(c, o);
    }
  }
  // The radial camera's displacement against the pinhole camera with the same intrinsics.
  for (const auto& r : cameras)
    for (const auto& p : cameras)
      if (r.camera->modelName() == "radial" && p.camera->modelName() == "pinhole")
        info.row().add(r.name).add(std::string("max_displacement_px")).add(maxRadialDisplacement(*r.camera, *p.camera));
  info.row().add(std::string("all")).add(std::string("default_test_set")).add(defaultComparisonSetName());
  info.write(path(o, "sim_info.csv"));
}

}  // namespace mdbrief::eval
