// The tracker benchmark of eval/: the matches a tracker keeps (tracker_metrics.hpp) and the
// poster-dev ground truth (poster_dev.hpp), on constructed inputs whose answers are known.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "eval/eval_commands.hpp"
#include "eval/poster_dev.hpp"
#include "eval/tracker_metrics.hpp"
#include "test_data.hpp"
#include "scenes/photo_camera.hpp"

namespace mdbrief::eval {
namespace {

TEST(TrackerMatches, MutualNearestNeighboursPassingTheRatio) {
  NeighbourTable t;
  t.best = {0, 1, 1, -1};
  t.bestDistance = {10, 10, 30, 0};
  t.secondDistance = {40, 12, 60, 0};
  t.bestQuery = {0, 2};  // train 1's nearest query is query 2
  // Query 0: mutual, 10 < r * 40 for r > 0.25. Query 1: not mutual. Query 2: mutual, 30 < r * 60
  // for r > 0.5. Query 3: no neighbour.
  using Pairs = std::vector<std::pair<int, int>>;
  EXPECT_EQ(mutualRatioMatches(t, 1.0), (Pairs{{0, 0}, {2, 1}}));
  EXPECT_EQ(mutualRatioMatches(t, 0.6), (Pairs{{0, 0}, {2, 1}}));
  EXPECT_EQ(mutualRatioMatches(t, 0.5), (Pairs{{0, 0}}));  // 30 < 30 fails: strict
  EXPECT_EQ(mutualRatioMatches(t, 0.2), Pairs{});
}

TEST(TrackerMatches, AveragePrecisionOfRankedNearestNeighbours) {
  PairMatches m;
  m.distance = {3, 1, 2, 4};
  m.correct = {1, 1, 0, 0};
  m.groundTruth = 3;
  // Ranked: d=1 correct (precision 1), d=2 wrong, d=3 correct (2/3), d=4 wrong; over 3 truths.
  EXPECT_NEAR(averagePrecision(m), (1.0 + 2.0 / 3.0) / 3.0, 1e-12);
  m.groundTruth = 0;
  EXPECT_EQ(averagePrecision(m), 0.0);
}

TEST(TrackerMatches, IdenticalViewsKeepEveryMatchAndFitExactly) {
  const CameraPtr camera = photoCamera({640, 480});
  cv::RNG rng(11);
  Features f;
  f.bits = 256;
  f.descriptors = cv::Mat(80, 32, CV_8U);
  rng.fill(f.descriptors, cv::RNG::UNIFORM, 0, 256);
  for (int i = 0; i < 80; ++i) f.keypoints.emplace_back(cv::Point2f(40.f + 60.f * (i % 10), 40.f + 50.f * (i / 10)), 31.f);
  const GroundTruthMap identity = [](const cv::Point2d& p) -> std::optional<cv::Point2d> { return p; };
  const TrackerOptions options;
  const PairEvidence e = pairEvidence(f, f, *camera, identity, {}, {640, 480}, options);
  EXPECT_EQ(e.repeated, 80);
  EXPECT_EQ(e.nearest.groundTruth, 80);
  EXPECT_NEAR(e.averagePrecision, 1.0, 1e-12);
  EXPECT_NEAR(e.localScale, 1.0, 1e-9);
  const GroundTruthGrid grid = groundTruthGrid(*camera, identity, {640, 480}, {}, 16);
  EXPECT_EQ(grid.pixelA.size(), 40u * 30u);
  const TrackerResult r = trackerResult(f, e, 0.8, *camera, grid, true, options);
  EXPECT_EQ(r.matches, 80);
  EXPECT_EQ(r.correct, 80);
  EXPECT_EQ(r.homographyInliers, 80);
  EXPECT_LT(r.homographyErrorPx, 1e-6);
  // A pure rotation's epipolar geometry is undefined, but whatever essential matrix fits the
  // matches, the identical grid lies on it.
  EXPECT_TRUE(r.essentialChecked);
}

// A poster-dev folder with two frames of a 752x480 OCamCalib camera; both frames see the poster
// through the same G, so every valid pixel maps to itself.
struct FakePosterDev {
  testing::TempDir data{"poster_dev"};  // a shared data folder: fisheye/poster-dev inside
  struct {
    std::filesystem::path path;
  } dir;
  std::string json;
  FakePosterDev() {
    dir.path = data.path / "fisheye" / "poster-dev";
    std::filesystem::create_directories(dir.path);
    std::ofstream(dir.path / "calib_results.txt") << "3 -209.2 0 0.002\n3 1 2 3\n240 376\n1 0 0\n480 752\n";
    cv::Mat frame(480, 752, CV_8U);
    cv::randu(frame, 0, 255);
    cv::imwrite((dir.path / "a.png").string(), frame);
    cv::imwrite((dir.path / "b.png").string(), frame);
    cv::imwrite((dir.path / "mask.png").string(), cv::Mat(480, 752, CV_8U, cv::Scalar(255)));
    // Pattern pixel (x, y) -> ray (x - 800, y - 600, 1000): the poster 1 unit in front, centred.
    const std::string g = "[[1, 0, -800], [0, 1, -600], [0, 0, 1000]]";
    json = R"({"calibration": "calib_results.txt", "max_incidence_deg": 88,
               "printed_region_pattern_px": {"x0": 0, "x1": 1600, "y0": 0, "y1": 1200},
               "frames": [{"frame": 1, "image": "a.png", "mask": "mask.png", "G": )" + g + R"(},
                          {"frame": 2, "image": "b.png", "mask": "mask.png", "G": )" + g + "}]}";
    write(json);
  }
  void write(const std::string& text) const { std::ofstream(dir.path / "ground_truth.json") << text; }
  // The message loadPosterDev throws, or "" when it loads.
  std::string problem() const {
    try {
      loadPosterDev(dir.path.string());
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
};

TEST(PosterDev, LoadsFramesMasksAndAGroundTruthThatMapsThroughTheCamera) {
  FakePosterDev fake;
  const PosterDev poster = loadPosterDev(fake.dir.path.string());
  ASSERT_EQ(poster.frames.size(), 2u);
  EXPECT_EQ(poster.frames[1].id, 2);
  const auto p = poster.map(0, 1, {400.3, 250.7});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 400.3, 1e-6);
  EXPECT_NEAR(p->y, 250.7, 1e-6);
  EXPECT_FALSE(poster.map(0, 1, {-5, 250}));  // outside the image
  const EvalSequence seq = posterDevSequence(poster);
  EXPECT_EQ(seq.pairs.size(), 1u);
  EXPECT_TRUE(seq.baseline);
  ASSERT_EQ(seq.regions.size(), 2u);
  EXPECT_EQ(cv::countNonZero(seq.regions[0]), 752 * 480);
}

TEST(PosterDev, BadFilesAreNamedWithTheProblem) {
  FakePosterDev fake;
  const std::string json = (fake.dir.path / "ground_truth.json").string();
  fake.write("{ not json");
  EXPECT_EQ(fake.problem(), json + ": not a JSON object");
  fake.write(R"({"calibration": "calib_results.txt", "calibration": "other.txt"})");
  EXPECT_EQ(fake.problem(), json + ": key 'calibration' appears twice in one object");
  fake.write(R"({"calibration": "calib_results.txt"})");
  EXPECT_EQ(fake.problem(), json + ": missing \"printed_region_pattern_px\"");
  std::string text = fake.json;
  text.replace(text.find("[[1, 0, -800]"), 13, "[[1, 0]");
  fake.write(text);
  EXPECT_EQ(fake.problem(), json + ": frame 1: G is not 3x3");
  text = fake.json;
  text.replace(text.find("b.png"), 5, "c.png");
  fake.write(text);
  EXPECT_NE(fake.problem().find("c.png: no such file"), std::string::npos) << fake.problem();
  fake.write(fake.json);
  cv::imwrite((fake.dir.path / "mask.png").string(), cv::Mat(100, 100, CV_8U, cv::Scalar(255)));
  EXPECT_NE(fake.problem().find("mask.png: the mask is 100x100 but the calibration 752x480"), std::string::npos)
      << fake.problem();
  std::filesystem::remove(json);
  EXPECT_EQ(fake.problem(), json + ": no such file");
}

// `mdbrief-eval tracker ...` in-process: "" on success, else the message of the error that exits 2.
std::string runTrackerCommand(std::vector<std::string> args) {
  CLI::App app;
  addTrackerCommand(app);
  args.insert(args.begin(), {"mdbrief-eval", "tracker"});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  try {
    app.parse(static_cast<int>(argv.size()), argv.data());
  } catch (const std::invalid_argument& e) {
    return e.what();
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(TrackerCommand, ADamagedDataSetIsSkippedWithItsReasonOrRefusedWhenNamed) {
  FakePosterDev fake;
  testing::TempDir out("tracker_out"), noPhotos("tracker_no_photos");
  const std::vector<std::string> common{"--data", fake.data.path.string(), "--opencv-doc-dir", noPhotos.path.string(),
                                        "--only", "AKAZE", "--budget", "60", "--out", out.path.string()};
  const std::string json = (fake.dir.path / "ground_truth.json").string();
  // The intact data set runs; the missing ones are skipped with a reason.
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(runTrackerCommand(common), "");
  std::string err = ::testing::internal::GetCapturedStderr();
  ::testing::internal::GetCapturedStdout();
  EXPECT_NE(err.find("skipping oxford: "), std::string::npos) << err;
  const std::string summary = testing::readFile(out.path / "tracker_summary.csv");
  EXPECT_NE(summary.find("poster-dev,AKAZE,"), std::string::npos) << summary;
  // Damaged: asked for by name, an error naming the file; otherwise skipped with the same reason.
  fake.write("{ not json");
  auto named = common;
  named.insert(named.end(), {"--datasets", "poster-dev"});
  EXPECT_EQ(runTrackerCommand(named), "poster-dev: " + json + ": not a JSON object");
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(runTrackerCommand(common), "no data set could be read (see the messages above)");
  err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("skipping poster-dev: " + json + ": not a JSON object"), std::string::npos) << err;
}

// Issue 29: --library naming a FIFO blocked for ever; /dev/zero read without end.
TEST(TrackerCommand, ALibraryOptionsFileMustBeARegularFile) {
  testing::TempDir dir("tracker_library");
  const std::string fifo = (dir.path / "options.yml").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(runTrackerCommand({"--library", "mine=" + fifo, "--out", dir.path.string()}),
            "--library: " + fifo + ": is a FIFO, not a regular file");
  EXPECT_EQ(runTrackerCommand({"--library", "mine=/dev/zero", "--out", dir.path.string()}),
            "--library: /dev/zero: is a character device, not a regular file");
}

// Issue 45: OpenCV's parsers recursed once per level of an options file nested 100000 deep until
// the stack overflowed; such a file is refused before it is parsed, naming the line.
TEST(TrackerCommand, ALibraryOptionsFileNestedTooDeepIsRefusedUnparsed) {
  testing::TempDir dir("tracker_library_deep");
  const int levels = 100000;
  std::string xml = "<?xml version=\"1.0\"?>\n<opencv_storage>\n";
  for (int i = 0; i < levels; ++i) xml += "<a>";
  const std::string yaml = "%YAML:1.0\n---\na: " + std::string(levels, '[') + std::string(levels, ']') + "\n";
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"deep.xml", xml}, {"deep.yml", yaml}}) {
    const std::string file = (dir.path / name).string();
    std::ofstream(file) << text;
    EXPECT_EQ(runTrackerCommand({"--library", "mine=" + file, "--out", dir.path.string()}),
              file + ": library options file: nested deeper than 64 levels (line 3)");
  }
}

