// Evidence that the shipped learned set is better than the random BRIEF set on images it was
// not trained on (Oxford affine when present, else opencv-doc): higher mean bit variance,
// lower mean pairwise correlation, and better matching on graf 1->2 and 1->3 with the same
// keypoints (recall at fixed precision).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "mdbrief/descriptor.hpp"
#include "mdbrief/hamming.hpp"
#include "mdbrief/patterns.hpp"
#include "patchextract/patch_extraction.hpp"
#include "test_data.hpp"
#include "trainer/trainer.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using namespace mdbrief::train;

namespace {

constexpr int kBits = 256;
constexpr const char* kLearned = "orb_perspective_512";
constexpr const char* kRandom = "brief_random_512";
// Matching is compared at this precision (graf 1->3 has almost no matches above it).
constexpr double kPrecision = 0.8;

std::optional<fs::path> heldApartFolder() {
  if (const auto shared = mdbrief::testing::sharedDataDir(); shared && fs::is_directory(*shared / "oxford-affine"))
    return *shared / "oxford-affine";
  return std::nullopt;
}

std::optional<fs::path> grafFolder() {
  if (const auto held = heldApartFolder(); held && fs::exists(*held / "graf" / "img1.png")) return *held / "graf";
  return std::nullopt;
}

cv::Mat readHomography(const fs::path& path) {
  std::ifstream f(path);
  cv::Mat H(3, 3, CV_64F);
  for (int i = 0; i < 9; ++i) f >> H.at<double>(i / 3, i % 3);
  return f ? H : cv::Mat();
}

// Recall of nearest-neighbour matching at the loosest Hamming threshold whose precision is still
// >= minPrecision. A match is correct when it lands within 3 px of H p; recall counts the
// keypoints with some img2 keypoint there.
double recallAtPrecision(const cv::Mat& img1, const cv::Mat& img2, const cv::Mat& H,
                         const std::string& pattern, double minPrecision) {
  auto orb = cv::ORB::create(1000);
  std::vector<cv::KeyPoint> k1, k2;
  orb->detect(img1, k1);
  orb->detect(img2, k2);
  DescriptorOptions o;
  o.kind = DescriptorKind::Brief;
  o.bits = kBits;
  o.pattern = pattern;
  const DescriptorExtractor extractor(nullptr, o);
  cv::Mat d1, d2;
  extractor.compute(img1, k1, d1);
  extractor.compute(img2, k2, d2);
  std::vector<cv::Point2f> p1, mapped;
  for (const auto& k : k1) p1.push_back(k.pt);
  cv::perspectiveTransform(p1, mapped, H);
  struct Match { int distance; bool correct; };
  std::vector<Match> matches;
  int positives = 0;
  for (size_t i = 0; i < k1.size(); ++i) {
    bool hasPartner = false;
    for (const auto& k : k2) hasPartner = hasPartner || cv::norm(k.pt - mapped[i]) < 3.0;
    positives += hasPartner;
    int nn = 0, nnDist = 1 << 30;
    for (int j = 0; j < d2.rows; ++j) {
      const int d = hammingDistance(d1.ptr<uint8_t>(int(i)), d2.ptr<uint8_t>(j), d1.cols);
      if (d < nnDist) nnDist = d, nn = j;
    }
    matches.push_back({nnDist, cv::norm(k2[nn].pt - mapped[i]) < 3.0});
  }
  std::sort(matches.begin(), matches.end(), [](const Match& a, const Match& b) { return a.distance < b.distance; });
  double bestRecall = 0;
  int correct = 0;
  for (size_t n = 0; n < matches.size(); ++n) {
    correct += matches[n].correct;
    const bool thresholdEnds = n + 1 == matches.size() || matches[n + 1].distance != matches[n].distance;
    if (thresholdEnds && double(correct) / (n + 1) >= minPrecision)
      bestRecall = std::max(bestRecall, double(correct) / std::max(positives, 1));
  }
  return bestRecall;
}

}  // namespace

TEST(LearnedSet, HigherVarianceAndLowerCorrelationThanRandomOnHeldApartImages) {
  const auto held = heldApartFolder();
  if (!held) GTEST_SKIP() << "../shared/data/oxford-affine not found (set MDBRIEF_DATA)";
  ExtractionOptions o;
  o.imageDirs = {*held};
  o.patches = 5000;
  ExtractionReport report;
  const PatchSet patches = extractPatches(o, report);
  ASSERT_GT(patches.count(), 2000u);
  const PatchMatrix m{patches.pixels.data(), patches.count()};
  const TestSetQuality learned = measureTestSet(m, builtinTestSet(kLearned).first(kBits).tests);
  const TestSetQuality random = measureTestSet(m, builtinTestSet(kRandom).first(kBits).tests);
  RecordProperty("learned_variance", std::to_string(learned.meanVariance));
  RecordProperty("random_variance", std::to_string(random.meanVariance));
  RecordProperty("learned_correlation", std::to_string(learned.meanCorrelation));
  RecordProperty("random_correlation", std::to_string(random.meanCorrelation));
  EXPECT_GT(learned.meanVariance, random.meanVariance);
  EXPECT_LT(learned.meanCorrelation, random.meanCorrelation);
}

TEST(LearnedSet, BetterGrafMatchingThanRandomWithTheSameKeypoints) {
  const auto graf = grafFolder();
  if (!graf) GTEST_SKIP() << "../shared/data/oxford-affine/graf not found (set MDBRIEF_DATA)";
  const cv::Mat img1 = cv::imread((*graf / "img1.png").string(), cv::IMREAD_GRAYSCALE);
  for (const char* pair : {"2", "3"}) {
    const cv::Mat img2 = cv::imread((*graf / (std::string("img") + pair + ".png")).string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat H = readHomography(*graf / (std::string("H1to") + pair + "p"));
    ASSERT_FALSE(img1.empty() || img2.empty() || H.empty());
    const double learned = recallAtPrecision(img1, img2, H, kLearned, kPrecision);
    const double random = recallAtPrecision(img1, img2, H, kRandom, kPrecision);
    RecordProperty(std::string("recall_learned_1to") + pair, std::to_string(learned));
    RecordProperty(std::string("recall_random_1to") + pair, std::to_string(random));
    EXPECT_GT(learned, random) << "graf 1->" << pair;
  }
}
