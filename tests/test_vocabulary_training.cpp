// Training vocabularies: k-majority finds known clusters, votes only where a member's mask
// trusts a bit and keeps the bits the members agree on; the hierarchy gives one word per known
// group with the expected idf, and the same seed gives the same bytes whatever the threads.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <tbb/task_arena.h>

#include "vocabulary/kmajority.hpp"
#include "vocabulary/vocabulary_training.hpp"

using namespace mdbrief;
using namespace mdbrief::vocab;

namespace {

// `per` copies of each center (32-bit rows), each with one bit flipped (a different one per copy).
cv::Mat noisyGroups(const std::vector<uint32_t>& centers, int per, std::vector<int>* group = nullptr) {
  cv::Mat m(static_cast<int>(centers.size()) * per, 4, CV_8UC1);
  int r = 0;
  for (size_t g = 0; g < centers.size(); ++g)
    for (int i = 0; i < per; ++i) {
      const uint32_t v = centers[g] ^ (1u << ((i * 7 + static_cast<int>(g)) % 32));
      std::memcpy(m.ptr(r++), &v, 4);
      if (group) group->push_back(static_cast<int>(g));
    }
  return m;
}

uint32_t row32(const cv::Mat& m, int r) {
  uint32_t v;
  std::memcpy(&v, m.ptr(r), 4);
  return v;
}

}  // namespace

TEST(KMajority, FindsSeparatedGroupsWithTheirCentersAsMajorityCentroids) {
  const std::vector<uint32_t> centers{0x00000000u, 0xFFFF0000u, 0x0000FFFFu};
  std::vector<int> group;
  const cv::Mat desc = noisyGroups(centers, 20, &group);
  KMajorityOptions o;
  o.clusters = 3;
  const KMajorityResult r = kMajority(desc, cv::Mat(), o, 5);
  ASSERT_EQ(r.centroids.rows, 3);
  EXPECT_TRUE(r.masks.empty());
  // Each group is one cluster, whose centroid is the group's center (one flipped bit per member
  // never wins the vote).
  for (size_t g = 0; g < centers.size(); ++g) {
    const int c = r.assignment[g * 20];
    for (int i = 0; i < 20; ++i) EXPECT_EQ(r.assignment[g * 20 + i], c);
    EXPECT_EQ(row32(r.centroids, c), centers[g]);
  }
  EXPECT_GE(r.rounds, 1);
}

TEST(KMajority, GivesFewerClustersThanAskedWhenFewerMembersDiffer) {
  const cv::Mat desc = noisyGroups({0x12345678u}, 1);
  const cv::Mat three = cv::repeat(desc, 3, 1);
  KMajorityOptions o;
  o.clusters = 10;
  const KMajorityResult r = kMajority(three, cv::Mat(), o, 1);
  EXPECT_EQ(r.centroids.rows, 1);
  EXPECT_EQ(r.assignment, (std::vector<int>{0, 0, 0}));
}

TEST(KMajority, VotesOnlyWhereTheMemberTrustsTheBitAndKeepsTheBitsMembersAgreeOn) {
  // Four members, one cluster. Bit 0: all trust it and hold 1. Bit 1: three hold 1 but distrust
  // it, one trusts it and holds 0. Bit 2: all trust it, two hold 1, two 0. Bit 3: three trust
  // it and hold 1, one distrusts it.
  const uint8_t d[4] = {0b1011, 0b1111, 0b1011, 0b0101};
  const uint8_t m[4] = {0b1101, 0b1101, 0b1101, 0b0111};
  cv::Mat desc(4, 4, CV_8UC1, cv::Scalar(0)), masks(4, 4, CV_8UC1, cv::Scalar(0));
  for (int i = 0; i < 4; ++i) {
    desc.at<uint8_t>(i, 0) = d[i];
    masks.at<uint8_t>(i, 0) = m[i];
  }
  KMajorityOptions o;
  o.clusters = 1;
  o.maskAgreement = 0.75;
  const KMajorityResult r = kMajority(desc, masks, o, 3);
  ASSERT_EQ(r.centroids.rows, 1);
  // Bit 0: 1, trusted (4 of 4 agree). Bit 1: only the trusting vote (0) counts: 0, untrusted (1 of
  // 4). Bit 2: a tie gives 0, untrusted (2 of 4). Bit 3: 1, trusted (3 of 4).
  EXPECT_EQ(r.centroids.at<uint8_t>(0, 0) & 0x0F, 0b1001);
  EXPECT_EQ(r.masks.at<uint8_t>(0, 0) & 0x0F, 0b1001);
  // Bits no member trusts (8..31) are 0 and untrusted.
  EXPECT_EQ(r.masks.at<uint8_t>(0, 1), 0);
  // Plain: every member votes on every bit.
  const KMajorityResult plain = kMajority(desc, cv::Mat(), o, 3);
  EXPECT_EQ(plain.centroids.at<uint8_t>(0, 0) & 0x0F, 0b1011);
}

