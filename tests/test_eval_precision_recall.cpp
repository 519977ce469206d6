// The precision-recall protocol of eval/ (precision_recall.hpp, eval_datasets.hpp) on
// constructed inputs whose curves are known by hand.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "eval/eval_cli.hpp"
#include "eval/eval_datasets.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/detect/detector.hpp"
#include "scenes/plane_renderer.hpp"
#include "eval/pipeline_experiment.hpp"
#include "eval/plane_geometry.hpp"
#include "eval/pr_experiment.hpp"
#include "eval/precision_recall.hpp"
#include "test_data.hpp"

namespace mdbrief::eval {
namespace {

// n keypoints on a grid, 32-byte descriptors with distinct random bits.
Features gridFeatures(int n, cv::RNG& rng) {
  Features f;
  f.bits = 256;
  f.descriptors = cv::Mat(n, 32, CV_8U);
  rng.fill(f.descriptors, cv::RNG::UNIFORM, 0, 256);
  for (int i = 0; i < n; ++i) f.keypoints.emplace_back(cv::Point2f(20.f * (i % 10), 20.f * (i / 10)), 31.f);
  return f;
}

const GroundTruthMap kIdentity = [](const cv::Point2d& p) -> std::optional<cv::Point2d> { return p; };

TEST(EvalPrecisionRecall, IdenticalImagesGiveAPerfectCurve) {
  cv::RNG rng(7);
  const Features a = gridFeatures(50, rng);
  const PairMatches m = matchPair(a, a, kIdentity);
  EXPECT_EQ(m.groundTruth, 50);
  ASSERT_EQ(m.correct.size(), 50u);
  for (char c : m.correct) EXPECT_TRUE(c);
  const PrSummary s = summarize(meanCurve({m}));
  EXPECT_NEAR(s.auc, 1.0, 1e-9);
  EXPECT_NEAR(s.recallAt01, 1.0, 1e-9);
}

TEST(EvalPrecisionRecall, ShuffledDescriptorsAreAllWrong) {
  cv::RNG rng(8);
  const Features a = gridFeatures(40, rng);
  Features b = a;
  // Rotate the rows: every keypoint of b carries another keypoint's descriptor.
  cv::Mat rotated;
  cv::vconcat(a.descriptors.rowRange(1, 40), a.descriptors.rowRange(0, 1), rotated);
  b.descriptors = rotated;
  const PairMatches m = matchPair(a, b, kIdentity);
  EXPECT_EQ(m.groundTruth, 40);
  int correct = 0;
  for (char c : m.correct) correct += c;
  EXPECT_EQ(correct, 0);
  const PrSummary s = summarize(meanCurve({m}));
  EXPECT_NEAR(s.auc, 0.0, 1e-9);
  EXPECT_EQ(s.recallAt02, 0.0);
}

TEST(EvalPrecisionRecall, KeypointsWithoutCounterpartAreNotGroundTruth) {
  cv::RNG rng(9);
  const Features a = gridFeatures(30, rng);
  // Shift by 10 px: no keypoint of b lies within 3 px of a mapped keypoint.
  const GroundTruthMap shift = [](const cv::Point2d& p) -> std::optional<cv::Point2d> { return p + cv::Point2d(10, 0); };
  EXPECT_EQ(matchPair(a, a, shift).groundTruth, 0);
  const GroundTruthMap none = [](const cv::Point2d&) -> std::optional<cv::Point2d> { return std::nullopt; };
  EXPECT_EQ(matchPair(a, a, none).groundTruth, 0);
}

// Repeatability counts only keypoints that land inside the second image and its valid area,
// and a repeat needs a keypoint of the second image within the radius.
TEST(EvalPipelines, RepeatabilityCountsVisibleKeypointsWithANeighbourInRadius) {
  const auto shift = [](const cv::Point2d& p) -> std::optional<cv::Point2d> { return p + cv::Point2d(10, 0); };
  const std::vector<cv::KeyPoint> a{{{20, 20}, 31}, {{50, 50}, 31}, {{95, 50}, 31}, {{30, 80}, 31}};
  // (30, 20): exact; (60, 50): 2.5 px off; (105, 50): outside the 100 px wide image; (40, 80):
  // masked out.
  const std::vector<cv::KeyPoint> b{{{30, 20}, 31}, {{62.5f, 50}, 31}, {{40, 80}, 31}};
  cv::Mat mask(100, 100, CV_8U, cv::Scalar(255));
  mask.rowRange(70, 100).setTo(0);
  auto [repeated, candidates] = mdbrief::eval::repeatedKeypoints(a, b, shift, {100, 100}, mask, 3.0);
  EXPECT_EQ(candidates, 2);
  EXPECT_EQ(repeated, 2);
  std::tie(repeated, candidates) = mdbrief::eval::repeatedKeypoints(a, b, shift, {100, 100}, mask, 2.0);
  EXPECT_EQ(candidates, 2);
  EXPECT_EQ(repeated, 1);
  std::tie(repeated, candidates) = mdbrief::eval::repeatedKeypoints(a, b, shift, {100, 100}, cv::Mat(), 3.0);
  EXPECT_EQ(candidates, 3);
  EXPECT_EQ(repeated, 3);
}

TEST(EvalPrecisionRecall, RecallAtInterpolatesTheCrossingSegment) {
  PrCurve c;
  c.threshold = {0, 1, 2};
  c.oneMinusPrecision = {0.0, 0.2, 0.4};
  c.recall = {0.2, 0.6, 0.8};
  EXPECT_NEAR(recallAt(c, 0.1), 0.4, 1e-12);
  EXPECT_NEAR(recallAt(c, 0.2), 0.6, 1e-12);
  // Area: trapezoids up to 0.4 (0.08 + 0.14) plus the final recall continued to 1 (0.48).
  EXPECT_NEAR(summarize(c).auc, 0.08 + 0.14 + 0.48, 1e-12);
}

TEST(EvalPrecisionRecall, HomographyFileErrorsNameTheFile) {
  const auto path = std::filesystem::temp_directory_path() / ("mdbrief_test_h_" + std::to_string(::getpid()));
  {
    std::ofstream out(path);
    out << "1 0 0\n0 1 0\n0 0\n";
  }
  try {
    readHomography(path.string());
    ADD_FAILURE() << "a file with eight numbers was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  // Issue 45: a tenth number and an all-zero matrix were accepted.
  for (const auto& [content, why] : std::vector<std::pair<std::string, std::string>>{
           {"1 0 0\n0 1 0\n0 0 1\n7\n", "found more: '7'"},
           {"0 0 0\n0 0 0\n0 0 0\n", "singular"},
           {"1 2 3\n2 4 6\n0 0 1\n", "singular"}}) {
    std::ofstream(path) << content;
    try {
      readHomography(path.string());
      ADD_FAILURE() << "accepted: " << content;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ": "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
  // Valid files read as before, whatever the spacing and the scale.
  std::ofstream(path) << "  2e-3 0 0 0 2e-3 0\n0 0 2e-3\n\n";
  EXPECT_EQ(readHomography(path.string()), cv::Matx33d(2e-3, 0, 0, 0, 2e-3, 0, 0, 0, 2e-3));
  std::filesystem::remove(path);
  EXPECT_THROW(readHomography(path.string()), std::runtime_error);
}

// User data: two fisheye views from the same centre, rotated by 20 degrees; the bearing
// homography of a pure rotation is the relative rotation. Every keypoint mapped through it must
// land on the same plane point, so the same corners are re-detected within 3 px and identical
// patches (up to resampling) give a high recall.
TEST(EvalPrecisionRecall, UserSequenceMapsThroughBearingHomographies) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc || !std::filesystem::exists(*doc / "graf1.png")) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const std::string camPath = (testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string();
  const CameraPtr cam = loadCamera(camPath);
  const PlaneScene scene{cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE), 0.004};
  CameraPose a, b;
  b.rotation = cameraRotation(20.0, 0.0, 0.0);
  const auto dir = std::filesystem::temp_directory_path() / ("mdbrief_test_user_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string ia = (dir / "a.png").string(), ib = (dir / "b.png").string(), h = (dir / "H").string();
  cv::imwrite(ia, renderPlane(*cam, a, scene));
  cv::imwrite(ib, renderPlane(*cam, b, scene));
  {
    std::ofstream out(h);
    const cv::Matx33d r = b.rotation * a.rotation.t();  // bearing_b = R_b R_a^T bearing_a
    for (int i = 0; i < 9; ++i) out << r.val[i] << (i % 3 == 2 ? "\n" : " ");
  }
  const EvalSequence seq = loadUserSequence("user", {ia, ib}, camPath, {h});
  ASSERT_EQ(seq.pairs.size(), 1u);
  // The map agrees with the plane geometry.
  const cv::Point2d px(400, 250);
  const auto mapped = seq.pairs[0].map(px);
  const auto plane = pixelToPlane(*cam, a, px);
  ASSERT_TRUE(mapped && plane);
  cv::Point2d expected;
  ASSERT_TRUE(projectPlanePoint(*cam, b, *plane, expected));
  EXPECT_LT(cv::norm(*mapped - expected), 0.05);

  DetectorOptions dopt;
  dopt.nfeatures = 300;
  const Detector det(cam, dopt);
  const MethodSpec brief = briefFamilyMethod("BRIEF", DescriptorKind::Brief, 256, true);
  const Features fa = describe(brief, seq.images[0], cam, det.detect(seq.images[0]));
  const Features fb = describe(brief, seq.images[1], cam, det.detect(seq.images[1]));
  const PairMatches m = matchPair(fa, fb, seq.pairs[0].map);
  EXPECT_GT(m.groundTruth, 100);
  EXPECT_GT(summarize(meanCurve({m})).recallAt02, 0.5);
  std::filesystem::remove_all(dir);
  EXPECT_THROW(loadUserSequence("user", {ia}, camPath, {}), std::runtime_error);
}

// Exported user data (general poses: translation, yaw, pitch, roll) read back through the
// user-data path gives the same ground truth as the rendered sequence's exact plane geometry,
// whatever the sign the homography file carries.
TEST(EvalPrecisionRecall, ExportedUserSequenceReproducesThePlaneGroundTruth) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc || !std::filesystem::exists(*doc / "graf1.png")) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const CameraPtr cam = loadCamera((testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
  const cv::Mat texture = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  const testing::TempDir dir("user_export");
  const UserSequenceFiles files = exportUserSequence(dir.path.string(), texture, cam, 4);
  ASSERT_EQ(files.images.size(), 4u);
  ASSERT_EQ(files.homographies.size(), 3u);
  const EvalSequence user = loadUserSequence("user", files.images, files.camera, files.homographies);
  const EvalSequence rendered = renderedFisheyeSequence("rendered", texture, cam, 4);
  ASSERT_EQ(user.pairs.size(), rendered.pairs.size());
  for (size_t k = 0; k < user.images.size(); ++k)
    EXPECT_EQ(cv::norm(user.images[k], rendered.images[k], cv::NORM_INF), 0.0) << "image " << k;

  // The same homography negated (equally valid up to scale) maps the same way.
  const std::string negated = (dir.path / "H1to4_negated").string();
  {
    const cv::Matx33d h = readHomography(files.homographies[2]);
    std::ofstream out(negated);
    out.precision(17);
    for (int i = 0; i < 9; ++i) out << -h.val[i] << " ";
  }
  const EvalSequence flipped = loadUserSequence(
      "flipped", files.images, files.camera, {files.homographies[0], files.homographies[1], negated});

  for (size_t p = 0; p < user.pairs.size(); ++p) {
    int compared = 0;
    double worst = 0.0;
    for (int y = 10; y < 480; y += 20)
      for (int x = 10; x < 754; x += 20) {
        const auto exact = rendered.pairs[p].map({double(x), double(y)});
        if (!exact) continue;  // off the texture or leaving the lens
        const auto viaFile = user.pairs[p].map({double(x), double(y)});
        ASSERT_TRUE(viaFile) << "pair " << p << " at " << x << "," << y;
        worst = std::max(worst, cv::norm(*viaFile - *exact));
        ++compared;
        if (p == 2) {
          const auto viaNegated = flipped.pairs[p].map({double(x), double(y)});
          ASSERT_TRUE(viaNegated);
          EXPECT_LT(cv::norm(*viaNegated - *viaFile), 1e-9);
        }
      }
    EXPECT_GT(compared, 100) << "pair " << p;
    EXPECT_LT(worst, 1e-3) << "pair " << p;  // text round trip of the homography, 17 digits
  }

  const std::string singular = (dir.path / "H_singular").string();
  std::ofstream(singular) << "1 0 0  0 1 0  0 0 0\n";
  EXPECT_THROW(loadUserSequence("bad", {files.images[0], files.images[1]}, files.camera, {singular}),
               std::runtime_error);
}

// A real photo seen by the turned lens: the written rotations are the ground truth, and a bright
// spot lands where they map it.
TEST(EvalPrecisionRecall, RotatedViewsOfAPhotoMapByTheirRotations) {
  const CameraPtr cam = loadCamera((testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string());
  const cv::Size size = cam->imageSize();
  cv::Mat photo(size, CV_8UC1, cv::Scalar(40));
  const cv::Point2d spot(400, 250);
  cv::circle(photo, cv::Point(400, 250), 3, cv::Scalar(255), cv::FILLED);
  const testing::TempDir dir("rotated");
  const UserSequenceFiles files = exportRotatedViews(dir.path.string(), photo, cam, 3);
  ASSERT_EQ(files.images.size(), 3u);
  ASSERT_EQ(files.homographies.size(), 2u);
  const EvalSequence seq = loadUserSequence("rotated", files.images, files.camera, files.homographies);
  for (size_t p = 0; p < seq.pairs.size(); ++p) {
    const auto mapped = seq.pairs[p].map(spot);
    ASSERT_TRUE(mapped) << "pair " << p;
    const cv::Moments m = cv::moments(seq.images[seq.pairs[p].second] > 128, true);
    ASSERT_GT(m.m00, 0.0);
    EXPECT_LT(cv::norm(cv::Point2d(m.m10 / m.m00, m.m01 / m.m00) - *mapped), 1.0) << "pair " << p;
    EXPECT_GT(cv::norm(*mapped - spot), 20.0) << "the lens turned";
  }
  EXPECT_THROW(exportRotatedViews(dir.path.string(), cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), cam, 3),
               std::runtime_error);
}

TEST(KeypointSources, OneSpellingPerDetectorAndTheChoicesListed) {
  EXPECT_EQ(parseKeypointSource(toString(DetectorMethod::Hessian)), KeypointSource::Hessian);
  EXPECT_EQ(parseKeypointSource(train::detectorName(train::DetectorKind::Akaze)), KeypointSource::Akaze);
  try {
    parseKeypointSource("harris");
    ADD_FAILURE() << "an unknown keypoint source was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "keypoint source 'harris' is not one of: modorb, hessian, orb, akaze, brisk, sift");
  }
}

}  // namespace
}  // namespace mdbrief::eval

namespace mdbrief::eval {
namespace {

namespace fs = std::filesystem;

struct EvalRun {
  int code;
  std::string err;
};

EvalRun runEval(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = runEvalCli(args, out, err);
  return {code, err.str()};
}

// Issue 29: `eval --oxford-dir /mistyped --no-fisheye` replaced eval_summary.csv with a header
// and exited 0. An evaluation of nothing keeps the previous results and exits 2.
TEST(EvalCli, AnEvaluationOfNothingKeepsThePreviousResults) {
  testing::TempDir dir("eval_nothing");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  const std::string old = "group,sequence,method\nperspective,graf,old\n";
  for (const char* name : {"eval_summary.csv", "pipelines_summary.csv"}) std::ofstream(out / name) << old;
  const std::string missing = (dir.path / "mistyped").string();
  for (const char* command : {"eval", "pipelines"}) {
    const EvalRun r = runEval({command, "--oxford-dir", missing, "--no-fisheye", "--out", out.string()});
    EXPECT_EQ(r.code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("no sequence to evaluate"), std::string::npos) << r.err;
  }
  EXPECT_EQ(testing::readFile(out / "eval_summary.csv"), old);
  EXPECT_EQ(testing::readFile(out / "pipelines_summary.csv"), old);
}

// Issue 45: two sim cameras of one name overwrote each other's files (exit 0), a name with a
// path or a comma failed after the whole run or broke sim_info.csv, and two --fisheye-camera
// files of one stem shared rows of eval_summary.csv. Each is refused before any work.
TEST(EvalCli, NamesThatWouldClashOrEscapeAreRefusedBeforeTheWork) {
  testing::TempDir dir("eval_names");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  fs::create_directories(dir.path / "a");
  fs::create_directories(dir.path / "b");
  const std::string camera = (testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string();
  for (const char* folder : {"a", "b"}) fs::copy_file(camera, dir.path / folder / "cam.yaml");
  const std::string photo = (dir.path / "photo.png").string();
  cv::Mat pixels(48, 64, CV_8UC1);
  cv::randu(pixels, 0, 256);
  ASSERT_TRUE(cv::imwrite(photo, pixels));
  const auto sim = [&](std::vector<std::string> cameras) {
    std::vector<std::string> args{"sim", "--texture", photo, "--out", out.string()};
    for (const auto& c : cameras) args.insert(args.end(), {"--camera", c});
    return args;
  };
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {sim({"fe=" + camera, "fe=" + camera}), "the name 'fe' is given twice"},
      {sim({"../../escape=" + camera}), "the name '../../escape' names output files"},
      {sim({"a,b=" + camera}), "the name 'a,b' names output files"},
      {{"eval", "--no-perspective", "--fisheye-camera", (dir.path / "a/cam.yaml").string(), "--fisheye-camera",
        (dir.path / "b/cam.yaml").string(), "--texture", photo, "--out", out.string()},
       "both are named 'cam'"},
  };
  for (const auto& [args, expected] : cases) {
    const EvalRun r = runEval(args);
    EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << args[0] << ": " << r.err;
  }
  EXPECT_TRUE(fs::is_empty(out));
}

// Issue 29: an output that names an input is refused before the work, the input unchanged.
TEST(EvalCli, AnOutputThatIsAnInputIsRefused) {
  testing::TempDir dir("eval_same");
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  const fs::path camera = out / "camera.yaml", photo = dir.path / "photo.png";
  fs::copy_file(testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml", camera);
  cv::Mat pixels(48, 64, CV_8UC1);
  cv::randu(pixels, 0, 256);
  ASSERT_TRUE(cv::imwrite(photo.string(), pixels));
  const std::string cameraBytes = testing::readFile(camera), photoBytes = testing::readFile(photo);
  const fs::path timingTexture = dir.path / "timing_table.csv";  // timing's own output given as its texture
  fs::copy_file(photo, timingTexture);
  const std::vector<std::vector<std::string>> cases = {
      {"export-user-sample", "--camera", camera.string(), "--texture", photo.string(), "--out", out.string()},
      {"export-rotated-views", "--camera", camera.string(), "--image", photo.string(), "--out", out.string()},
      {"held-out-images", "--only", photo.string(), "--out", photo.string()},
      {"timing", "--camera", camera.string(), "--texture", timingTexture.string(), "--out", dir.path.string()},
      // A former output of sim as its texture.
      {"sim", "--texture", (out / "sim_pinhole_views.png").string(), "--out", out.string()},
  };
  fs::copy_file(photo, out / "sim_pinhole_views.png");
  for (const auto& args : cases) {
    const EvalRun r = runEval(args);
    EXPECT_EQ(r.code, 2) << args[0] << ": " << r.err;
    EXPECT_NE(r.err.find("the output is the same file as the input"), std::string::npos) << args[0] << ": " << r.err;
  }
  EXPECT_EQ(testing::readFile(camera), cameraBytes);
  EXPECT_EQ(testing::readFile(photo), photoBytes);
  EXPECT_EQ(testing::readFile(dir.path / "timing_table.csv"), photoBytes);
  EXPECT_EQ(testing::readFile(out / "sim_pinhole_views.png"), photoBytes);
  EXPECT_FALSE(fs::exists(out / "img1.png"));
}

// A rig file's cameras are chosen by --camera-id in the evaluation too: the photo of cam1 is
// turned with cam1's lens (its camera.yaml is cam1's), and a rig without a choice is refused
// naming the ids. Flags that take several calibrations take file#id.
TEST(EvalCli, CameraIdChoosesTheCameraOfARigFile) {
  testing::TempDir dir("eval_rig");
  const fs::path rig = dir.path / "camchain.yaml", photo = dir.path / "photo.png", out = dir.path / "out";
  std::ofstream(rig) << "cam0:\n  camera_model: pinhole\n  distortion_model: equidistant\n"
                        "  distortion_coeffs: [-0.0125, 0.0578, -0.0850, 0.0436]\n"
                        "  intrinsics: [461.6, 460.3, 366.3, 249.1]\n  resolution: [752, 480]\n"
                        "cam1:\n  camera_model: pinhole\n  distortion_model: equidistant\n"
                        "  distortion_coeffs: [-0.0125, 0.0578, -0.0850, 0.0436]\n"
                        "  intrinsics: [455.0, 455.0, 370.0, 240.0]\n  resolution: [752, 480]\n";
  cv::Mat pixels(480, 752, CV_8UC1);
  cv::randu(pixels, 0, 256);
  ASSERT_TRUE(cv::imwrite(photo.string(), pixels));
  const EvalRun refused = runEval({"export-rotated-views", "--camera", rig.string(), "--image", photo.string(),
                                   "--views", "2", "--out", out.string()});
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_NE(refused.err.find("cam1"), std::string::npos) << refused.err;
  const EvalRun chosen = runEval({"export-rotated-views", "--camera", rig.string(), "--camera-id", "cam1", "--image",
                                  photo.string(), "--views", "2", "--out", out.string()});
  ASSERT_EQ(chosen.code, 0) << chosen.err;
  CameraFileOptions cam1;
  cam1.cameraId = "cam1";
  EXPECT_EQ(cameraToYaml(*loadCamera((out / "camera.yaml").string())), cameraToYaml(*loadCamera(rig.string(), cam1)));

  // Flags that take several calibrations name a rig's camera as file#id, and say so when it is
  // missing; the rendered sequence is named after the camera.
  const fs::path texture = dir.path / "texture.png";
  cv::Mat smooth;
  cv::GaussianBlur(pixels, smooth, cv::Size(0, 0), 2.0);
  ASSERT_TRUE(cv::imwrite(texture.string(), smooth));
  const auto evalFisheye = [&](const std::string& camera) {
    return runEval({"eval", "--no-perspective", "--fisheye-camera", camera, "--texture", texture.string(), "--poses",
                    "2", "--quick", "--out", (dir.path / "eval").string()});
  };
  const EvalRun noId = evalFisheye(rig.string());
  EXPECT_EQ(noId.code, 2);
  EXPECT_NE(noId.err.find("choose one by its id as " + rig.string() + "#id"), std::string::npos) << noId.err;
  const EvalRun unknownId = evalFisheye(rig.string() + "#cam7");
  EXPECT_EQ(unknownId.code, 2);
  EXPECT_NE(unknownId.err.find("cam7"), std::string::npos) << unknownId.err;
  const EvalRun withId = evalFisheye(rig.string() + "#cam1");
  ASSERT_EQ(withId.code, 0) << withId.err;
  EXPECT_NE(testing::readFile(dir.path / "eval" / "eval_summary.csv").find("fisheye,camchain-cam1:"), std::string::npos);
  // sim's name=path pairs take the same form (no experiment run: the cameras load first).
  const auto sim = [&](const std::string& camera) {
    return runEval({"sim", "--camera", "fish=" + camera, "--texture", texture.string(), "--no-projected",
                    "--no-detected", "--out", (dir.path / "sim").string()});
  };
  const EvalRun simUnknownId = sim(rig.string() + "#cam7");
  EXPECT_EQ(simUnknownId.code, 2);
  EXPECT_NE(simUnknownId.err.find("cam7"), std::string::npos) << simUnknownId.err;
  EXPECT_EQ(sim(rig.string() + "#cam1").code, 0);
}

}  // namespace
}  // namespace mdbrief::eval
