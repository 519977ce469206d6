// The `mdbrief` command line run in-process through runCli: every subcommand's success path
// (outputs checked for content and consistency) and bad input (exit code 2 and a one-line
// message naming the file or flag at fault).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli/commands.hpp"
#include "cli/storage_io.hpp"
#include "cli_runner.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/api/feature2d.hpp"
#include "scenes/plane_renderer.hpp"
#include "test_data.hpp"
#include "write_limits.hpp"

namespace mdbrief {
namespace {

namespace fs = std::filesystem;
using Result = testing::CliResult;
using testing::expectOneLineNaming;

Result run(std::vector<std::string> args) { return testing::runMdbrief(std::move(args)); }

const std::string kCamera = (testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string();

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mdbrief_test_cli_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Graffiti rendered through the paper's fisheye at a pose (x offset of the camera), saved
  // as PNG. Empty string without opencv-doc.
  std::string fisheyeImage(const std::string& name, double x = 0.3) {
    const auto doc = testing::opencvDocDataDir();
    if (!doc) return "";
    PlaneScene scene;
    scene.texture = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
    if (scene.texture.empty()) return "";
    scene.texelSize = 0.004;
    CameraPose pose;
    pose.centre = {x, 0.1, -0.8};
    const cv::Mat image = renderPlane(*loadCamera(kCamera), pose, scene);
    const std::string p = path(name);
    cv::imwrite(p, image);
    return p;
  }

  fs::path dir_;
};

#define REQUIRE_IMAGE(var, ...)                           \
  const std::string var = fisheyeImage(__VA_ARGS__);      \
  if (var.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed")

struct FeatureFile {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors, masks;
  bool hasMasks = false;
};

FeatureFile readFeatures(const std::string& p) {
  cv::FileStorage fs(p, cv::FileStorage::READ);
  EXPECT_TRUE(fs.isOpened()) << p;
  FeatureFile f;
  cv::read(fs["keypoints"], f.keypoints);
  fs["descriptors"] >> f.descriptors;
  f.hasMasks = !fs["masks"].empty();
  if (f.hasMasks) fs["masks"] >> f.masks;
  return f;
}

TEST_F(CliTest, ExtractMdBriefWritesAlignedKeypointsDescriptorsAndMasks) {
  REQUIRE_IMAGE(image, "view.png");
  const Result r = run({"extract", "--camera", kCamera, image, "-o", path("out.yml")});
  ASSERT_EQ(r.code, 0) << r.err;
  const FeatureFile f = readFeatures(path("out.yml"));
  ASSERT_GT(f.keypoints.size(), 500u);
  EXPECT_LE(f.keypoints.size(), 1000u);
  EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  EXPECT_EQ(f.descriptors.cols, 32);
  EXPECT_EQ(f.descriptors.type(), CV_8UC1);
  ASSERT_TRUE(f.hasMasks);
  EXPECT_EQ(f.masks.size(), f.descriptors.size());
  const auto camera = loadCamera(kCamera);
  for (const auto& kp : f.keypoints) EXPECT_TRUE(camera->isValid(kp.pt)) << kp.pt;
  // No temporary left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 2);
}

TEST_F(CliTest, ExtractBriefAndDBriefHaveNoMasksAndHonourBitsAndFeatures) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--descriptor", "dbrief", "--bits", "512", "--nfeatures", "300",
                 "--form", "paper", image, "-o", path("d.json")})
                .code,
            0);
  const FeatureFile d = readFeatures(path("d.json"));
  EXPECT_FALSE(d.hasMasks);
  EXPECT_EQ(d.descriptors.cols, 64);
  EXPECT_LE(d.keypoints.size(), 300u);
  EXPECT_GT(d.keypoints.size(), 100u);
  EXPECT_EQ(d.descriptors.rows, static_cast<int>(d.keypoints.size()));

  // BRIEF needs no calibration.
  ASSERT_EQ(run({"extract", "--descriptor", "brief", "--no-orientation", image, "-o", path("b.yml.gz")}).code, 0);
  const FeatureFile b = readFeatures(path("b.yml.gz"));
  EXPECT_FALSE(b.hasMasks);
  EXPECT_EQ(b.descriptors.rows, static_cast<int>(b.keypoints.size()));
  EXPECT_GT(b.keypoints.size(), 100u);

  // Masked BRIEF neither: BRIEF's bits plus masks.
  ASSERT_EQ(run({"extract", "--descriptor", "mbrief", image, "-o", path("m.yml")}).code, 0);
  const FeatureFile m = readFeatures(path("m.yml"));
  EXPECT_TRUE(m.hasMasks);
  EXPECT_EQ(m.descriptors.rows, static_cast<int>(m.keypoints.size()));
  EXPECT_GT(m.keypoints.size(), 100u);
}

TEST_F(CliTest, DetectorFlagSelectsTheHessianBlobsOrModOrbCorners) {
  REQUIRE_IMAGE(image, "view.png");
  // The pyramid of modORB's 31 * 1.2^octave sizes (the default detector's pyramid differs).
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--detector", "modorb", "--levels", "8", "--scale-factor", "1.2",
                 "--first-level", "0", "--nfeatures", "300", image, "-o", path("orb.yml")})
                .code,
            0);
  const Result r = run({"extract", "--camera", kCamera, "--nfeatures", "300", image, "-o", path("hessian.yml")});
  ASSERT_EQ(r.code, 0) << r.err;
  const FeatureFile corners = readFeatures(path("orb.yml")), blobs = readFeatures(path("hessian.yml"));
  EXPECT_GT(blobs.keypoints.size(), 100u);
  EXPECT_EQ(blobs.descriptors.rows, static_cast<int>(blobs.keypoints.size()));
  // modORB sizes are 31 * 1.2^octave exactly; refined blob scales (the default detector's) fall
  // between the default pyramid's levels, 31 * 1.25^(level - 1).
  const auto between = [](const FeatureFile& f, double factor) {
    return std::count_if(f.keypoints.begin(), f.keypoints.end(), [factor](const cv::KeyPoint& k) {
      const double level = std::log(k.size / 31.0) / std::log(factor);
      return std::abs(level - std::round(level)) > 0.05;
    });
  };
  EXPECT_EQ(between(corners, 1.2), 0);
  EXPECT_GT(between(blobs, 1.25), static_cast<long>(blobs.keypoints.size() / 2));
  const Result bad = run({"extract", "--camera", kCamera, "--detector", "harris", image, "-o", path("x.yml")});
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--detector"), std::string::npos) << bad.err;
}

// --preset picks the options the other flags start from; an unknown name exits 2 and lists the
// presets.
// nfeatures is one name in C++, Python and on the command line; the older --features names it.
TEST_F(CliTest, OldFeaturesFlagNamesNfeatures) {
  REQUIRE_IMAGE(image, "view.png");
  const Result r = run({"extract", "--camera", kCamera, "--features", "300", image, "-o", path("old.yml")});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--features: is now --nfeatures"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("old.yml")));
  const Result help = run({"extract", "--help"});
  EXPECT_NE(help.out.find("--nfeatures"), std::string::npos);
  EXPECT_EQ(help.out.find("--features "), std::string::npos) << "the old spelling is not offered";
}

