// `mdbrief draw`: a PNG showing what the camera model does: the keypoints (colour = octave),
// with --other/--matches the matches between two images side by side (green: consistent with the
// ground truth or a robust fit, red: not; match_consistency.hpp), and with --keypoint the
// keypoint's test pairs as distorted on the image (the paper's test-set figure).
#include <iostream>
#include <memory>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/consistency_flags.hpp"
#include "cli/extraction_flags.hpp"
#include "cli/match_consistency.hpp"
#include "cli/storage_io.hpp"
#include "mdbrief/detect/image_pyramid.hpp"
#include "mdbrief/geometry/two_view.hpp"
#include "toolkit/option_flags.hpp"
#include "toolkit/homography_file.hpp"

namespace mdbrief::cli {
namespace {

struct DrawArgs {
  ExtractionFlags flags;
  std::string image;
  std::string keypoints;
  std::string other;
  std::string otherKeypoints;
  std::string matches;
  std::string homography;  // ground truth for --matches; empty: a robust fit
  CameraFileFlags otherCamera;  // --other's calibration when another camera took it
  std::string model = toString(ConsistencyModel::Auto);
  double thresholdPx = MatchConsistencyOptions{}.thresholdPx;
  bool hideKeypoints = false;
  std::optional<int> keypoint;
  std::string output;
};

cv::Scalar octaveColour(int octave) {
  static const cv::Scalar kColours[] = {{0, 255, 255}, {0, 200, 0},   {255, 160, 0},  {255, 0, 255},
                                        {0, 128, 255}, {255, 255, 0}, {128, 128, 255}, {0, 0, 255}};
  return kColours[std::max(0, octave) % 8];
}

void drawKeypoints(cv::Mat& canvas, const std::vector<cv::KeyPoint>& keypoints, cv::Point2f offset) {
  for (const auto& kp : keypoints)
    cv::circle(canvas, kp.pt + offset, std::max(2, cvRound(kp.size / 8)), octaveColour(kp.octave), 1, cv::LINE_AA);
}

// One keypoint's test pairs, p1 -> p2 lines (p1 ends red, p2 ends blue), at `zoom` about
// `origin` (so they can be drawn on a magnified crop).
void drawComparisonLines(cv::Mat& canvas, const std::vector<std::pair<cv::Point2f, cv::Point2f>>& tests,
                         cv::Point2f origin, float zoom) {
  const auto at = [&](cv::Point2f p) { return (p - origin) * zoom; };
  for (const auto& [p1, p2] : tests) cv::line(canvas, at(p1), at(p2), {0, 220, 0}, 1, cv::LINE_AA);
  const int r = zoom > 2 ? 2 : 1;
  for (const auto& [p1, p2] : tests) {
    cv::circle(canvas, at(p1), r, {0, 0, 255}, cv::FILLED, cv::LINE_AA);
    cv::circle(canvas, at(p2), r, {255, 0, 0}, cv::FILLED, cv::LINE_AA);
  }
}

// The tests on the image, and a magnified copy of their neighbourhood in the top-left corner:
// at full size a test footprint is a few dozen pixels, too small to see the distortion.
void drawComparisons(cv::Mat& canvas, const cv::Mat& grey,
                     const std::vector<std::pair<cv::Point2f, cv::Point2f>>& tests, const cv::KeyPoint& keypoint) {
  drawComparisonLines(canvas, tests, {0, 0}, 1.f);
  std::vector<cv::Point2f> points;
  for (const auto& [p1, p2] : tests) points.insert(points.end(), {p1, p2});
  const cv::Rect box = (cv::boundingRect(points) + cv::Size(8, 8) - cv::Point(4, 4)) & cv::Rect({0, 0}, grey.size());
  if (box.empty()) return;
  const float zoom = std::max(1.f, 0.45f * std::min(canvas.rows, canvas.cols) / std::max(box.width, box.height));
  cv::Mat inset;
  cv::resize(grey(box), inset, cv::Size(), zoom, zoom, cv::INTER_NEAREST);
  cv::cvtColor(inset, inset, cv::COLOR_GRAY2BGR);
  drawComparisonLines(inset, tests, cv::Point2f(box.tl()), zoom);
  cv::circle(inset, (keypoint.pt - cv::Point2f(box.tl())) * zoom, 4, {255, 255, 255}, cv::FILLED, cv::LINE_AA);
  cv::rectangle(canvas, box, {255, 255, 255}, 1);
  const cv::Rect place = cv::Rect({0, 0}, inset.size()) & cv::Rect({0, 0}, canvas.size());
  inset(cv::Rect({0, 0}, place.size())).copyTo(canvas(place));
  cv::rectangle(canvas, place, {255, 255, 255}, 2);
}

// Refuses a match file whose recorded descriptor digests are not those of the two images as
// described here: its rows would index other keypoints (issue 45: swapped images were drawn
// with exit 0). A file without the digests (written before match recorded them, or by hand) is
// read unchecked.
void checkMatchedFeatures(const StorageReader& storage, const std::string& path, const Features& query,
                          const Features& train, const std::string& queryImage, const std::string& trainImage) {
  const std::string queryDigest = storage.text("query_digest"), trainDigest = storage.text("train_digest");
  if (queryDigest.empty() && trainDigest.empty()) return;
  const std::string a = descriptorDigest(query.descriptors), b = descriptorDigest(train.descriptors);
  if (queryDigest == a && trainDigest == b) return;
  const std::string from = path + " (matches of " + storage.text("query") + " with " + storage.text("train") + ")";
  if (queryDigest == b && trainDigest == a)
    throw InputError(from + ": the images are swapped: " + trainImage + " was matched as A and " + queryImage +
                     " as B; draw " + trainImage + " --other " + queryImage);
  throw InputError(from + ": not the features of " + queryImage + " and " + trainImage +
                   " as these flags describe them (descriptor digests " + a + " and " + b + ", the file records " +
                   queryDigest + " and " + trainDigest + "); give the images in match's order and the flags used "
                   "for extract");
}

// Rows of node `matches` (query, train, distance), checked against the features drawn.
std::vector<std::pair<int, int>> loadMatches(const std::string& path, const Features& query, const Features& train,
                                             const std::string& queryImage, const std::string& trainImage) {
  const StorageReader storage(path);
  if (!storage.has("matches")) throw InputError(path + ": no node 'matches'");
  checkMatchedFeatures(storage, path, query, train, queryImage, trainImage);
  const size_t queryCount = query.keypoints.size(), trainCount = train.keypoints.size();
  cv::Mat table = storage.matrix("matches");
  if (table.empty()) return {};
  if (table.cols != 3 || table.channels() != 1) throw InputError(path + ": 'matches' must be an N x 3 matrix");
  table.convertTo(table, CV_64F);
  std::vector<std::pair<int, int>> out;
  for (int i = 0; i < table.rows; ++i) {
    const double q = table.at<double>(i, 0), t = table.at<double>(i, 1);
    if (!(q >= 0 && q < double(queryCount)) || !(t >= 0 && t < double(trainCount)))
      throw InputError(path + ": match " + std::to_string(i) + " refers to keypoints outside " + queryImage + " (" +
                       std::to_string(queryCount) + ") or " + trainImage + " (" + std::to_string(trainCount) +
                       "); draw with the flags used for extract");
    out.emplace_back(static_cast<int>(q), static_cast<int>(t));
  }
  return out;
}

void runDraw(const DrawArgs& args) {
  if (args.other.empty() != args.matches.empty()) throw InputError("--other and --matches go together");
  if (!args.homography.empty() && args.matches.empty()) throw InputError("--homography needs --matches");
  const CameraFileFlags otherCamera = secondCameraFlags(args.flags.camera, args.otherCamera);
  if (args.other.empty() && !otherCamera.path.empty()) throw InputError("--other-camera needs --other");
  checkConsistencyModel(args.model, args.flags.camera, otherCamera);
  checkImageOutput(args.output);
  checkOutputsApart({args.flags.camera.path, otherCamera.path, args.image, args.keypoints, args.other,
                     args.otherKeypoints, args.matches, args.homography},
                    {args.output});
  const CameraPtr calibration = loadCalibration(args.flags);
  const cv::Mat image = loadImage(args.image, args.flags.strict);
  std::optional<std::vector<cv::KeyPoint>> given;
  if (!args.keypoints.empty()) given = loadKeypoints(args.keypoints);
  const Features f = extractFeatures(args.flags, calibration, args.image, image, given);

  cv::Mat canvas;
  cv::cvtColor(image, canvas, cv::COLOR_GRAY2BGR);
  if (!args.hideKeypoints) drawKeypoints(canvas, f.keypoints, {0, 0});
  if (args.keypoint) {
    const int k = *args.keypoint;
    if (k < 0 || k >= static_cast<int>(f.keypoints.size()))
      throw InputError("--keypoint " + std::to_string(k) + ": " + args.image + " has " +
                       std::to_string(f.keypoints.size()) + " described keypoints");
    const auto feature = makeFeature(args.flags, calibration, args.image, image.size());
    const ImagePyramid pyramid(image, feature->options().detector.pyramid);
    const auto tests = feature->extractor().comparisonPositions(pyramid, f.keypoints[k]);
    if (tests.empty()) throw InputError("--keypoint " + std::to_string(k) + ": its tests cannot be placed");
    drawComparisons(canvas, image, tests, f.keypoints[k]);
  }

  std::string summary = std::to_string(f.keypoints.size()) + " keypoints drawn";
  if (!args.other.empty()) {
    MatchConsistencyOptions consistency;
    consistency.thresholdPx = args.thresholdPx;
    consistency.model = parseName(args.model, kConsistencyModelNames, "--model");
    consistency.calibrated = calibration != nullptr;
    if (consistency.model == ConsistencyModel::KnownPose) setRigPose(args.flags.camera, otherCamera, consistency);
    if (!args.homography.empty()) {
      try {
        consistency.groundTruth = readHomography(args.homography);
      } catch (const std::runtime_error& e) {
        throw InputError(std::string("--homography: ") + e.what());
      }
    }
    const cv::Mat otherImage = loadImage(args.other, args.flags.strict);
    std::optional<std::vector<cv::KeyPoint>> otherGiven;
    if (!args.otherKeypoints.empty()) otherGiven = loadKeypoints(args.otherKeypoints);
    // The other image described with its own camera when it has one.
    ExtractionFlags otherFlags = args.flags;
    if (!otherCamera.path.empty()) otherFlags.camera = otherCamera;
    const CameraPtr otherCalibration = otherCamera.path.empty() ? calibration : loadCalibration(otherFlags);
    const Features g = extractFeatures(otherFlags, otherCalibration, args.other, otherImage, otherGiven);
    const auto pairs = loadMatches(args.matches, f, g, args.image, args.other);
    // The calibration as each image was described (rescaled with --allow-size-mismatch).
    const auto cameraFor = [](const CameraPtr& camera, cv::Size size) -> CameraPtr {
      if (!camera) return pixelPlaneCamera(size);
      return camera->imageSize() == size ? camera : camera->resized(size);
    };
    std::vector<cv::Point2f> pointsA, pointsB;
    for (const auto& kp : f.keypoints) pointsA.push_back(kp.pt);
    for (const auto& kp : g.keypoints) pointsB.push_back(kp.pt);
    const MatchConsistency verdict = classifyMatches(*cameraFor(calibration, image.size()),
                                                     *cameraFor(otherCalibration, otherImage.size()), pointsA, pointsB,
                                                     pairs, consistency);
    cv::Mat right;
    cv::cvtColor(otherImage, right, cv::COLOR_GRAY2BGR);
    const cv::Point2f offset(static_cast<float>(canvas.cols), 0.f);
    cv::Mat both(std::max(canvas.rows, right.rows), canvas.cols + right.cols, CV_8UC3, cv::Scalar::all(0));
    canvas.copyTo(both(cv::Rect(0, 0, canvas.cols, canvas.rows)));
    right.copyTo(both(cv::Rect(canvas.cols, 0, right.cols, right.rows)));
    if (!args.hideKeypoints) drawKeypoints(both, g.keypoints, offset);
    // Wrong matches first, so the correct ones stay visible where lines cross.
    for (const bool correct : {false, true})
      for (size_t k = 0; k < pairs.size(); ++k)
        if (static_cast<bool>(verdict.correct[k]) == correct)
          cv::line(both, f.keypoints[pairs[k].first].pt, g.keypoints[pairs[k].second].pt + offset,
                   correct ? cv::Scalar(0, 255, 0) : cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
    canvas = both;
    const int total = static_cast<int>(pairs.size());
    summary = std::to_string(total) + " matches: " + std::to_string(verdict.correctCount) + " correct, " +
              std::to_string(total - verdict.correctCount) + " wrong (" + verdict.method + ")";
  }
  writeImageAtomically(args.output, canvas);
  std::cout << args.image << ": " << summary << " -> " << args.output << "\n";
}

}  // namespace

void addDrawCommand(CLI::App& app) {
  auto args = std::make_shared<DrawArgs>();
  CLI::App* cmd = app.add_subcommand(
      "draw",
      "Draw keypoints (colour = octave), matches between two images (green: correct, red: wrong, by --homography "
      "or else by --model fitted on the matches' bearings: the essential matrix with a calibration), and one "
      "keypoint's test pairs as the camera "
      "model distorts them (green lines, red = first point, blue = second). Keypoints are re-extracted with the "
      "extraction flags: give the flags used for extract so match indices agree.");
  addExtractionFlags(*cmd, args->flags);
  cmd->add_option("image", args->image, "Image to draw on")
      ->check(inputFileCheck())->required();
  cmd->add_option("--keypoints", args->keypoints, "Describe these keypoints (node 'keypoints') instead of detecting")
      ->check(inputFileCheck());
  cmd->add_option("--other", args->other, "Second image, drawn to the right, for --matches")
      ->check(inputFileCheck());
  cmd->add_option("--other-keypoints", args->otherKeypoints, "Keypoints of the second image (as --keypoints)")
      ->check(inputFileCheck());
  cmd->add_option("--matches", args->matches, "Output of match (IMAGE's features as A, --other's as B)")
      ->check(inputFileCheck());
  cmd->add_option("--homography", args->homography,
                  "Ground truth for --matches: a file of the pixel homography from IMAGE to --other (nine numbers, row by row)")
      ->check(inputFileCheck());
  cmd->add_option("--other-camera", args->otherCamera.path,
                  "Calibration of --other when another camera took it; --other-camera-id alone: another camera of "
                  "--camera's file (a rig)")
      ->check(inputFileCheck());
  addCameraFileFlags(*cmd, args->otherCamera, "--other-camera");
  addModelFlag(*cmd, args->model);
  cmd->add_option("--inlier-threshold", args->thresholdPx, "A match is correct within this many pixels of the model")
      ->check(fieldRangeCheck(twoViewOptionFields(), "max_pixels"))
      ->capture_default_str();
  cmd->add_flag("--no-keypoints", args->hideKeypoints, "Do not draw the keypoint circles");
  cmd->add_option("--keypoint", args->keypoint, "Draw the test pairs of this keypoint (row of the extract output)");
  cmd->add_option("-o,--output", args->output, "Output image (.png)")->required();
  cmd->callback([args] { runDraw(*args); });
}

}  // namespace mdbrief::cli
