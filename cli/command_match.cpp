// `mdbrief match`: brute-force matching of two `extract` outputs, masked (mdBRIEF's masked
// Hamming distance) when both files have masks, plain Hamming otherwise; with --refine, B's side
// of each match refined to sub-pixel accuracy (match_refinement.hpp) on the images the files
// were extracted from; with --inliers, how many matches agree with a model of the two views
// (match_consistency.hpp): by default the essential matrix on the bearings of --camera (and
// --camera-b for B), or the rig's relative pose.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/consistency_flags.hpp"
#include "cli/extraction_flags.hpp"
#include "cli/match_consistency.hpp"
#include "cli/storage_io.hpp"
#include "mdbrief/internal/base/size_text.hpp"
#include "mdbrief/match/match_refinement.hpp"
#include "mdbrief/match/matcher.hpp"
#include "mdbrief/api/presets.hpp"
#include "toolkit/option_flags.hpp"
#include "mdbrief/geometry/two_view.hpp"

namespace mdbrief::cli {
namespace {

struct MatchArgs {
  std::string query;
  std::string train;
  std::string preset = toString(Preset::Tracking);
  OptionFlags<MatchOptions> options;  // MatchOptions' field table: --ratio, --no-cross-check, --max-distance
  bool noRatio = false;
  bool inliers = false;
  CameraFileFlags camera;   // the bearings for --inliers and --refine; none: the pixels' own plane
  CameraFileFlags cameraB;  // B's, when another camera took it (a rig's second camera)
  std::string model = toString(ConsistencyModel::Auto);
  double thresholdPx = MatchConsistencyOptions{}.thresholdPx;
  bool refine = false;
  std::string imageA, imageB;                        // the images A and B were extracted from
  OptionFlags<MatchRefinementOptions> refinement;    // --refine-patch-radius, --refine-max-shift, ...
  std::string output;
};

// The calibrations of A and B (null without one), each checked against the camera digest its
// file records.
struct Calibrations {
  CameraPtr a, b;
};

Calibrations readCalibrations(const MatchArgs& args, const Features& a, const Features& b) {
  const CameraFileFlags cameraB = secondCameraFlags(args.camera, args.cameraB);
  Calibrations c;
  c.a = args.camera.path.empty() ? nullptr : CameraPtr(readCalibrationFile(args.camera).camera);
  c.b = cameraB.path.empty() ? c.a : CameraPtr(readCalibrationFile(cameraB).camera);
  for (const auto* f : {&a, &b}) {
    const CameraPtr& calibration = f == &a ? c.a : c.b;
    if (calibration && !f->provenance.cameraDigest.empty() && f->provenance.cameraDigest != cameraDigest(*calibration))
      throw InputError((f == &a || cameraB.path.empty() ? "--camera " + args.camera.path : "--camera-b " + cameraB.path) +
                       ": not the calibration " + (f == &a ? args.query : args.train) +
                       " was described with (camera digest " + cameraDigest(*calibration) + ", the file records " +
                       f->provenance.cameraDigest + ")");
  }
  return c;
}

// One side of --refine: the pyramid of the image the file's keypoints were detected on, rebuilt
// with the detection's options so that their octaves are its levels, and the camera.
struct RefinementSide {
  ImagePyramid pyramid;
  CameraPtr camera;
};

RefinementSide refinementSide(const Features& f, const std::string& file, const std::string& imageFlag,
                              const std::string& image, const CameraPtr& calibration, const std::string& cameraFlag) {
  const Provenance& p = f.provenance;
  if (p.pyramid.empty() || p.imageDigest.empty())
    throw InputError(file + ": --refine needs the pyramid options and the image the keypoints were detected on, "
                            "which this file does not record (written before they were): extract it again");
  const PyramidOptions pyramid = pyramidFromText(p.pyramid, file + ": node 'pyramid'");
  const cv::Mat pixels = loadImage(image, false);
  const std::string size = internal::sizeText(pixels.size()), digest = imageDigest(pixels);
  if (size != p.imageSize || digest != p.imageDigest)
    throw InputError(imageFlag + " " + image + ": not the image " + file + " was extracted from (" + size +
                     ", image digest " + digest + "; the file records " + p.imageSize + ", " + p.imageDigest + ")");
  if (!calibration && !p.cameraDigest.empty())
    throw InputError(file + ": described with a calibration (camera digest " + p.cameraDigest +
                     "): --refine needs it, give it with " + cameraFlag);
  // Without a calibration the lens is taken for a pinhole. A calibration of another size was
  // rescaled to the image by extract --allow-size-mismatch: the same here.
  CameraPtr camera = calibration ? calibration : pixelPlaneCamera(pixels.size());
  if (camera->imageSize() != pixels.size()) camera = camera->resized(pixels.size());
  return {ImagePyramid(pixels, pyramid), camera};
}

// The camera the keypoints of `features` were detected with; without a calibration, a pinhole
// stand-in spanning the keypoints (pixelPlaneCamera).
CameraPtr cameraForInliers(const CameraPtr& calibration, const Features& features) {
  if (calibration) return calibration;
  // Bounded, so that a file's far-off or infinite keypoint cannot overflow the size.
  const float limit = 1e6f;
  float width = 1, height = 1;
  for (const auto& kp : features.keypoints) width = std::max(width, kp.pt.x + 1), height = std::max(height, kp.pt.y + 1);
  return pixelPlaneCamera({static_cast<int>(std::ceil(std::min(width, limit))),
                           static_cast<int>(std::ceil(std::min(height, limit)))});
}

// "<count> inliers (<method>)" for the matches, whose rows index a and b; B's side at its
// refined points where there are any (one per match).
std::string inlierSummary(const MatchArgs& args, const Features& a, const Features& b, const Calibrations& calibrations,
                          const std::vector<cv::DMatch>& matches, const std::vector<RefinedMatch>& refined) {
  std::vector<cv::Point2f> pointsA, pointsB;
  for (const auto& kp : a.keypoints) pointsA.push_back(kp.pt);
  std::vector<std::pair<int, int>> pairs;
  if (refined.empty()) {
    for (const auto& kp : b.keypoints) pointsB.push_back(kp.pt);
    for (const auto& m : matches) pairs.emplace_back(m.queryIdx, m.trainIdx);
  } else {
    for (size_t m = 0; m < matches.size(); ++m) {
      pointsB.push_back(refined[m].pointB);
      pairs.emplace_back(matches[m].queryIdx, static_cast<int>(m));
    }
  }
  MatchConsistencyOptions consistency;
  consistency.thresholdPx = args.thresholdPx;
  consistency.model = parseName(args.model, kConsistencyModelNames, "--model");
  consistency.calibrated = calibrations.a != nullptr;
  if (consistency.model == ConsistencyModel::KnownPose)
    setRigPose(args.camera, secondCameraFlags(args.camera, args.cameraB), consistency);
  const MatchConsistency verdict = classifyMatches(*cameraForInliers(calibrations.a, a),
                                                   *cameraForInliers(calibrations.b, b), pointsA, pointsB, pairs,
                                                   consistency);
  return std::to_string(verdict.correctCount) + " inliers (" + verdict.method + ")";
}

// One row per match: B's refined x, y (input pixels; B's keypoint where it failed), sigma_px
// (-1 where it failed: JSON has no infinity), the finest level refined on (-1), and the
// failure (RefinementFailure: 0 refined, 1 outside the image, 2 aperture, 3 diverged, 4 uncertain).
cv::Mat refinedTable(const std::vector<RefinedMatch>& refined) {
  cv::Mat table(static_cast<int>(refined.size()), 5, CV_64F);
  for (int i = 0; i < table.rows; ++i) {
    const RefinedMatch& r = refined[i];
    double* row = table.ptr<double>(i);
    row[0] = r.pointB.x, row[1] = r.pointB.y;
    row[2] = r.ok() ? r.sigmaPx : -1.0;
    row[3] = r.level;
    row[4] = static_cast<int>(r.failure);
  }
  return table;
}

void runMatch(const MatchArgs& args) {
  MatchOptions options;
  MatchRefinementOptions refinement;
  try {
    options = args.options.apply(presetSettings(parsePreset(args.preset)).matching,
                                 [](const MatchOptions& o) { validate(o); });
    refinement = args.refinement.apply({}, [](const MatchRefinementOptions& o) { validate(o); });
  } catch (const OptionError& e) {
    throw InputError(e.what());
  }
  if (args.noRatio) options.ratio.reset();
  if (!args.inliers && !args.refine &&
      (!args.camera.path.empty() || !args.cameraB.path.empty() || args.cameraB.anyGiven()))
    throw InputError("--camera and --camera-b are used only with --inliers or --refine");
  if (args.camera.path.empty() && args.camera.anyGiven()) throw InputError(args.camera.flagNames() + " need --camera");
  if (!args.refine && (!args.imageA.empty() || !args.imageB.empty() || args.refinement.anyGiven()))
    throw InputError("--image-a, --image-b and the --refine-* flags are used only with --refine");
  if (args.refine && (args.imageA.empty() || args.imageB.empty()))
    throw InputError("--refine needs --image-a and --image-b, the images A and B were extracted from");
  checkConsistencyModel(args.model, args.camera, secondCameraFlags(args.camera, args.cameraB));
  checkStorageOutput(args.output);
  checkOutputsApart({args.query, args.train, args.camera.path, args.cameraB.path, args.imageA, args.imageB},
                    {args.output});
  const Features a = readFeatureFile(args.query);
  const Features b = readFeatureFile(args.train);
  if (!a.descriptors.empty() && !b.descriptors.empty() && a.descriptors.cols != b.descriptors.cols)
    throw InputError(args.query + " and " + args.train + ": descriptor lengths differ (" +
                     std::to_string(a.descriptors.cols * 8) + " vs " + std::to_string(b.descriptors.cols * 8) +
                     " bits)");
  // Files that record their test sets must share one: other tests give unrelated bits.
  const Provenance &pa = a.provenance, &pb = b.provenance;
  if (!pa.testSetDigest.empty() && !pb.testSetDigest.empty() && pa.testSetDigest != pb.testSetDigest)
    throw InputError(args.query + " and " + args.train + ": described with different test sets (" + pa.testSet + " " +
                     pa.testSetDigest + ", " + pb.testSet + " " + pb.testSetDigest + ")");
  for (const auto& [needed, flag] : {std::pair(args.inliers, "--inliers"), std::pair(args.refine, "--refine")})
    for (const auto* f : {&a, &b})
      if (needed && f->keypoints.size() != static_cast<size_t>(f->descriptors.rows))
        throw InputError((f == &a ? args.query : args.train) + ": " + flag + " needs the keypoints (node 'keypoints')");
  const Calibrations calibrations = args.inliers || args.refine ? readCalibrations(args, a, b) : Calibrations{};
  std::optional<RefinementSide> sideA, sideB;
  if (args.refine) {
    sideA = refinementSide(a, args.query, "--image-a", args.imageA, calibrations.a, "--camera");
    sideB = refinementSide(b, args.train, "--image-b", args.imageB, calibrations.b,
                           args.cameraB.path.empty() ? "--camera (or --camera-b)" : "--camera-b");
  }
  // refineMatches checks the keypoints (octaves that are levels, finite positions) and the
  // cameras before it refines anything: on no match, that refuses bad input before the matching.
  const auto refine = [&](const std::vector<cv::DMatch>& matches) {
    try {
      return refineMatches(sideA->pyramid, *sideA->camera, a.keypoints, sideB->pyramid, *sideB->camera, b.keypoints,
                           matches, refinement);
    } catch (const std::invalid_argument& e) {
      std::string message = e.what();
      for (const auto& [from, to] : {std::pair("refineMatches: keypointsA", args.query + ": keypoints"),
                                     std::pair("refineMatches: keypointsB", args.train + ": keypoints")})
        if (message.rfind(from, 0) == 0) message = to + message.substr(std::string(from).size());
      throw InputError("--refine: " + message);
    }
  };
  if (args.refine) refine({});

  const bool masked = !a.masks.empty() && !b.masks.empty();
  const std::vector<cv::DMatch> matches =
      masked ? matchBruteForceMasked(a.descriptors, a.masks, b.descriptors, b.masks, options)
             : matchBruteForce(a.descriptors, b.descriptors, options);
  const std::vector<RefinedMatch> refined = args.refine ? refine(matches) : std::vector<RefinedMatch>{};

  // One row per match: query row, train row, distance in bits (masked: the scaled masked
  // distance of masked_hamming.hpp). CV_64F keeps the indices exact.
  cv::Mat table(static_cast<int>(matches.size()), 3, CV_64F);
  for (int i = 0; i < table.rows; ++i) {
    table.at<double>(i, 0) = matches[i].queryIdx;
    table.at<double>(i, 1) = matches[i].trainIdx;
    table.at<double>(i, 2) = matches[i].distance;
  }
  const std::string inliers =
      args.inliers ? ", " + inlierSummary(args, a, b, calibrations, matches, refined) : "";
  const auto refinedCount = std::count_if(refined.begin(), refined.end(), [](const RefinedMatch& r) { return r.ok(); });
  writeStorageAtomically(args.output, [&](cv::FileStorage& storage) {
    storage << "query" << args.query << "train" << args.train;
    storage << "masked" << static_cast<int>(masked);
    storage << "matches" << table;
    if (args.refine) storage << "refined" << refinedTable(refined);
    // What draw checks its images against (issue 45: swapped images were drawn, exit 0).
    storage << "query_digest" << descriptorDigest(a.descriptors) << "train_digest" << descriptorDigest(b.descriptors);
  });
  std::cout << args.query << " x " << args.train << ": " << matches.size() << (masked ? " masked" : "")
            << " matches" << (args.refine ? ", " + std::to_string(refinedCount) + " refined" : "") << inliers << " -> "
            << args.output << "\n";
}

}  // namespace

void addMatchCommand(CLI::App& app) {
  auto args = std::make_shared<MatchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "match",
      "Match the descriptors of two extract outputs (brute force; masked Hamming distance when both have masks). "
      "Output: node 'matches', an N x 3 CV_64F matrix whose rows are (query row in A, train row in B, distance in "
      "bits), in query order; also 'query', 'train' (the input files), 'masked' (0/1) and 'query_digest', "
      "'train_digest' (digests of A's and B's descriptors, which draw --matches checks its images against). With "
      "--refine also node 'refined', N x 5 CV_64F, row i for match i: (x, y) B's refined position in pixels (B's "
      "keypoint where it failed), sigma_px (standard deviation along the least certain direction; -1 where it "
      "failed), the finest pyramid level refined on (-1), and the failure (0 refined, 1 patch outside the image or "
      "the lens, 2 aperture: an edge or flat patch, 3 diverged, 4 uncertain: sigma_px above --refine-max-sigma-px).");
  cmd->add_option("A", args->query, "Query features (extract output)")
      ->check(inputFileCheck())->required();
  cmd->add_option("B", args->train, "Train features (extract output)")
      ->check(inputFileCheck())->required();
  cmd->add_option("--preset", args->preset,
                  "Start from this preset's matcher settings (mdbrief/api/presets.hpp); the flags below change them")
      ->check(CLI::IsMember(namesOf(kPresetNames)))
      ->capture_default_str();
  args->options.add(*cmd, matchOptionFields());
  cmd->add_flag("--no-ratio", args->noRatio, "Disable the ratio test");
  cmd->add_flag("--inliers", args->inliers,
                "Also print how many matches agree with a model of the two views fitted on their bearings, and "
                "which model (needs the keypoints in A and B)");
  cmd->add_option("--camera", args->camera.path,
                  "Calibration of A (and of B without --camera-b) for --inliers and --refine; without it --inliers "
                  "fits a homography on the pixels")
      ->check(inputFileCheck());
  addCameraFileFlags(*cmd, args->camera, "--camera");
  cmd->add_option("--camera-b", args->cameraB.path,
                  "Calibration of B when another camera took it; --camera-b-id alone: another camera of --camera's "
                  "file (a rig)")
      ->check(inputFileCheck());
  addCameraFileFlags(*cmd, args->cameraB, "--camera-b");
  cmd->add_flag("--refine", args->refine,
                "Refine B's side of each match to sub-pixel accuracy: B's patch aligned with A's by Lucas-Kanade on "
                "the pyramid levels, on the planes tangent to the cameras' rays (node 'refined'; --inliers then "
                "counts on the refined points). Needs --image-a, --image-b and, for files described with a "
                "calibration, --camera (--camera-b); without one the lens is taken for a pinhole");
  cmd->add_option("--image-a", args->imageA, "--refine: the image A was extracted from (checked against the file)")
      ->check(inputFileCheck());
  cmd->add_option("--image-b", args->imageB, "--refine: the image B was extracted from (checked against the file)")
      ->check(inputFileCheck());
  args->refinement.add(*cmd, matchRefinementOptionFields());
  addModelFlag(*cmd, args->model);
  cmd->add_option("--inlier-threshold", args->thresholdPx, "--inliers: a match agrees within this many pixels of the fit")
      ->check(fieldRangeCheck(twoViewOptionFields(), "max_pixels"))
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output, "Output FileStorage file (.yml, .yml.gz, .json)")->required();
  cmd->callback([args] { runMatch(*args); });
}

}  // namespace mdbrief::cli
