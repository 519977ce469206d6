// `mdbrief match --refine` (cli/command_match.cpp): on an image and a copy of it shifted by a
// known fraction of a pixel, the refined points of B lie nearer the shift than B's keypoints;
// missing, swapped or unrecorded inputs are refused with exit 2 before any output is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli_runner.hpp"
#include "test_data.hpp"

namespace mdbrief {
namespace {

namespace fs = std::filesystem;
using Result = testing::CliResult;
using testing::expectOneLineNaming;

Result run(std::vector<std::string> args) { return testing::runMdbrief(std::move(args)); }

const std::string kPinhole = (testing::sourceDir() / "configs/cameras/pinhole_example.yaml").string();
const std::string kFisheye = (testing::sourceDir() / "configs/cameras/lafida_fisheye0.yaml").string();

// Where A's content lies in B: B is A's scene moved by this many pixels.
const cv::Point2d kShift(-1.25, 0.75);

// A smooth random texture at 4 times the pinhole's 754x480, and two windows of it 5 and -3 fine
// pixels apart, each averaged down to 754x480 by INTER_AREA (the same box filter for both): B's
// pixel x shows what A's pixel x - kShift shows, exactly.
void writeShiftedPair(const fs::path& a, const fs::path& b) {
  cv::Mat noise(520, 800, CV_32F), sum = cv::Mat::zeros(520, 800, CV_32F), blurred;
  cv::RNG rng(11);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 1.0);
  for (const double sigma : {1.5, 3.0, 6.0}) {
    cv::GaussianBlur(noise, blurred, cv::Size(), sigma);
    cv::normalize(blurred, blurred, 0, 1, cv::NORM_MINMAX);
    sum += blurred;
  }
  cv::normalize(sum, sum, 0, 255, cv::NORM_MINMAX);
  cv::Mat fine;
  cv::resize(sum, fine, cv::Size(), 4, 4, cv::INTER_CUBIC);
  const auto window = [&](int dx, int dy) {
    cv::Mat out, bytes;
    cv::resize(fine(cv::Rect(80 + dx, 80 + dy, 754 * 4, 480 * 4)), out, cv::Size(754, 480), 0, 0, cv::INTER_AREA);
    out.convertTo(bytes, CV_8U);
    return bytes;
  };
  ASSERT_TRUE(cv::imwrite(a.string(), window(0, 0)));
  ASSERT_TRUE(cv::imwrite(b.string(), window(5, -3)));
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

class CliRefine : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("mdbrief_test_cli_refine_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "features");
    writeShiftedPair(dir_ / "a.png", dir_ / "b.png");
    ASSERT_EQ(run({"extract", "--camera", kPinhole, path("a.png"), path("b.png"), "-o", path("features")}).code, 0);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // match A B --refine with both images and the pinhole, then `extra`.
  Result refine(std::vector<std::string> extra, const std::string& output = "m.yml") const {
    std::vector<std::string> args = {"match", path("features/a.yml"), path("features/b.yml"), "--refine",
                                     "--camera", kPinhole, "--image-a", path("a.png"), "--image-b", path("b.png"),
                                     "-o", path(output)};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }

  fs::path dir_;
};

TEST_F(CliRefine, RefinedPointsOfBLieNearerTheKnownShiftThanItsKeypoints) {
  for (const std::string output : {"m.yml", "m.json"}) {  // JSON holds no infinity: a failure's sigma is -1
    // --inliers counts on the refined points: a pure translation, which the essential matrix
    // explains.
    const bool inliers = output == "m.json";
    const Result r = refine(inliers ? std::vector<std::string>{"--inliers"} : std::vector<std::string>{}, output);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto countBefore = [&](const std::string& word) {
      const std::size_t at = r.out.rfind(' ', r.out.find(word) - 1);
      return std::stoi(r.out.substr(at + 1));
    };
    ASSERT_NE(r.out.find(" refined"), std::string::npos) << r.out;
    if (inliers) EXPECT_GT(countBefore(" inliers ("), 0.9 * countBefore(" masked matches")) << r.out;
    cv::FileStorage file(path(output), cv::FileStorage::READ);
    cv::Mat matches, refined;
    file["matches"] >> matches;
    file["refined"] >> refined;
    ASSERT_EQ(refined.rows, matches.rows);
    ASSERT_EQ(refined.cols, 5);
    ASSERT_EQ(refined.type(), CV_64F);
    cv::FileStorage fa(path("features/a.yml"), cv::FileStorage::READ), fb(path("features/b.yml"), cv::FileStorage::READ);
    std::vector<cv::KeyPoint> ka, kb;
    cv::read(fa["keypoints"], ka);
    cv::read(fb["keypoints"], kb);
    std::vector<double> before, after;
    int right = 0, ok = 0;
    for (int i = 0; i < matches.rows; ++i) {
      const cv::KeyPoint& a = ka.at(static_cast<size_t>(matches.at<double>(i, 0)));
      const cv::KeyPoint& b = kb.at(static_cast<size_t>(matches.at<double>(i, 1)));
      const cv::Point2d truth = cv::Point2d(a.pt) + kShift;
      const double* row = refined.ptr<double>(i);
      if (cv::norm(cv::Point2d(b.pt) - truth) > 3.0) continue;
      ++right;
      if (row[4] != 0) {  // failed: B's keypoint, no sigma, no level
        EXPECT_EQ(cv::Point2d(row[0], row[1]), cv::Point2d(b.pt));
        EXPECT_EQ(row[2], -1.0);
        EXPECT_EQ(row[3], -1.0);
        continue;
      }
      ++ok;
      before.push_back(cv::norm(cv::Point2d(b.pt) - truth));
      after.push_back(cv::norm(cv::Point2d(row[0], row[1]) - truth));
      EXPECT_GT(row[2], 0.0);
      EXPECT_LE(row[3], b.octave);
    }
    ASSERT_GT(right, 200) << output;
    EXPECT_GT(ok, 0.9 * right) << output;
    RecordProperty("median_error_before_px", std::to_string(median(before)));
    RecordProperty("median_error_after_px", std::to_string(median(after)));
    EXPECT_LT(median(after), 0.5 * median(before)) << output;
    EXPECT_LT(median(after), 0.05) << output;
  }
}

TEST_F(CliRefine, MissingOrMismatchedImagesAreRefusedBeforeAnyWork) {
  // Swapped: B's image is not the one A was extracted from.
  Result r = run({"match", path("features/a.yml"), path("features/b.yml"), "--refine", "--camera", kPinhole,
                  "--image-a", path("b.png"), "--image-b", path("a.png"), "-o", path("m.yml")});
  expectOneLineNaming(r, "--image-a " + path("b.png") + ": not the image " + path("features/a.yml"));
  // Missing: refused when the arguments are parsed.
  r = run({"match", path("features/a.yml"), path("features/b.yml"), "--refine", "--camera", kPinhole, "--image-a",
           path("none.png"), "--image-b", path("b.png"), "-o", path("m.yml")});
  expectOneLineNaming(r, path("none.png"));
  expectOneLineNaming(run({"match", path("features/a.yml"), path("features/b.yml"), "--refine", "--camera", kPinhole,
                           "-o", path("m.yml")}),
                      "--refine needs --image-a and --image-b");
  expectOneLineNaming(run({"match", path("features/a.yml"), path("features/b.yml"), "--image-a", path("a.png"), "-o",
                           path("m.yml")}),
                      "used only with --refine");
  expectOneLineNaming(refine({"--refine-patch-radius", "1"}), "--refine-patch-radius must be in [2, 15], got 1");
  expectOneLineNaming(refine({"--refine-smoothing-sigma", "0"}), "--refine-smoothing-sigma must be in (0, 8], got 0");
  // The files were described with the pinhole: refining without it, or with another lens, would
  // compare other patches.
  expectOneLineNaming(run({"match", path("features/a.yml"), path("features/b.yml"), "--refine", "--image-a",
                           path("a.png"), "--image-b", path("b.png"), "-o", path("m.yml")}),
                      "--refine needs it, give it with --camera");
  expectOneLineNaming(run({"match", path("features/a.yml"), path("features/b.yml"), "--refine", "--camera", kFisheye,
                           "--image-a", path("a.png"), "--image-b", path("b.png"), "-o", path("m.yml")}),
                      "--camera " + kFisheye + ": not the calibration");
  EXPECT_FALSE(fs::exists(path("m.yml")));
}

TEST_F(CliRefine, FilesThatDoNotRecordThePyramidAreRefused) {
  // A file as extract wrote it before the pyramid and image were recorded, and one whose pyramid
  // options are out of range or not numbers.
  cv::FileStorage in(path("features/a.yml"), cv::FileStorage::READ);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors, masks;
  cv::read(in["keypoints"], keypoints);
  in["descriptors"] >> descriptors;
  in["masks"] >> masks;
  const std::string digest = in["image_digest"].string(), size = in["image_size"].string();
  const auto write = [&](const std::string& name, const std::string& pyramid) {
    cv::FileStorage out(path(name), cv::FileStorage::WRITE);
    cv::write(out, "keypoints", keypoints);
    out << "descriptors" << descriptors << "masks" << masks;
    if (!pyramid.empty()) out << "pyramid" << pyramid << "image_size" << size << "image_digest" << digest;
  };
  const auto refineA = [&](const std::string& name) {
    return run({"match", path(name), path("features/b.yml"), "--refine", "--camera", kPinhole, "--image-a",
                path("a.png"), "--image-b", path("b.png"), "-o", path("m.yml")});
  };
  write("old.yml", "");
  expectOneLineNaming(refineA("old.yml"), path("old.yml") + ": --refine needs the pyramid options");
  write("levels.yml", "levels=99 scale_factor=1.2");
  expectOneLineNaming(refineA("levels.yml"), "node 'pyramid': levels must be in [1, 32], got 99");
  write("word.yml", "levels=8 scale_factor=x1.2");
  expectOneLineNaming(refineA("word.yml"), "scale_factor must be a number, got 'x1.2'");
  write("key.yml", "levels=8 octaves=3");
  expectOneLineNaming(refineA("key.yml"), "'octaves=3' is no pyramid option");
  // A keypoint whose octave is no level of the pyramid: the file says 2 levels.
  write("two.yml", "levels=2");
  expectOneLineNaming(refineA("two.yml"), path("two.yml") + ": keypoints[");
  EXPECT_FALSE(fs::exists(path("m.yml")));
}

}  // namespace
}  // namespace mdbrief
