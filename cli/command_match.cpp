// `mdbrief match`: brute-force matching of two `extract` outputs, masked (mdBRIEF's masked
// Hamming distance) when both files have masks, plain Hamming otherwise; with --inliers, how many
// matches agree with a model of the two views (match_consistency.hpp): by default the essential
// matrix on the bearings of --camera (and --camera-b for B), or the rig's relative pose.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/consistency_flags.hpp"
#include "cli/extraction_flags.hpp"
#include "cli/match_consistency.hpp"
#include "cli/storage_io.hpp"
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
  CameraFileFlags camera;   // the bearings for --inliers; none: the pixels' own plane
  CameraFileFlags cameraB;  // B's, when another camera took it (a rig's second camera)
  std::string model = toString(ConsistencyModel::Auto);
  double thresholdPx = MatchConsistencyOptions{}.thresholdPx;
  std::string output;
};

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

// "<count> inliers (<method>)" for the matches, whose rows index a and b.
std::string inlierSummary(const MatchArgs& args, const Features& a, const Features& b,
                          const std::vector<cv::DMatch>& matches) {
  for (const auto* f : {&a, &b})
    if (f->keypoints.size() != static_cast<size_t>(f->descriptors.rows))
      throw InputError((f == &a ? args.query : args.train) + ": --inliers needs the keypoints (node 'keypoints')");
  const CameraFileFlags cameraB = secondCameraFlags(args.camera, args.cameraB);
  const CameraPtr calibrationA = args.camera.path.empty() ? nullptr : CameraPtr(readCalibrationFile(args.camera).camera);
  const CameraPtr calibrationB = cameraB.path.empty() ? calibrationA : CameraPtr(readCalibrationFile(cameraB).camera);
  for (const auto* f : {&a, &b}) {
    const CameraPtr& calibration = f == &a ? calibrationA : calibrationB;
    if (calibration && !f->provenance.cameraDigest.empty() && f->provenance.cameraDigest != cameraDigest(*calibration))
      throw InputError((f == &a || cameraB.path.empty() ? "--camera " + args.camera.path : "--camera-b " + cameraB.path) +
                       ": not the calibration " + (f == &a ? args.query : args.train) +
                       " was described with (camera digest " + cameraDigest(*calibration) + ", the file records " +
                       f->provenance.cameraDigest + ")");
  }
  std::vector<cv::Point2f> pointsA, pointsB;
  for (const auto& kp : a.keypoints) pointsA.push_back(kp.pt);
  for (const auto& kp : b.keypoints) pointsB.push_back(kp.pt);
  std::vector<std::pair<int, int>> pairs;
  for (const auto& m : matches) pairs.emplace_back(m.queryIdx, m.trainIdx);
  MatchConsistencyOptions consistency;
  consistency.thresholdPx = args.thresholdPx;
  consistency.model = parseName(args.model, kConsistencyModelNames, "--model");
  consistency.calibrated = calibrationA != nullptr;
  if (consistency.model == ConsistencyModel::KnownPose) setRigPose(args.camera, cameraB, consistency);
  const MatchConsistency verdict =
      classifyMatches(*cameraForInliers(calibrationA, a), *cameraForInliers(calibrationB, b), pointsA, pointsB, pairs,
                      consistency);
  return std::to_string(verdict.correctCount) + " inliers (" + verdict.method + ")";
}

void runMatch(const MatchArgs& args) {
  MatchOptions options;
  try {
    options = args.options.apply(presetSettings(parsePreset(args.preset)).matching,
                                 [](const MatchOptions& o) { validate(o); });
  } catch (const OptionError& e) {
    throw InputError(e.what());
  }
  if (args.noRatio) options.ratio.reset();
  if (!args.inliers && (!args.camera.path.empty() || !args.cameraB.path.empty() || args.cameraB.anyGiven()))
    throw InputError("--camera and --camera-b are used only with --inliers");
  if (args.camera.path.empty() && args.camera.anyGiven()) throw InputError(args.camera.flagNames() + " need --camera");
  checkConsistencyModel(args.model, args.camera, secondCameraFlags(args.camera, args.cameraB));
  checkStorageOutput(args.output);
  checkOutputsApart({args.query, args.train, args.camera.path, args.cameraB.path}, {args.output});
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
  const bool masked = !a.masks.empty() && !b.masks.empty();
  const std::vector<cv::DMatch> matches =
      masked ? matchBruteForceMasked(a.descriptors, a.masks, b.descriptors, b.masks, options)
             : matchBruteForce(a.descriptors, b.descriptors, options);

  // One row per match: query row, train row, distance in bits (masked: the scaled masked
  // distance of masked_hamming.hpp). CV_64F keeps the indices exact.
  cv::Mat table(static_cast<int>(matches.size()), 3, CV_64F);
  for (int i = 0; i < table.rows; ++i) {
    table.at<double>(i, 0) = matches[i].queryIdx;
    table.at<double>(i, 1) = matches[i].trainIdx;
    table.at<double>(i, 2) = matches[i].distance;
  }
  const std::string inliers = args.inliers ? ", " + inlierSummary(args, a, b, matches) : "";
  writeStorageAtomically(args.output, [&](cv::FileStorage& storage) {
    storage << "query" << args.query << "train" << args.train;
    storage << "masked" << static_cast<int>(masked);
    storage << "matches" << table;
    // What draw checks its images against (issue 45: swapped images were drawn, exit 0).
    storage << "query_digest" << descriptorDigest(a.descriptors) << "train_digest" << descriptorDigest(b.descriptors);
  });
  std::cout << args.query << " x " << args.train << ": " << matches.size() << (masked ? " masked" : "")
            << " matches" << inliers << " -> " << args.output << "\n";
}

}  // namespace

void addMatchCommand(CLI::App& app) {
  auto args = std::make_shared<MatchArgs>();
  CLI::App* cmd = app.add_subcommand(
      "match",
      "Match the descriptors of two extract outputs (brute force; masked Hamming distance when both have masks). "
      "Output: node 'matches', an N x 3 CV_64F matrix whose rows are (query row in A, train row in B, distance in "
      "bits), in query order; also 'query', 'train' (the input files), 'masked' (0/1) and 'query_digest', "
      "'train_digest' (digests of A's and B's descriptors, which draw --matches checks its images against).");
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
                  "Calibration of A (and of B without --camera-b) for --inliers; without it a homography is fitted "
                  "on the pixels")
      ->check(inputFileCheck());
  addCameraFileFlags(*cmd, args->camera, "--camera");
  cmd->add_option("--camera-b", args->cameraB.path,
                  "Calibration of B when another camera took it; --camera-b-id alone: another camera of --camera's "
                  "file (a rig)")
      ->check(inputFileCheck());
  addCameraFileFlags(*cmd, args->cameraB, "--camera-b");
  addModelFlag(*cmd, args->model);
  cmd->add_option("--inlier-threshold", args->thresholdPx, "--inliers: a match agrees within this many pixels of the fit")
      ->check(fieldRangeCheck(twoViewOptionFields(), "max_pixels"))
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output, "Output FileStorage file (.yml, .yml.gz, .json)")->required();
  cmd->callback([args] { runMatch(*args); });
}

}  // namespace mdbrief::cli