TEST_F(CliTest, PresetChoosesTheStartingOptions) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--preset", "paper", image, "-o", path("paper.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--preset", "matching", image, "-o", path("matching.yml")}).code, 0);
  const FeatureFile paper = readFeatures(path("paper.yml")), matching = readFeatures(path("matching.yml"));
  // The paper's modORB: sizes 31 * 1.2^octave; matching: 512 bits.
  for (const auto& k : paper.keypoints) {
    const double level = std::log(k.size / 31.0) / std::log(1.2);
    ASSERT_NEAR(level, std::round(level), 1e-3) << k.size;
  }
  EXPECT_EQ(paper.descriptors.cols, 32);
  EXPECT_EQ(matching.descriptors.cols, 64);
  // A flag changes the preset's value.
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--preset", "matching", "--bits", "128", image, "-o",
                 path("m128.yml")})
                .code,
            0);
  EXPECT_EQ(readFeatures(path("m128.yml")).descriptors.cols, 16);
  // The paper's matcher keeps every query's nearest neighbour; the default a ratio test.
  ASSERT_EQ(run({"match", "--preset", "paper", path("paper.yml"), path("matching.yml"), "-o", path("p.yml")}).code, 2)
      << "descriptor lengths differ";
  const std::string other = fisheyeImage("other.png", 0.2);
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--preset", "paper", other, "-o", path("other.yml")}).code, 0);
  ASSERT_EQ(run({"match", "--preset", "paper", path("paper.yml"), path("other.yml"), "-o", path("p.yml")}).code, 0);
  ASSERT_EQ(run({"match", path("paper.yml"), path("other.yml"), "-o", path("t.yml")}).code, 0);
  cv::Mat all, kept;
  cv::FileStorage(path("p.yml"), cv::FileStorage::READ)["matches"] >> all;
  cv::FileStorage(path("t.yml"), cv::FileStorage::READ)["matches"] >> kept;
  EXPECT_EQ(all.rows, paper.descriptors.rows);
  EXPECT_LT(kept.rows, all.rows);
  for (const char* command : {"extract", "match"}) {
    const Result bad = command == std::string("extract")
                           ? run({"extract", "--camera", kCamera, "--preset", "fast", image, "-o", path("x.yml")})
                           : run({"match", "--preset", "fast", path("paper.yml"), path("paper.yml"), "-o", path("x.yml")});
    EXPECT_EQ(bad.code, 2) << command;
    EXPECT_NE(bad.err.find("--preset"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("tracking"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("paper"), std::string::npos) << bad.err;
  }
}

TEST_F(CliTest, OrientationSourceChangesTheAnglesOfDBrief) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--descriptor", "dbrief", image, "-o", path("tp.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--descriptor", "dbrief", "--orientation", "keypoint", image, "-o",
                 path("kp.yml")})
                .code,
            0);
  const FeatureFile tp = readFeatures(path("tp.yml")), kp = readFeatures(path("kp.yml"));
  ASSERT_GT(tp.keypoints.size(), 100u);
  // Same detections; the default re-measures the angle on the tangent plane and writes it back.
  std::map<std::pair<float, float>, float> kpAngle;
  for (const auto& k : kp.keypoints) kpAngle[{k.pt.x, k.pt.y}] = k.angle;
  int same = 0, differentAngle = 0;
  for (const auto& k : tp.keypoints) {
    const auto it = kpAngle.find({k.pt.x, k.pt.y});
    if (it == kpAngle.end()) continue;
    ++same;
    differentAngle += std::abs(k.angle - it->second) > 1e-3f;
  }
  EXPECT_GT(same, static_cast<int>(tp.keypoints.size()) * 9 / 10);
  EXPECT_GT(differentAngle, same / 2);
  expectOneLineNaming(run({"extract", "--camera", kCamera, "--orientation", "sideways", image, "-o", path("x.yml")}),
                      "sideways");
}

// A truncated JPEG decodes partly: extract warns naming the file (exit 0), or with --strict
// refuses it (exit 2) and writes nothing.
TEST_F(CliTest, TruncatedImagesWarnOrFailUnderStrict) {
  REQUIRE_IMAGE(image, "view.png");
  std::vector<uchar> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", cv::imread(image, cv::IMREAD_GRAYSCALE), jpeg));
  {
    std::ofstream cut(path("cut.jpg"), std::ios::binary);
    cut.write(reinterpret_cast<const char*>(jpeg.data()), static_cast<std::streamsize>(jpeg.size() / 2));
  }
  const Result warned = run({"extract", "--camera", kCamera, path("cut.jpg"), "-o", path("w.yml")});
  EXPECT_EQ(warned.code, 0) << warned.err;
  EXPECT_NE(warned.err.find("warning: " + path("cut.jpg") + ": truncated JPEG"), std::string::npos) << warned.err;
  const Result strict = run({"extract", "--strict", "--camera", kCamera, path("cut.jpg"), "-o", path("s.yml")});
  EXPECT_EQ(strict.code, 2);
  EXPECT_NE(strict.err.find("truncated JPEG"), std::string::npos) << strict.err;
  EXPECT_FALSE(std::filesystem::exists(path("s.yml")));
  // The intact file: no warning.
  {
    std::ofstream whole(path("whole.jpg"), std::ios::binary);
    whole.write(reinterpret_cast<const char*>(jpeg.data()), static_cast<std::streamsize>(jpeg.size()));
  }
  const Result clean = run({"extract", "--strict", "--camera", kCamera, path("whole.jpg"), "-o", path("c.yml")});
  EXPECT_EQ(clean.code, 0) << clean.err;
  EXPECT_EQ(clean.err.find("warning"), std::string::npos) << clean.err;
}

TEST_F(CliTest, ExtractRejectsKeypointFilesWithUnusableSizesOrPositions) {
  REQUIRE_IMAGE(image, "view.png");
  for (const float bad : {0.f, -5.f, NAN, INFINITY}) {
    {
      cv::FileStorage fs(path("badkp.yml"), cv::FileStorage::WRITE);
      cv::write(fs, "keypoints", std::vector<cv::KeyPoint>{cv::KeyPoint({392.f, 243.f}, 31.f, 0.f, 1.f, 0),
                                                           cv::KeyPoint({300.f, 200.f}, bad, 0.f, 1.f, 0)});
    }
    const Result r = run({"extract", "--camera", kCamera, "--keypoints", path("badkp.yml"), image, "-o", path("b.yml")});
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_NE(r.err.find("keypoint 1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("positive finite size"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("b.yml")));
  }
  // Sizes from another detector: described at a support proportional to the size.
  {
    cv::FileStorage fs(path("akaze.yml"), cv::FileStorage::WRITE);
    cv::write(fs, "keypoints", std::vector<cv::KeyPoint>{cv::KeyPoint({392.f, 243.f}, 7.5f, 0.f, 1.f, 99)});
  }
  const Result r = run({"extract", "--camera", kCamera, "--keypoints", path("akaze.yml"), "--support-scale", "6",
                        image, "-o", path("a.yml")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(readFeatures(path("a.yml")).keypoints.size(), 1u);
}

// Refused before OpenCV 4.6 parses them: it hangs on such files (fuzz/regressions/keypoints).
TEST_F(CliTest, ExtractRejectsMalformedKeypointFilesBeforeOpenCvParsesThem) {
  REQUIRE_IMAGE(image, "view.png");
  const std::vector<std::pair<std::string, std::string>> cases{
      {std::string("%YAML:1.0\n---\nkeypoints: [ 392, 243\0, 31, 0 ]\n", 46), "byte 35 is NUL"},
      {"%YAML:1.0\n---AML:1.0\n-*--\nkeypoints: [ 1 ]\n", "not well-formed YAML"},
      {"keypoints: " + std::string(100, '[') + std::string(100, ']') + "\n", "nested deeper than 64"}};
  for (const auto& [text, reason] : cases) {
    std::ofstream(path("bad.yml"), std::ios::binary | std::ios::trunc) << text;
    const Result r = run({"extract", "--camera", kCamera, "--keypoints", path("bad.yml"), image, "-o", path("n.yml")});
    EXPECT_EQ(r.code, 2) << reason;
    EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("n.yml")));
  }
}

TEST_F(CliTest, ExtractGivenKeypointsDropsTheUndescribableConsistently) {
  REQUIRE_IMAGE(image, "view.png");
  std::vector<cv::KeyPoint> given = {
      cv::KeyPoint({392.f, 243.f}, 31.f, 10.f, 1.f, 0),  // image centre: describable
      cv::KeyPoint({3.f, 3.f}, 31.f, 0.f, 1.f, 0),       // outside the image circle
      cv::KeyPoint({300.f, 200.f}, 37.2f, 45.f, 1.f, 1),
      cv::KeyPoint({750.f, 470.f}, 31.f, 0.f, 1.f, 0),   // image corner
  };
  {
    cv::FileStorage fs(path("kp.yml"), cv::FileStorage::WRITE);
    cv::write(fs, "keypoints", given);
  }
  const Result r = run({"extract", "--camera", kCamera, "--keypoints", path("kp.yml"), image, "-o", path("o.yml")});
  ASSERT_EQ(r.code, 0) << r.err;
  const FeatureFile f = readFeatures(path("o.yml"));
  ASSERT_EQ(f.keypoints.size(), 2u);
  EXPECT_EQ(f.keypoints[0].pt, given[0].pt);
  EXPECT_EQ(f.keypoints[1].pt, given[2].pt);
  EXPECT_EQ(f.descriptors.rows, 2);
  EXPECT_EQ(f.masks.rows, 2);
  // The same as the library describes them.
  std::vector<cv::KeyPoint> kps = given;
  cv::Mat desc;
  MdBrief::create(loadCamera(kCamera))->compute(cv::imread(image, cv::IMREAD_GRAYSCALE), kps, desc);
  EXPECT_EQ(cv::norm(desc, f.descriptors, cv::NORM_HAMMING), 0.0);
}

TEST_F(CliTest, ExtractSeveralImagesWritesOneFilePerImageIntoTheFolder) {
  REQUIRE_IMAGE(a, "left.png", 0.3);
  const std::string b = fisheyeImage("right.png", 0.2);
  fs::create_directory(path("out"));
  ASSERT_EQ(run({"extract", "--camera", kCamera, a, b, "-o", path("out")}).code, 0);
  EXPECT_GT(readFeatures(path("out/left.yml")).keypoints.size(), 100u);
  EXPECT_GT(readFeatures(path("out/right.yml")).keypoints.size(), 100u);
  expectOneLineNaming(run({"extract", "--camera", kCamera, a, b, "-o", path("missing")}), path("missing"));
}

TEST_F(CliTest, MatchingAFileWithItselfPairsEveryRowWithItself) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--camera", kCamera, image, "-o", path("a.yml")}).code, 0);
  const Result r = run({"match", path("a.yml"), path("a.yml"), "--no-ratio", "-o", path("m.yml")});  // mutual by default
  ASSERT_EQ(r.code, 0) << r.err;
  cv::FileStorage fs(path("m.yml"), cv::FileStorage::READ);
  cv::Mat m;
  fs["matches"] >> m;
  EXPECT_EQ(static_cast<int>(fs["masked"]), 1);
  const int n = readFeatures(path("a.yml")).descriptors.rows;
  ASSERT_EQ(m.cols, 3);
  // Identical descriptors may exist (ties go to the lower row), so not strictly all rows.
  ASSERT_GT(m.rows, n * 95 / 100);
  int self = 0;
  for (int i = 0; i < m.rows; ++i) self += m.at<double>(i, 0) == m.at<double>(i, 1) && m.at<double>(i, 2) == 0.0;
  EXPECT_GT(self, n * 95 / 100);
}

TEST_F(CliTest, MatchingTwoViewsFindsMatchesWithinLimits) {
  REQUIRE_IMAGE(a, "a.png", 0.3);
  const std::string b = fisheyeImage("b.png", 0.25);
  ASSERT_EQ(run({"extract", "--camera", kCamera, a, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, b, "-o", path("b.yml")}).code, 0);
  ASSERT_EQ(run({"match", path("a.yml"), path("b.yml"), "--max-distance", "40", "-o", path("m.json")}).code, 0);
  cv::FileStorage fs(path("m.json"), cv::FileStorage::READ);
  cv::Mat m;
  fs["matches"] >> m;
  const FeatureFile fa = readFeatures(path("a.yml")), fb = readFeatures(path("b.yml"));
  ASSERT_GT(m.rows, 100);
  for (int i = 0; i < m.rows; ++i) {
    EXPECT_GE(m.at<double>(i, 0), 0);
    EXPECT_LT(m.at<double>(i, 0), fa.descriptors.rows);
    EXPECT_LT(m.at<double>(i, 1), fb.descriptors.rows);
    EXPECT_LE(m.at<double>(i, 2), 40.0);
  }
  // Plain matching when masks are missing on one side.
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--descriptor", "dbrief", b, "-o", path("bd.yml")}).code, 0);
  ASSERT_EQ(run({"match", path("a.yml"), path("bd.yml"), "-o", path("m2.yml")}).code, 0);
  cv::FileStorage fs2(path("m2.yml"), cv::FileStorage::READ);
  EXPECT_EQ(static_cast<int>(fs2["masked"]), 0);
}

TEST_F(CliTest, DrawWritesDecodablePngs) {
  REQUIRE_IMAGE(a, "a.png", 0.3);
  const std::string b = fisheyeImage("b.png", 0.25);
  ASSERT_EQ(run({"draw", "--camera", kCamera, a, "--keypoint", "3", "-o", path("one.png")}).code, 0);
  const cv::Mat one = cv::imread(path("one.png"), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one.type(), CV_8UC3);
  EXPECT_EQ(one.size(), cv::Size(754, 480));

  ASSERT_EQ(run({"extract", "--camera", kCamera, a, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, b, "-o", path("b.yml")}).code, 0);
  ASSERT_EQ(run({"match", path("a.yml"), path("b.yml"), "-o", path("m.yml")}).code, 0);
  const Result r = run({"draw", "--camera", kCamera, a, "--other", b, "--matches", path("m.yml"), "-o", path("two.png")});
  ASSERT_EQ(r.code, 0) << r.err;
  const cv::Mat two = cv::imread(path("two.png"));
  EXPECT_EQ(two.size(), cv::Size(2 * 754, 480));

  expectOneLineNaming(run({"draw", "--camera", kCamera, a, "--keypoint", "100000", "-o", path("x.png")}),
                      "--keypoint");
  expectOneLineNaming(run({"draw", "--camera", kCamera, a, "--other", b, "-o", path("x.png")}), "--matches");
}

// Number of pixels whose colour is exactly (b, g, r).
int countColour(const cv::Mat& image, cv::Vec3b colour) {
  int n = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) n += image.at<cv::Vec3b>(y, x) == colour;
  return n;
}