TEST(KMajority, ACentroidWhoseMembersAgreeOnNoBitTrustsEveryBit) {
  cv::Mat desc(2, 4, CV_8UC1), masks(2, 4, CV_8UC1, cv::Scalar(255));
  desc.row(0).setTo(0);
  desc.row(1).setTo(255);
  KMajorityOptions o;
  o.clusters = 1;
  o.maskAgreement = 0.9;
  const KMajorityResult r = kMajority(desc, masks, o, 1);
  EXPECT_EQ(cv::countNonZero(r.masks == 255), 4);
}

TEST(KMajority, TheSameSeedGivesTheSameClusters) {
  cv::Mat desc(500, 32, CV_8UC1), masks(500, 32, CV_8UC1);
  cv::randu(desc, 0, 256);
  cv::randu(masks, 0, 256);
  KMajorityOptions o;
  o.clusters = 8;
  const KMajorityResult a = kMajority(desc, masks, o, 42), b = kMajority(desc, masks, o, 42);
  EXPECT_EQ(a.assignment, b.assignment);
  EXPECT_EQ(cv::norm(a.centroids, b.centroids, cv::NORM_L1), 0.0);
  EXPECT_EQ(cv::norm(a.masks, b.masks, cv::NORM_L1), 0.0);
  EXPECT_THROW(kMajority(cv::Mat(0, 32, CV_8UC1), cv::Mat(), o, 1), std::invalid_argument);
}

namespace {

// Four well separated groups, two per half of the bits; image i holds group i's descriptors and,
// for i < 2, some of group 3's too.
std::vector<TrainingImage> groupImages(bool masked) {
  const std::vector<uint32_t> centers{0x00000000u, 0x000000FFu, 0xFFFF0000u, 0xFFFFFF00u};
  std::vector<TrainingImage> images;
  for (size_t g = 0; g < centers.size(); ++g) {
    TrainingImage im;
    im.descriptors = noisyGroups({centers[g]}, 12);
    if (g < 2) cv::vconcat(im.descriptors, noisyGroups({centers[3]}, 3), im.descriptors);
    if (masked) im.masks = cv::Mat(im.descriptors.size(), CV_8UC1, cv::Scalar(255));
    im.digest = 100 + g;
    images.push_back(im);
  }
  return images;
}

}  // namespace

TEST(VocabularyTraining, OneWordPerGroupWithIdfFromTheImagesThatReachIt) {
  for (const bool masked : {false, true}) {
    VocabularyTrainingOptions o;
    o.branching = 2;
    o.depth = 2;
    o.masked = masked;
    const std::vector<TrainingImage> images = groupImages(masked);
    const Vocabulary v = trainVocabulary(images, o);
    EXPECT_EQ(v.masked(), masked);
    EXPECT_EQ(v.bits(), 32);
    ASSERT_EQ(v.wordCount(), 4u);
    EXPECT_EQ(v.trainingImages(), (std::vector<uint64_t>{100, 101, 102, 103}));
    // Every group's descriptors reach one word, each group another.
    std::vector<uint32_t> groupWord;
    for (size_t g = 0; g < 4; ++g) {
      const std::vector<uint32_t> w = v.words(images[g].descriptors.rowRange(0, 12));
      for (const uint32_t x : w) EXPECT_EQ(x, w[0]) << "group " << g;
      groupWord.push_back(w[0]);
    }
    std::vector<uint32_t> sorted = groupWord;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, (std::vector<uint32_t>{0, 1, 2, 3}));
    // Groups 0..2 are in one image of four, group 3 in three.
    EXPECT_FLOAT_EQ(v.wordWeight(groupWord[0]), std::log(4.0f));
    EXPECT_FLOAT_EQ(v.wordWeight(groupWord[3]), std::log(4.0f / 3.0f));
  }
}