// Issue 29: an output that is one of the inputs is refused before the run, the input kept.
TEST(TrackerCommand, AnOutputThatIsAnInputIsRefused) {
  FakePosterDev fake;
  testing::TempDir out("tracker_same"), noPhotos("tracker_same_no_photos");
  const std::string summary = (out.path / "tracker_summary.csv").string();
  std::ofstream(summary) << "previous results\n";
  ::testing::internal::CaptureStderr();
  const std::string message =
      runTrackerCommand({"--data", fake.data.path.string(), "--opencv-doc-dir", noPhotos.path.string(), "--only",
                         "AKAZE", "--fisheye-camera", summary, "--out", out.path.string()});
  ::testing::internal::GetCapturedStderr();
  EXPECT_NE(message.find("the output is the same file as the input " + summary), std::string::npos) << message;
  EXPECT_EQ(testing::readFile(summary), "previous results\n");
}

TEST(PosterDev, TheSharedFramesGiveFortyFivePairs) {
  MDBRIEF_REQUIRE_SHARED_DATA(data);
  if (!std::filesystem::exists(data / "fisheye" / "poster-dev" / "ground_truth.json"))
    MDBRIEF_SKIP_WITHOUT_DATA("fisheye/poster-dev not in " << data);
  const PosterDev poster = loadPosterDev((data / "fisheye" / "poster-dev").string());
  EXPECT_EQ(poster.frames.size(), 10u);
  EXPECT_EQ(poster.camera->modelName(), "ocam");
  EXPECT_EQ(posterDevSequence(poster).pairs.size(), 45u);
}

}  // namespace
}  // namespace mdbrief::eval