// "<n> <word>" in text (the number just before the word), or -1.
int countBefore(const std::string& text, const std::string& word) {
  const size_t at = text.find(" " + word);
  if (at == std::string::npos) return -1;
  size_t start = at;
  while (start > 0 && std::isdigit(static_cast<unsigned char>(text[start - 1]))) --start;
  return start == at ? -1 : std::stoi(text.substr(start, at - start));
}

// Two views of one plane: a homography relates their bearings, so the matches of a correct
// matcher mostly agree with the robust fit, and matches shuffled against each other mostly do not.
TEST_F(CliTest, DrawMatchesColoursCorrectAndWrongAndMatchCountsInliers) {
  REQUIRE_IMAGE(a, "a.png", 0.3);
  const std::string b = fisheyeImage("b.png", 0.25);
  ASSERT_EQ(run({"extract", "--camera", kCamera, a, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, b, "-o", path("b.yml")}).code, 0);
  const Result m = run({"match", path("a.yml"), path("b.yml"), "--inliers", "--camera", kCamera, "-o", path("m.yml")});
  ASSERT_EQ(m.code, 0) << m.err;
  const int matches = countBefore(m.out, "masked matches"), inliers = countBefore(m.out, "inliers");
  ASSERT_GT(matches, 50) << m.out;
  EXPECT_GT(inliers, matches / 2) << m.out;
  EXPECT_LE(inliers, matches);

  const Result d = run({"draw", "--camera", kCamera, a, "--other", b, "--matches", path("m.yml"), "-o", path("d.png")});
  ASSERT_EQ(d.code, 0) << d.err;
  // The same fit on the same matches: draw's correct count is match's inlier count.
  EXPECT_EQ(countBefore(d.out, "matches:"), matches) << d.out;
  EXPECT_EQ(countBefore(d.out, "correct"), inliers) << d.out;
  EXPECT_EQ(countBefore(d.out, "wrong"), matches - inliers) << d.out;
  const cv::Mat drawn = cv::imread(path("d.png"));
  EXPECT_GT(countColour(drawn, {0, 255, 0}), 0);

  // Train indices rotated by one: nearly every match is wrong, drawn red.
  cv::FileStorage in(path("m.yml"), cv::FileStorage::READ);
  cv::Mat table;
  in["matches"] >> table;
  in.release();
  const cv::Mat trainColumn = table.col(1).clone();
  for (int i = 0; i < table.rows; ++i) table.at<double>(i, 1) = trainColumn.at<double>((i + 1) % table.rows);
  cv::FileStorage out(path("shuffled.yml"), cv::FileStorage::WRITE);
  out << "matches" << table;
  out.release();
  const Result s =
      run({"draw", "--camera", kCamera, a, "--other", b, "--matches", path("shuffled.yml"), "-o", path("s.png")});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_LT(countBefore(s.out, "correct"), matches / 10) << s.out;
  EXPECT_GT(countColour(cv::imread(path("s.png")), {0, 0, 255}), countColour(cv::imread(path("d.png")), {0, 0, 255}));

  // A ground-truth homography that maps nothing onto its match: every match wrong.
  std::ofstream(path("h.txt")) << "1 0 5000\n0 1 0\n0 0 1\n";
  const Result g = run({"draw", "--camera", kCamera, a, "--other", b, "--matches", path("m.yml"), "--homography",
                        path("h.txt"), "-o", path("g.png")});
  ASSERT_EQ(g.code, 0) << g.err;
  EXPECT_EQ(countBefore(g.out, "correct"), 0) << g.out;
  EXPECT_NE(g.out.find("ground-truth homography"), std::string::npos) << g.out;

  std::ofstream(path("bad_h.txt")) << "1 0 0\n";
  expectOneLineNaming(run({"draw", "--camera", kCamera, a, "--other", b, "--matches", path("m.yml"), "--homography",
                           path("bad_h.txt"), "-o", path("x.png")}),
                      path("bad_h.txt"));
  expectOneLineNaming(run({"draw", "--camera", kCamera, a, "--homography", path("h.txt"), "-o", path("x.png")}),
                      "--homography");
  expectOneLineNaming(run({"match", path("a.yml"), path("b.yml"), "--camera", kCamera, "-o", path("x.yml")}),
                      "--inliers");
}