TEST(VocabularyTraining, TheSameSeedGivesTheSameBytesOnOneThreadOrMany) {
  std::vector<TrainingImage> images(6);
  cv::RNG rng(3);
  for (auto& im : images) {
    im.descriptors.create(400, 32, CV_8UC1);
    im.masks.create(400, 32, CV_8UC1);
    rng.fill(im.descriptors, cv::RNG::UNIFORM, 0, 256);
    rng.fill(im.masks, cv::RNG::UNIFORM, 0, 256);
  }
  VocabularyTrainingOptions o;
  o.branching = 6;
  o.depth = 3;
  const std::string many = trainVocabulary(images, o).fileBytes();
  std::string one;
  tbb::task_arena(1).execute([&] { one = trainVocabulary(images, o).fileBytes(); });
  EXPECT_EQ(one, many);
  o.seed = 2;
  EXPECT_NE(trainVocabulary(images, o).fileBytes(), many);
}

TEST(VocabularyTraining, RefusesMissingMasksMixedWidthsAndNoDescriptors) {
  VocabularyTrainingOptions o;
  std::vector<TrainingImage> images = groupImages(false);
  EXPECT_THROW(trainVocabulary(images, o), std::invalid_argument) << "masked without masks";
  o.masked = false;
  images[1].descriptors = cv::Mat(3, 8, CV_8UC1, cv::Scalar(1));
  EXPECT_THROW(trainVocabulary(images, o), std::invalid_argument);
  EXPECT_THROW(trainVocabulary({TrainingImage{}}, o), std::invalid_argument);
  o.branching = 1;
  EXPECT_THROW(trainVocabulary(groupImages(false), o), std::invalid_argument);
}

// TF and binary weighting have no idf part (DBoW2 sets it to 1): a word that every training
// image holds still counts. Before, they took the idf weights, 0 for such words, so a vocabulary
// trained with --weighting tf gave empty bags of words for images made of common words.
// Issue 45: descriptors of another type were refused without naming it.
TEST(VocabularyTraining, DescriptorsAndMasksOfAnotherTypeAreNamedByTypeAndShape) {
  const auto message = [](const std::vector<TrainingImage>& images, bool masked) -> std::string {
    VocabularyTrainingOptions o;
    o.masked = masked;
    try {
      trainVocabulary(images, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "trained";
  };
  const cv::Mat bytes(7, 32, CV_8UC1, cv::Scalar(1));
  const std::string floats = message({TrainingImage{cv::Mat(7, 32, CV_32F, cv::Scalar(1)), {}, 0}}, false);
  EXPECT_NE(floats.find("image 0: descriptors must be CV_8U"), std::string::npos) << floats;
  EXPECT_NE(floats.find("got 7 x 32 CV_32F"), std::string::npos) << floats;
  const std::string masks = message({TrainingImage{bytes, cv::Mat(7, 32, CV_16U, cv::Scalar(1)), 0}}, true);
  EXPECT_NE(masks.find("got 7 x 32 CV_16U"), std::string::npos) << masks;
}

TEST(VocabularyTraining, TfAndBinaryWeightsAreOneEvenForWordsEveryImageHolds) {
  std::vector<TrainingImage> images(3);
  cv::RNG rng(5);
  for (auto& im : images) {
    im.descriptors.create(200, 32, CV_8UC1);
    rng.fill(im.descriptors, cv::RNG::UNIFORM, 0, 256);
  }
  VocabularyTrainingOptions o;
  o.masked = false;
  o.branching = 3;
  o.depth = 1;
  for (const Weighting w : {Weighting::Tf, Weighting::Binary}) {
    o.weighting = w;
    const Vocabulary v = trainVocabulary(images, o);
    for (uint32_t word = 0; word < v.wordCount(); ++word) EXPECT_EQ(v.wordWeight(word), 1.0f) << toString(w);
    EXPECT_FALSE(v.transform(images[0].descriptors).bow.empty()) << toString(w);
  }
  o.weighting = Weighting::TfIdf;
  const Vocabulary idf = trainVocabulary(images, o);
  for (uint32_t word = 0; word < idf.wordCount(); ++word) EXPECT_EQ(idf.wordWeight(word), 0.0f) << "every image holds it";
}