// A stereo rig (Kalibr camchain: two equidistant fisheye cameras 5 cm apart, cam1's T_cn_cnm1)
// renders one plane: `match --inliers` checks the matches with the essential matrix by default,
// or against the rig's extrinsics with --model pose (--camera-b-id picks the second camera of the
// same file), and says which model it used. A wrong baseline in the file rejects the matches.
TEST_F(CliTest, MatchInliersUsesTheGeneralModelOrTheRigsRelativePose) {
  const auto doc = testing::opencvDocDataDir();
  cv::Mat texture;
  if (doc) texture = cv::imread((*doc / "graf1.png").string(), cv::IMREAD_GRAYSCALE);
  if (texture.empty()) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc graf1.png not installed");
  const auto camchain = [&](const std::string& name, const std::string& t) {
    const std::string camera = "  camera_model: pinhole\n  distortion_model: equidistant\n"
                               "  distortion_coeffs: [-0.0125, 0.0578, -0.0850, 0.0436]\n"
                               "  intrinsics: [461.6, 460.3, 366.3, 249.1]\n  resolution: [752, 480]\n";
    std::ofstream(path(name)) << "cam0:\n" << camera << "cam1:\n  T_cn_cnm1:\n" << t << camera;
    return path(name);
  };
  // cam1 sits 5 cm right of cam0 (+x), same orientation: X_1 = X_0 - (0.05, 0, 0).
  const std::string rig = camchain("rig.yaml",
                                   "  - [1.0, 0.0, 0.0, -0.05]\n  - [0.0, 1.0, 0.0, 0.0]\n"
                                   "  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n");
  const std::string wrong = camchain("wrong.yaml",
                                     "  - [1.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, -0.05]\n"
                                     "  - [0.0, 0.0, 1.0, 0.0]\n  - [0.0, 0.0, 0.0, 1.0]\n");
  PlaneScene scene;
  scene.texture = texture;
  scene.texelSize = 0.004;
  const auto camera = loadCamera(rig, {CameraFormat::Auto, "cam0"});
  for (const auto& [name, x] : {std::pair<std::string, double>{"left.png", 0.25}, {"right.png", 0.30}}) {
    CameraPose pose;
    pose.centre = {x, 0.1, -0.8};
    cv::imwrite(path(name), renderPlane(*camera, pose, scene));
  }
  ASSERT_EQ(run({"extract", "--camera", rig, "--camera-id", "cam0", path("left.png"), "-o", path("l.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", rig, "--camera-id", "cam1", path("right.png"), "-o", path("r.yml")}).code, 0);
  const std::vector<std::string> base = {"match", path("l.yml"), path("r.yml"), "--inliers", "--camera", rig,
                                         "--camera-id", "cam0", "--camera-b-id", "cam1", "-o", path("m.yml")};
  const auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  };
  const Result general = with({});
  ASSERT_EQ(general.code, 0) << general.err;
  const int matches = countBefore(general.out, "masked matches");
  ASSERT_GT(matches, 50) << general.out;
  EXPECT_NE(general.out.find("essential matrix on bearings"), std::string::npos) << general.out;
  EXPECT_GT(countBefore(general.out, "inliers"), matches * 8 / 10) << general.out;

  const Result pose = with({"--model", "pose"});
  ASSERT_EQ(pose.code, 0) << pose.err;
  EXPECT_NE(pose.out.find("known relative pose of " + rig + " (cam0 and cam1)"), std::string::npos) << pose.out;
  EXPECT_GT(countBefore(pose.out, "inliers"), matches * 8 / 10) << pose.out;

  const Result plane = with({"--model", "homography"});
  ASSERT_EQ(plane.code, 0) << plane.err;
  EXPECT_NE(plane.out.find("homography on bearings"), std::string::npos) << plane.out;

  // The same matches against a baseline the file gets wrong (5 cm down instead of right).
  std::vector<std::string> wrongArgs = base;
  std::replace(wrongArgs.begin(), wrongArgs.end(), rig, wrong);
  wrongArgs.insert(wrongArgs.end(), {"--model", "pose"});
  const Result rejected = run(wrongArgs);
  ASSERT_EQ(rejected.code, 0) << rejected.err;
  EXPECT_LT(countBefore(rejected.out, "inliers"), matches / 2) << rejected.out;

  // What the models need, named.
  expectOneLineNaming(run({"match", path("l.yml"), path("r.yml"), "--inliers", "--model", "pose", "--camera", rig,
                           "--camera-id", "cam0", "-o", path("x.yml")}),
                      "--camera-b");
  expectOneLineNaming(run({"match", path("l.yml"), path("r.yml"), "--inliers", "--model", "essential", "-o",
                           path("x.yml")}),
                      "--model essential needs --camera");
  expectOneLineNaming(run({"match", path("l.yml"), path("r.yml"), "--inliers", "--camera-b", rig, "-o", path("x.yml")}),
                      "--camera-b needs --camera");
  // A file without extrinsics: the rig's pose cannot be asked of it.
  std::ofstream(path("two.yaml")) << "cam0:\n  camera_model: pinhole\n  distortion_model: none\n  distortion_coeffs: []\n"
                                     "  intrinsics: [461.6, 460.3, 366.3, 249.1]\n  resolution: [752, 480]\n"
                                     "cam1:\n  camera_model: pinhole\n  distortion_model: none\n  distortion_coeffs: []\n"
                                     "  intrinsics: [461.6, 460.3, 366.3, 249.1]\n  resolution: [752, 480]\n";
  ASSERT_EQ(run({"extract", "--camera", path("two.yaml"), "--camera-id", "cam0", path("left.png"), "-o",
                 path("p0.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", path("two.yaml"), "--camera-id", "cam1", path("right.png"), "-o",
                 path("p1.yml")}).code, 0);
  expectOneLineNaming(run({"match", path("p0.yml"), path("p1.yml"), "--inliers", "--model", "pose", "--camera",
                           path("two.yaml"), "--camera-id", "cam0", "--camera-b-id", "cam1", "-o", path("x.yml")}),
                      path("two.yaml"));

  // draw: the other image with its own camera, the same model and count as match.
  const Result d = run({"draw", "--camera", rig, "--camera-id", "cam0", path("left.png"), "--other", path("right.png"),
                        "--other-camera-id", "cam1", "--matches", path("m.yml"), "--model", "pose", "-o", path("d.png")});
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_EQ(countBefore(d.out, "correct"), countBefore(pose.out, "inliers")) << d.out;
  EXPECT_NE(d.out.find("known relative pose"), std::string::npos) << d.out;
}

TEST_F(CliTest, MatchInliersWithoutCameraFitsPixelsAndNeedsKeypoints) {
  REQUIRE_IMAGE(a, "a.png", 0.3);
  ASSERT_EQ(run({"extract", "--descriptor", "brief", a, "-o", path("a.yml")}).code, 0);
  // An image against itself: every match is the identity, which a homography explains.
  const Result r = run({"match", path("a.yml"), path("a.yml"), "--inliers", "-o", path("m.yml")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(countBefore(r.out, "matches,"), 50) << r.out;
  EXPECT_EQ(countBefore(r.out, "inliers"), countBefore(r.out, "matches,")) << r.out;
  // draw fits the same pixel-plane homography without a calibration.
  const Result d = run({"draw", "--descriptor", "brief", a, "--other", a, "--matches", path("m.yml"), "-o", path("d.png")});
  ASSERT_EQ(d.code, 0) << d.err;
  EXPECT_EQ(countBefore(d.out, "correct"), countBefore(r.out, "inliers")) << d.out;
  EXPECT_EQ(countBefore(d.out, "wrong"), 0) << d.out;

  cv::FileStorage in(path("a.yml"), cv::FileStorage::READ);
  cv::Mat descriptors;
  in["descriptors"] >> descriptors;
  in.release();
  cv::FileStorage out(path("bare.yml"), cv::FileStorage::WRITE);
  out << "descriptors" << descriptors;
  out.release();
  expectOneLineNaming(run({"match", path("bare.yml"), path("a.yml"), "--inliers", "-o", path("x.yml")}),
                      path("bare.yml"));

  // Far-off keypoints (a file written by another program): counted, never an overflow.
  cli::Features far;
  for (int i = 0; i < 8; ++i) far.keypoints.emplace_back(cv::Point2f(1e30f * static_cast<float>(i + 1), 3e9f), 7.f);
  far.descriptors = descriptors.rowRange(0, 8).clone();
  cli::writeFeatureFiles({path("far.yml")}, {far});
  const Result f = run({"match", path("far.yml"), path("far.yml"), "--inliers", "-o", path("f.yml")});
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_GE(countBefore(f.out, "inliers"), 0) << f.out;
}

// Issue 45: `draw --matches` with the images swapped reported 9 right and 108 wrong, exit 0.
// match records its feature files and a digest of each one's descriptors; draw refuses a match
// file whose digests are not those of its images as described, and says when they are swapped.
TEST_F(CliTest, DrawRefusesAMatchFileOfOtherFeatures) {
  REQUIRE_IMAGE(a, "a.png", 0.3);
  const std::string b = fisheyeImage("b.png", 0.25);
  ASSERT_EQ(run({"extract", "--camera", kCamera, a, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, b, "-o", path("b.yml")}).code, 0);
  ASSERT_EQ(run({"match", path("a.yml"), path("b.yml"), "-o", path("m.yml")}).code, 0);
  {
    cv::FileStorage m(path("m.yml"), cv::FileStorage::READ);
    EXPECT_EQ(static_cast<std::string>(m["query"]), path("a.yml"));
    EXPECT_EQ(static_cast<std::string>(m["train"]), path("b.yml"));
    EXPECT_EQ(static_cast<std::string>(m["query_digest"]).size(), 16u);
    EXPECT_EQ(static_cast<std::string>(m["train_digest"]).size(), 16u);
    EXPECT_NE(static_cast<std::string>(m["query_digest"]), static_cast<std::string>(m["train_digest"]));
  }
  const Result right = run({"draw", "--camera", kCamera, a, "--other", b, "--matches", path("m.yml"), "-o", path("d.png")});
  ASSERT_EQ(right.code, 0) << right.err;

  const Result swapped =
      run({"draw", "--camera", kCamera, b, "--other", a, "--matches", path("m.yml"), "-o", path("s.png")});
  expectOneLineNaming(swapped, path("m.yml"));
  EXPECT_NE(swapped.err.find("swapped"), std::string::npos) << swapped.err;
  EXPECT_FALSE(fs::exists(path("s.png")));

  // Other flags describe other features: the indices would point at other keypoints.
  const Result other = run({"draw", "--camera", kCamera, "--bits", "512", a, "--other", b, "--matches", path("m.yml"),
                            "-o", path("o.png")});
  expectOneLineNaming(other, path("m.yml"));
  EXPECT_NE(other.err.find("the flags used for extract"), std::string::npos) << other.err;
  EXPECT_FALSE(fs::exists(path("o.png")));
}

// Issue 45: `match --inliers` dropped a keypoint at a NaN position without a word. Every reader
// of keypoints refuses a position that is not finite, naming the file and the keypoint.
TEST_F(CliTest, FeatureFilesWithKeypointsAtNonFinitePositionsAreRefused) {
  cli::Features f;
  for (int i = 0; i < 8; ++i) f.keypoints.emplace_back(cv::Point2f(10.f * static_cast<float>(i), 5.f), 7.f);
  f.descriptors = cv::Mat(8, 32, CV_8UC1, cv::Scalar(3));
  cli::writeFeatureFiles({path("good.yml")}, {f});
  for (const float bad : {std::nanf(""), std::numeric_limits<float>::infinity()}) {
    f.keypoints[3].pt.y = bad;
    for (const char* name : {"bad.yml", "bad.xml"}) {
      cli::writeFeatureFiles({path(name)}, {f});
      for (const bool inliers : {false, true}) {
        std::vector<std::string> args = {"match", path(name), path("good.yml"), "-o", path("m.yml")};
        if (inliers) args.push_back("--inliers");
        const Result r = run(args);
        expectOneLineNaming(r, path(name));
        EXPECT_NE(r.err.find("keypoint 3"), std::string::npos) << r.err;
      }
    }
  }
  EXPECT_FALSE(fs::exists(path("m.yml")));
}

// Issue 45: --model pose with opencv-kd calibrations (K and D, no image size, no extrinsics)
// asked for --camera-size when it was given; what is missing is the extrinsics, and it is said.
TEST_F(CliTest, ModelPoseWithCalibrationsWithoutExtrinsicsSaysSo) {
  cli::Features f;
  for (int i = 0; i < 8; ++i) f.keypoints.emplace_back(cv::Point2f(100.f + 40.f * static_cast<float>(i), 200.f), 7.f);
  f.descriptors = cv::Mat(8, 32, CV_8UC1, cv::Scalar(3));
  cli::writeFeatureFiles({path("a.yml")}, {f});
  const fs::path kd = testing::sourceDir() / "tests/data/camera_formats/opencv_kd_fisheye.yaml";
  fs::copy_file(kd, path("kd0.yaml"));
  fs::copy_file(kd, path("kd1.yaml"));
  const Result r = run({"match", path("a.yml"), path("a.yml"), "--inliers", "--model", "pose", "--camera",
                        path("kd0.yaml"), "--camera-size", "752x480", "--camera-opencv-model", "fisheye",
                        "--camera-b", path("kd1.yaml"), "--camera-b-size", "752x480", "--camera-b-opencv-model",
                        "fisheye", "-o", path("m.yml")});
  expectOneLineNaming(r, "no extrinsics");
  EXPECT_NE(r.err.find(path("kd0.yaml")), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("camera-size"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("image size"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("m.yml")));
}

TEST_F(CliTest, DrawNoKeypointsLeavesTheImageGrey) {
  REQUIRE_IMAGE(a, "a.png", 0.3);
  ASSERT_EQ(run({"draw", "--camera", kCamera, a, "--no-keypoints", "-o", path("plain.png")}).code, 0);
  const cv::Mat plain = cv::imread(path("plain.png"));
  const cv::Mat grey = cv::imread(a, cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(plain.size(), grey.size());
  cv::Mat expected;
  cv::cvtColor(grey, expected, cv::COLOR_GRAY2BGR);
  EXPECT_EQ(cv::norm(plain, expected, cv::NORM_INF), 0);
  // Drawn keypoints are coloured.
  ASSERT_EQ(run({"draw", "--camera", kCamera, a, "-o", path("circles.png")}).code, 0);
  EXPECT_GT(cv::norm(cv::imread(path("circles.png")), expected, cv::NORM_INF), 0);
}

TEST_F(CliTest, HelpExitsZeroForEverySubcommand) {
  for (const char* cmd : {"extract", "match", "draw", "camera"}) {
    const Result r = run({cmd, "--help"});
    EXPECT_EQ(r.code, 0) << cmd;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << cmd;
  }
}

TEST_F(CliTest, BadUsageExitsTwo) {
  // The input files exist (any regular file passes the parse-time check), so the usage is at fault.
  const std::string file = kCamera;
  expectOneLineNaming(run({}), "subcommand");
  expectOneLineNaming(run({"extract", "--camera", kCamera, "--frobnicate", file, "-o", path("o.yml")}),
                      "--frobnicate");
  expectOneLineNaming(run({"extract", "--camera", kCamera, "--descriptor", "surf", file, "-o", path("o.yml")}),
                      "surf");
  expectOneLineNaming(run({"extract", "--camera", kCamera, "--form", "exact", file, "-o", path("o.yml")}), "exact");
  expectOneLineNaming(run({"extract", "--camera", kCamera, file}), "--output");
  expectOneLineNaming(run({"match", file, file, "--ratio", "1.5", "-o", path("m.yml")}), "--ratio");
}

TEST_F(CliTest, ExtractRejectsBadInputFiles) {
  REQUIRE_IMAGE(image, "view.png");
  // Missing image.
  expectOneLineNaming(run({"extract", "--camera", kCamera, path("nope.png"), "-o", path("o.yml")}), path("nope.png"));
  // Empty file.
  std::ofstream(path("empty.png")).close();
  expectOneLineNaming(run({"extract", "--camera", kCamera, path("empty.png"), "-o", path("o.yml")}),
                      path("empty.png"));
  // Truncated PNG: the first half of a valid one.
  std::ifstream in(image, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(path("half.png"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expectOneLineNaming(run({"extract", "--camera", kCamera, path("half.png"), "-o", path("o.yml")}), path("half.png"));
  // Not an image at all.
  std::ofstream(path("text.png")) << "hello\n";
  expectOneLineNaming(run({"extract", "--camera", kCamera, path("text.png"), "-o", path("o.yml")}), path("text.png"));
  // Missing calibration, and a calibration with a bad value.
  expectOneLineNaming(run({"extract", "--camera", path("nocam.yaml"), image, "-o", path("o.yml")}),
                      path("nocam.yaml"));
  std::ifstream camIn(kCamera);
  std::string cam((std::istreambuf_iterator<char>(camIn)), std::istreambuf_iterator<char>());
  cam.replace(cam.find("u0: "), 4, "u0: not_a_number #");
  std::ofstream(path("bad.yaml")) << cam;
  const Result bad = run({"extract", "--camera", path("bad.yaml"), image, "-o", path("o.yml")});
  expectOneLineNaming(bad, path("bad.yaml"));
  EXPECT_NE(bad.err.find("u0"), std::string::npos) << bad.err;
  // dBRIEF without a calibration.
  expectOneLineNaming(run({"extract", image, "-o", path("o.yml")}), "--camera");
  // Bad keypoint file.
  std::ofstream(path("kp.yml")) << "%YAML:1.0\n---\nother: 1\n";
  expectOneLineNaming(run({"extract", "--camera", kCamera, "--keypoints", path("kp.yml"), image, "-o", path("o.yml")}),
                      path("kp.yml"));
  // Bits not a multiple of 32.
  expectOneLineNaming(run({"extract", "--camera", kCamera, "--bits", "100", image, "-o", path("o.yml")}), "bits");
  EXPECT_FALSE(fs::exists(path("o.yml")));
}

TEST_F(CliTest, ExtractChecksTheImageSizeAgainstTheCalibration) {
  const auto doc = testing::opencvDocDataDir();
  if (!doc) MDBRIEF_SKIP_WITHOUT_DATA("opencv-doc data not installed");
  const std::string graf = (*doc / "graf1.png").string();  // 800x640, the calibration is 754x480
  const Result r = run({"extract", "--camera", kCamera, graf, "-o", path("o.yml")});
  expectOneLineNaming(r, graf);
  EXPECT_NE(r.err.find("--allow-size-mismatch"), std::string::npos);
  EXPECT_FALSE(fs::exists(path("o.yml")));
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--allow-size-mismatch", graf, "-o", path("o.yml")}).code, 0);
  const FeatureFile f = readFeatures(path("o.yml"));
  EXPECT_GT(f.keypoints.size(), 100u);
  // Keypoints may now reach the rescaled circle's wider extent.
  const auto scaled = loadCamera(kCamera)->resized({800, 640});
  for (const auto& kp : f.keypoints) EXPECT_TRUE(scaled->isValid(kp.pt));
}

TEST_F(CliTest, OutputInAMissingFolderOrWithAnUnknownExtensionFails) {
  REQUIRE_IMAGE(image, "view.png");
  expectOneLineNaming(run({"extract", "--camera", kCamera, image, "-o", path("no/such/o.yml")}), path("no/such/o.yml"));
  expectOneLineNaming(run({"extract", "--camera", kCamera, image, "-o", path("o.txt")}), path("o.txt"));
  ASSERT_EQ(run({"extract", "--camera", kCamera, image, "-o", path("a.yml")}).code, 0);
  expectOneLineNaming(run({"match", path("a.yml"), path("a.yml"), "-o", path("no/m.yml")}), path("no/m.yml"));
  expectOneLineNaming(run({"draw", "--camera", kCamera, image, "-o", path("no/d.png")}), path("no/d.png"));
}

TEST_F(CliTest, MatchRejectsBadFeatureFiles) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--camera", kCamera, image, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--bits", "512", image, "-o", path("long.yml")}).code, 0);
  expectOneLineNaming(run({"match", path("a.yml"), path("none.yml"), "-o", path("m.yml")}), path("none.yml"));
  std::ofstream(path("garbage.yml")) << "this: [is not: closed\n";
  expectOneLineNaming(run({"match", path("garbage.yml"), path("a.yml"), "-o", path("m.yml")}), path("garbage.yml"));
  std::ofstream(path("nodesc.yml")) << "%YAML:1.0\n---\nkeypoints: []\n";
  expectOneLineNaming(run({"match", path("nodesc.yml"), path("a.yml"), "-o", path("m.yml")}), path("nodesc.yml"));
  expectOneLineNaming(run({"match", path("a.yml"), path("long.yml"), "-o", path("m.yml")}), path("long.yml"));
  EXPECT_FALSE(fs::exists(path("m.yml")));
}

// A write that fails (here: beyond the file size limit) keeps the previous output byte for byte,
// leaves no temporary and exits 2, for every FileStorage format and for match as for extract.
TEST_F(CliTest, AFailedWriteKeepsThePreviousOutputAndExitsTwo) {
  REQUIRE_IMAGE(image, "view.png");
  const std::vector<std::string> outputs{"keep.yml", "keep.yml.gz", "keep.json"};
  for (const auto& name : outputs)
    ASSERT_EQ(run({"extract", "--descriptor", "brief", "--nfeatures", "20", image, "-o", path(name)}).code, 0);
  ASSERT_EQ(run({"extract", "--descriptor", "brief", image, "-o", path("all.yml")}).code, 0);
  ASSERT_EQ(run({"match", path("keep.yml"), path("keep.yml"), "-o", path("matches.yml")}).code, 0);
  std::map<std::string, std::string> before;
  for (const auto& name : {"keep.yml", "keep.yml.gz", "keep.json", "matches.yml"}) before[name] = testing::readFile(path(name));
  std::vector<Result> results;
  {
    const testing::FileSizeLimit limit(8192);  // each new output is larger
    for (const auto& name : outputs)
      results.push_back(run({"extract", "--descriptor", "brief", image, "-o", path(name)}));
    results.push_back(run({"match", path("all.yml"), path("all.yml"), "--no-ratio", "-o", path("matches.yml")}));
  }
  const std::vector<std::string> names{"keep.yml", "keep.yml.gz", "keep.json", "matches.yml"};
  for (size_t i = 0; i < names.size(); ++i) {
    expectOneLineNaming(results[i], path(names[i]));
    EXPECT_NE(results[i].err.find("File too large"), std::string::npos) << results[i].err;
    EXPECT_EQ(testing::readFile(path(names[i])), before[names[i]]) << names[i] << " changed";
  }
  EXPECT_EQ(testing::temporaryFiles(dir_), std::vector<std::string>{});
}

TEST_F(CliTest, AFullDiskKeepsThePreviousOutputAndExitsTwo) {
  REQUIRE_IMAGE(image, "view.png");
  testing::SmallTmpfs disk("cli", 256 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
  const std::string keep = (disk.path / "keep.yml.gz").string();
  ASSERT_EQ(run({"extract", "--descriptor", "brief", "--nfeatures", "20", image, "-o", keep}).code, 0);
  const std::string before = testing::readFile(keep);
  disk.fill();
  const Result r = run({"extract", "--descriptor", "brief", image, "-o", keep});
  expectOneLineNaming(r, keep);
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_EQ(testing::readFile(keep), before);
  EXPECT_EQ(testing::temporaryFiles(disk.path), std::vector<std::string>{});
}

// -o naming a FIFO, a folder or a device (what /dev/null is) is refused before any work; the
// node stays what it was instead of being replaced by a regular file.
TEST_F(CliTest, OutputsThatAreNotRegularFilesAreRefusedAndKept) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--descriptor", "brief", "--nfeatures", "20", image, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(::mkfifo(path("fifo.yml").c_str(), 0600), 0);
  fs::create_directory(path("folder.yml"));
  std::vector<std::string> nodes{path("fifo.yml"), path("folder.yml")};
  // Only root may make a device node.
  if (::mknod(path("null.yml").c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0) nodes.push_back(path("null.yml"));
  if (::mknod(path("null.png").c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0) nodes.push_back(path("null.png"));
  for (const auto& node : nodes) {
    const fs::file_type type = fs::symlink_status(node).type();
    Result r;
    if (fs::path(node).extension() == ".png")
      r = run({"draw", "--descriptor", "brief", image, "-o", node});
    else if (type == fs::file_type::fifo)
      r = run({"match", path("a.yml"), path("a.yml"), "-o", node});
    else
      r = run({"extract", "--descriptor", "brief", image, "-o", node});
    expectOneLineNaming(r, node);
    EXPECT_NE(r.err.find("not a regular file; refusing to replace it"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << "refused before the work";
    EXPECT_EQ(fs::symlink_status(node).type(), type) << node;
  }
}

// A folder, a FIFO or a symlink loop given as an input is reported as what it is, not as a
// missing file, and a FIFO is never opened (which would block).
TEST_F(CliTest, InputsThatAreNotFilesAreNamedForWhatTheyAre) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--descriptor", "brief", "--nfeatures", "20", image, "-o", path("a.yml")}).code, 0);
  fs::create_directory(path("folder.png"));
  ASSERT_EQ(::mkfifo(path("fifo.yml").c_str(), 0600), 0);
  fs::create_symlink("loop.yaml", path("loop.yaml"));
  const std::string o = path("o.yml");
  const std::vector<std::pair<Result, std::string>> cases{
      {run({"extract", "--descriptor", "brief", path("folder.png"), "-o", o}), path("folder.png") + ": is a folder"},
      {run({"match", path("fifo.yml"), path("a.yml"), "-o", o}), path("fifo.yml") + ": is a FIFO"},
      {run({"match", path("a.yml"), path("folder.png"), "-o", o}), path("folder.png") + ": is a folder"},
      {run({"extract", "--descriptor", "brief", "--keypoints", path("fifo.yml"), image, "-o", o}),
       path("fifo.yml") + ": is a FIFO"},
      {run({"extract", "--camera", path("loop.yaml"), image, "-o", o}),
       path("loop.yaml") + ": too many levels of symbolic links"},
  };
  for (const auto& [r, message] : cases) {
    expectOneLineNaming(r, message);
    EXPECT_EQ(r.err.find("no such file"), std::string::npos) << r.err;
  }
}

// OpenCV logged "[ERROR:0@0.035] ... Can't open file: '/proc/.o.tmp<pid>-0.yml' in write mode"
// before the tool's message, naming the temporary file. /proc takes no new file, even from root.
TEST_F(CliTest, OpenCvLogsNothingBeforeTheToolsMessage) {
  REQUIRE_IMAGE(image, "view.png");
  if (!fs::is_directory("/proc/self")) GTEST_SKIP() << "no /proc";
  ::unsetenv("OPENCV_LOG_LEVEL");
  for (const std::string& out : std::vector<std::string>{"/proc/o.yml", "/proc/o.yml.gz"}) {
    const Result r = run({"extract", "--camera", kCamera, image, "-o", out});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("mdbrief: " + out + ": ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

// --conformal without a camera was ignored: the output was byte-identical to a run without it.
TEST_F(CliTest, ConformalWithoutACameraIsRefused) {
  REQUIRE_IMAGE(image, "view.png");
  for (const char* command : {"extract", "draw"}) {
    const std::string out = path(std::string(command) == "draw" ? "o.png" : "o.yml");
    expectOneLineNaming(run({command, "--descriptor", "brief", "--conformal", image, "-o", out}), "--conformal");
    EXPECT_FALSE(fs::exists(out));
  }
}

// A camera that leaves almost nothing describable gave 0 keypoints and exit 0 with no word: the
// run still succeeds, with a warning naming the calibration. A usable camera gives none.
TEST_F(CliTest, CameraWithAlmostNoDescribableAreaIsWarnedAbout) {
  REQUIRE_IMAGE(image, "view.png");
  const Result usable = run({"extract", "--camera", kCamera, image, "-o", path("o.yml")});
  ASSERT_EQ(usable.code, 0) << usable.err;
  EXPECT_EQ(usable.err.find("warning"), std::string::npos) << usable.err;
  // Every pixel of a 1e-9 px focal length is at 90 degrees from the axis: nothing for dBRIEF.
  std::ofstream(path("tiny_focal.yaml")) << "model: pinhole\nwidth: 754\nheight: 480\nfx: 1e-9\nfy: 1e-9\n"
                                            "cx: 377\ncy: 240\n";
  // An image circle of 20 pixels, about 0.3 % of the image.
  std::ifstream camIn(kCamera);
  std::string cam((std::istreambuf_iterator<char>(camIn)), std::istreambuf_iterator<char>());
  cam.replace(cam.find("valid_radius: "), 14, "valid_radius: 20 #");
  std::ofstream(path("tiny_circle.yaml")) << cam;
  for (const std::string& camera : {path("tiny_focal.yaml"), path("tiny_circle.yaml")}) {
    const Result r = run({"extract", "--camera", camera, image, "-o", path("o.yml")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("warning: " + camera + ": keypoints can be described on 0."), std::string::npos) << r.err;
  }
  // The incidence bound is the run's own (--max-incidence-deg), not the default's.
  const Result narrow = run({"extract", "--camera", kCamera, "--max-incidence-deg", "5", image, "-o", path("o.yml")});
  EXPECT_EQ(narrow.code, 0) << narrow.err;
  EXPECT_NE(narrow.err.find("warning: " + kCamera + ": keypoints can be described on "), std::string::npos)
      << narrow.err;
  EXPECT_NE(narrow.err.find("rays within 5 degrees of the optical axis"), std::string::npos) << narrow.err;
  // BRIEF does not use the model: the pinhole's whole image is describable.
  const Result brief = run({"extract", "--descriptor", "brief", "--camera", path("tiny_focal.yaml"), image, "-o",
                            path("o.yml")});
  EXPECT_EQ(brief.code, 0) << brief.err;
  EXPECT_EQ(brief.err.find("warning"), std::string::npos) << brief.err;
}

// Descriptors of no bytes matched every pair at distance 0 (exit 0); a file of no descriptors
// (an image without keypoints) stays valid.
TEST_F(CliTest, MatchRefusesDescriptorsOfNoBytes) {
  for (const char* name : {"none.yml", "none.xml", "none.yml.gz"}) {
    {
      cv::FileStorage storage(path(name), cv::FileStorage::WRITE);
      storage << "descriptors" << cv::Mat(5, 0, CV_8UC1);
    }
    expectOneLineNaming(run({"match", path(name), path(name), "-o", path("m.yml")}), "got 5 x 0");
  }
  EXPECT_FALSE(fs::exists(path("m.yml")));
  {
    cv::FileStorage storage(path("empty.yml"), cv::FileStorage::WRITE);
    storage << "descriptors" << cv::Mat();
  }
  EXPECT_EQ(run({"match", path("empty.yml"), path("empty.yml"), "-o", path("m.yml")}).code, 0);
}

// Issue 45: float descriptors were refused as "got 1000 x 32", which does not say what is wrong
// with them: a message about a descriptor matrix names its type and the one expected.
TEST_F(CliTest, DescriptorMatricesOfAnotherTypeAreNamedByType) {
  for (const auto& [type, name] : {std::pair<int, std::string>{CV_32F, "CV_32F"}, {CV_16U, "CV_16U"}}) {
    {
      cv::FileStorage storage(path("f.yml"), cv::FileStorage::WRITE);
      storage << "descriptors" << cv::Mat(7, 32, type, cv::Scalar(1));
    }
    const Result r = run({"match", path("f.yml"), path("f.yml"), "-o", path("m.yml")});
    expectOneLineNaming(r, "got 7 x 32 " + name);
    EXPECT_NE(r.err.find("CV_8U"), std::string::npos) << r.err;
  }
  {
    cv::FileStorage storage(path("masks.yml"), cv::FileStorage::WRITE);
    storage << "descriptors" << cv::Mat(7, 32, CV_8UC1, cv::Scalar(1)) << "masks" << cv::Mat(7, 32, CV_32F, cv::Scalar(1));
  }
  expectOneLineNaming(run({"match", path("masks.yml"), path("masks.yml"), "-o", path("m.yml")}), "got 7 x 32 CV_32F");
  EXPECT_FALSE(fs::exists(path("m.yml")));
}

// Issue 29: `match a.yml b.yml -o a.yml`, `draw pic.png -o pic.png`, `extract --camera kb.yaml
// ... -o kb.yaml` and `camera convert chain.yaml -o chain.yaml` replaced their input with exit 0.
// An output that is an input under any name (itself, a symbolic or a hard link) is refused with
// exit 2, and the input keeps its bytes.
TEST_F(CliTest, AnOutputThatIsAnInputIsRefusedAndTheInputKept) {
  cv::Mat pixels(120, 160, CV_8UC1);
  cv::randu(pixels, 0, 256);
  ASSERT_TRUE(cv::imwrite(path("pic.png"), pixels));
  cli::Features features;
  features.descriptors = cv::Mat(3, 32, CV_8UC1, cv::Scalar(7));
  cli::writeFeatureFiles({path("a.yml"), path("b.yml")}, {features, features});
  fs::copy_file(kCamera, path("kb.yaml"));
  fs::create_symlink(path("a.yml"), path("link.yml"));
  fs::create_hard_link(path("kb.yaml"), path("hard.yaml"));
  std::map<std::string, std::string> before;
  for (const char* name : {"pic.png", "a.yml", "b.yml", "kb.yaml"}) before[name] = testing::readFile(path(name));
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"match", path("a.yml"), path("b.yml"), "-o", path("a.yml")}, path("a.yml")},
      {{"match", path("a.yml"), path("b.yml"), "-o", path("link.yml")}, path("a.yml")},
      {{"draw", "--descriptor", "brief", path("pic.png"), "-o", path("pic.png")}, path("pic.png")},
      {{"extract", "--camera", path("kb.yaml"), "--allow-size-mismatch", path("pic.png"), "-o", path("hard.yaml")},
       path("kb.yaml")},
      {{"extract", "--descriptor", "brief", path("pic.png"), "--keypoints", path("a.yml"), "-o", path("a.yml")},
       path("a.yml")},
      {{"camera", "convert", path("kb.yaml"), "-o", path("kb.yaml")}, path("kb.yaml")},
      {{"camera", "convert", path("hard.yaml"), "-o", path("kb.yaml")}, path("hard.yaml")},
  };
  for (const auto& [args, input] : cases) {
    const Result r = run(args);
    expectOneLineNaming(r, "the output is the same file as the input " + input);
  }
  for (const auto& [name, bytes] : before) EXPECT_EQ(testing::readFile(path(name)), bytes) << name;
}

// Issue 29: `extract m1.jpg m5.jpg text.png -o DIR` wrote two outputs, then failed on the third.
// Every image is read before any output is written.
TEST_F(CliTest, ExtractWritesNoOutputWhenAnyImageIsBad) {
  cv::Mat pixels(120, 160, CV_8UC1);
  cv::randu(pixels, 0, 256);
  ASSERT_TRUE(cv::imwrite(path("a.png"), pixels));
  ASSERT_TRUE(cv::imwrite(path("b.png"), pixels));
  std::ofstream(path("text.png")) << "not an image";
  fs::create_directories(path("out"));
  const Result r = run({"extract", "--descriptor", "brief", path("a.png"), path("b.png"), path("text.png"), "-o",
                        path("out")});
  expectOneLineNaming(r, path("text.png"));
  EXPECT_TRUE(fs::is_empty(path("out")));
  ASSERT_EQ(run({"extract", "--descriptor", "brief", path("a.png"), path("b.png"), "-o", path("out")}).code, 0);
  EXPECT_TRUE(fs::exists(path("out/a.yml")));
  EXPECT_TRUE(fs::exists(path("out/b.yml")));
}

// Issue 29: --allow-size-mismatch stretched a calibration anisotropically (480x752 against
// 752x480) without a word. Another aspect ratio is warned about, with both factors; a uniform
// rescale is not.
TEST_F(CliTest, AllowSizeMismatchWarnsAboutAnotherAspectRatio) {
  const cv::Size size = loadCamera(kCamera)->imageSize();
  cv::Mat rotated(size.width, size.height, CV_8UC1), half(size.height / 2, size.width / 2, CV_8UC1);
  cv::randu(rotated, 0, 256);
  cv::randu(half, 0, 256);
  ASSERT_TRUE(cv::imwrite(path("rotated.png"), rotated));
  ASSERT_TRUE(cv::imwrite(path("half.png"), half));
  const Result r = run({"extract", "--camera", kCamera, "--allow-size-mismatch", path("rotated.png"), "-o",
                        path("r.yml")});
  EXPECT_EQ(r.code, 0) << r.err;
  const double across = double(size.height) / size.width, down = double(size.width) / size.height;
  std::ostringstream factors;
  factors << "stretches it by " << across << " across and " << down << " down";
  EXPECT_NE(r.err.find("warning: " + path("rotated.png") + ": image size " + std::to_string(size.height) + "x" +
                       std::to_string(size.width) + " has another aspect ratio than the calibration"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(factors.str()), std::string::npos) << r.err;
  const Result ok = run({"extract", "--camera", kCamera, "--allow-size-mismatch", path("half.png"), "-o",
                         path("h.yml")});
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("aspect ratio"), std::string::npos) << ok.err;
}

const std::vector<uchar> kStartOfScan{0xFF, 0xDA};

// A PNG chunk: length, type, data and the CRC-32 of type and data.
std::string pngChunk(const std::string& type, const std::string& data) {
  const auto bigEndian = [](uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  uint32_t crc = 0xFFFFFFFFu;
  for (const char c : type + data) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return bigEndian(static_cast<uint32_t>(data.size())) + type + data + bigEndian(~crc);
}

// Issue 29: a 60000x60000 PNG was "unsupported format or truncated", and a PNG cut in half was
// warned about as "describing the decodable part" before "cannot decode". One message each.
TEST_F(CliTest, ImagesThatDoNotDecodeSayWhy) {
  const std::string side = std::string{0, 0, char(0xEA), 0x60};  // 60000
  const std::string header = side + side + std::string{8, 0, 0, 0, 0};
  std::ofstream(path("huge.png"), std::ios::binary)
      << "\x89PNG\r\n\x1a\n" + pngChunk("IHDR", header) + pngChunk("IDAT", "") + pngChunk("IEND", "");
  expectOneLineNaming(run({"extract", "--descriptor", "brief", path("huge.png"), "-o", path("h.yml")}),
                      path("huge.png") + ": cannot decode the image: 60000x60000 = 3600000000 pixels, over the "
                                         "1073741824 OpenCV decodes (CV_IO_MAX_IMAGE_PIXELS)");
  cv::Mat pixels(200, 200, CV_8UC1);
  cv::randu(pixels, 0, 256);
  std::vector<uchar> png;
  ASSERT_TRUE(cv::imencode(".png", pixels, png));
  std::ofstream(path("half.png"), std::ios::binary).write(reinterpret_cast<const char*>(png.data()), 60);
  const Result r = run({"extract", "--descriptor", "brief", path("half.png"), "-o", path("h.yml")});
  expectOneLineNaming(r, path("half.png") + ": cannot decode the image: truncated PNG (no IEND chunk)\n");
  EXPECT_EQ(r.err.find("describing the decodable part"), std::string::npos) << r.err;
}

// Issue 29: match could not tell files of two test sets apart, nor that --inliers --camera named
// another lens than the one that described them. Feature files record both; match refuses a
// mismatch and still reads files without the record.
TEST_F(CliTest, MatchRefusesFilesOfAnotherComparisonSetOrLens) {
  REQUIRE_IMAGE(image, "view.png");
  ASSERT_EQ(run({"extract", "--camera", kCamera, image, "-o", path("a.yml")}).code, 0);
  ASSERT_EQ(run({"extract", "--camera", kCamera, "--pattern", "brief_random_512", image, "-o", path("r.yml")}).code,
            0);
  const FeatureFile a = readFeatures(path("a.yml"));
  cv::FileStorage recorded(path("a.yml"), cv::FileStorage::READ);
  EXPECT_EQ(recorded["test_set_digest"].string().size(), 16u);
  EXPECT_EQ(recorded["camera_digest"].string(), cli::cameraDigest(*loadCamera(kCamera)));
  expectOneLineNaming(run({"match", path("a.yml"), path("r.yml"), "-o", path("m.yml")}),
                      "described with different test sets (");
  const std::string pinhole = (testing::sourceDir() / "configs/cameras/pinhole_example.yaml").string();
  expectOneLineNaming(run({"match", path("a.yml"), path("a.yml"), "--inliers", "--camera", pinhole, "-o", path("m.yml")}),
                      "--camera " + pinhole + ": not the calibration " + path("a.yml") + " was described with");
  EXPECT_FALSE(fs::exists(path("m.yml")));
  const Result same = run({"match", path("a.yml"), path("a.yml"), "--inliers", "--camera", kCamera, "-o", path("m.yml")});
  EXPECT_EQ(same.code, 0) << same.err;
  // A file without the record (written before it) matches as before.
  cli::Features old;
  old.keypoints = a.keypoints;
  old.descriptors = a.descriptors;
  old.masks = a.masks;
  cli::writeFeatureFiles({path("old.yml")}, {old});
  const Result older = run({"match", path("old.yml"), path("r.yml"), "--inliers", "--camera", pinhole, "-o",
                            path("m.yml")});
  EXPECT_NE(older.err.find("not the calibration " + path("r.yml")), std::string::npos) << older.err;
  EXPECT_EQ(run({"match", path("old.yml"), path("a.yml"), "--inliers", "--camera", kCamera, "-o", path("m.yml")}).code,
            0);
}

// Issue 29: --strict passed a complete JPEG with flipped bits (half the keypoints, exit 0), with
// only libjpeg's unnamed "Corrupt JPEG data" line. libjpeg's warnings name the file; --strict
// refuses it.
TEST_F(CliTest, AJpegWithDamagedDataIsNamedAndRefusedUnderStrict) {
  cv::Mat pixels(240, 320, CV_8UC1);
  cv::RNG(29).fill(pixels, cv::RNG::UNIFORM, 0, 256);
  std::vector<uchar> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", pixels, jpeg));
  ASSERT_TRUE(cv::imwrite(path("intact.jpg"), pixels));
  // Flipped bits in the middle of the entropy-coded data; no marker (0xFF and the byte after it)
  // is made or changed.
  const size_t scan = std::search(jpeg.begin(), jpeg.end(), kStartOfScan.begin(), kStartOfScan.end()) - jpeg.begin();
  for (size_t i = scan + (jpeg.size() - scan) / 2, end = i + 64; i < end; i += 4)
    if (jpeg[i] != 0xFF && jpeg[i - 1] != 0xFF && (jpeg[i] ^ 0x5A) != 0xFF) jpeg[i] ^= 0x5A;
  std::ofstream(path("flipped.jpg"), std::ios::binary).write(reinterpret_cast<const char*>(jpeg.data()),
                                                             static_cast<std::streamsize>(jpeg.size()));
  expectOneLineNaming(run({"extract", "--descriptor", "brief", "--strict", path("flipped.jpg"), "-o", path("f.yml")}),
                      path("flipped.jpg") + ": damaged JPEG: Corrupt JPEG data");
  EXPECT_FALSE(fs::exists(path("f.yml")));
  const Result lenient = run({"extract", "--descriptor", "brief", path("flipped.jpg"), "-o", path("f.yml")});
  EXPECT_EQ(lenient.code, 0) << lenient.err;
  EXPECT_NE(lenient.err.find("warning: " + path("flipped.jpg") + ": damaged JPEG: Corrupt JPEG data"),
            std::string::npos)
      << lenient.err;
  const Result intact = run({"extract", "--descriptor", "brief", "--strict", path("intact.jpg"), "-o", path("i.yml")});
  EXPECT_EQ(intact.code, 0) << intact.err;
  EXPECT_EQ(intact.err, "");
}

}  // namespace
}  // namespace mdbrief
