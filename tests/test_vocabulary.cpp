// The vocabulary at run time: words by descent with the masked or the plain distance, the
// BowVector's weighting, the direct index, and the checks of a tree and of the input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "mdbrief/match/masked_hamming.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "mdbrief/recognition/vocabulary.hpp"
#include "vocabulary_trees.hpp"

using namespace mdbrief;
using mdbrief::testing::randomTree;
using mdbrief::testing::referenceWord;
using mdbrief::testing::treeFromParents;

namespace {

cv::Mat rows32(std::initializer_list<uint32_t> values) {
  cv::Mat m(static_cast<int>(values.size()), 4, CV_8UC1);
  int r = 0;
  for (const uint32_t v : values) std::memcpy(m.ptr(r++), &v, 4);
  return m;
}

// Root -> A (all zeros), B (all ones); A -> A1 (0), A2 (0x0000FFFF); B -> B1 (~0), B2 (0xFFFF0000).
VocabularyTree twoLevelTree() {
  return treeFromParents({0, 0, 1, 1, 2, 2},
                         rows32({0, 0u, ~0u, 0u, 0x0000FFFFu, ~0u, 0xFFFF0000u}), {}, 2, 2);
}

}  // namespace

TEST(Vocabulary, PlainDescentReachesTheNearestLeafAndNumbersWordsInNodeOrder) {
  const Vocabulary v = Vocabulary::create(twoLevelTree());
  EXPECT_EQ(v.wordCount(), 4u);
  EXPECT_EQ(v.nodeCount(), 7u);
  EXPECT_FALSE(v.masked());
  // Words: A1 = 0, A2 = 1, B1 = 2, B2 = 3.
  const std::vector<uint32_t> words = v.words(rows32({0x1u, 0x00007FFFu, 0xFFFFFFFEu, 0xFFFF0001u}));
  EXPECT_EQ(words, (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(v.wordNode(0), 3u);
  EXPECT_EQ(v.wordNode(3), 6u);
}

TEST(Vocabulary, TiesGoToTheFirstChild) {
  const Vocabulary v = Vocabulary::create(twoLevelTree());
  // 16 ones: as far from A as from B; then as far from A1 as from A2.
  EXPECT_EQ(v.words(rows32({0x0000FF00u | 0x00FF0000u})), (std::vector<uint32_t>{0}));
}

TEST(Vocabulary, MaskedVocabularyUsesTheMaskedDistanceOnBothSides) {
  // Two words. X differs from d in the 8 bits X's mask distrusts and d's mask distrusts too:
  // plain Hamming prefers Y (4 bits away), the masked distance X (0 trusted bits differ).
  const uint32_t d = 0x000000FFu;
  cv::Mat centroids = rows32({0, 0x00000000u, 0x0F0000FFu});
  cv::Mat masks = rows32({0, 0xFFFFFF00u, 0xFFFFFFFFu});
  const Vocabulary masked = Vocabulary::create(treeFromParents({0, 0}, centroids, masks, 2, 1));
  const Vocabulary plain = Vocabulary::create(treeFromParents({0, 0}, centroids, {}, 2, 1));
  const cv::Mat desc = rows32({d}), descMask = rows32({0xFFFFFF00u});
  EXPECT_EQ(plain.words(desc, descMask), (std::vector<uint32_t>{1})) << "plain ignores the masks";
  EXPECT_EQ(masked.words(desc, descMask), (std::vector<uint32_t>{0}));
  // Without descriptor masks every bit of the descriptor is trusted (ties to the first child).
  const uint32_t fx = maskedHammingFixed(desc.ptr(), rows32({~0u}).ptr(), centroids.ptr(1), masks.ptr(1), 4);
  const uint32_t fy = maskedHammingFixed(desc.ptr(), rows32({~0u}).ptr(), centroids.ptr(2), masks.ptr(2), 4);
  EXPECT_EQ(masked.words(desc), (std::vector<uint32_t>{fx <= fy ? 0u : 1u}));
}

TEST(Vocabulary, RandomTreesGiveTheReferenceWordsAtEverySimdLevel) {
  for (const bool masked : {false, true})
    for (const int bits : {96, 128, 256, 512}) {  // 96: an odd number of 32-bit words
      const VocabularyTree t = randomTree(5, 3, bits, masked, 7u + static_cast<uint32_t>(bits));
      cv::Mat desc(300, bits / 8, CV_8UC1), masks(300, bits / 8, CV_8UC1);
      cv::randu(desc, 0, 256);
      cv::randu(masks, 0, 256);
      masks.row(0).setTo(0);  // an all-zero mask acts as all ones
      std::vector<uint32_t> expected;
      for (int r = 0; r < desc.rows; ++r)
        expected.push_back(referenceWord(t, desc.ptr(r), masked ? masks.ptr(r) : nullptr));
      const SimdLevel top = supportedSimdLevel();
      for (const SimdLevel level : supportedSimdLevels()) {
        limitSimdLevel(level);
        // Created at this level too: the masks' weights are counted on load, by a kernel per level.
        const Vocabulary v = Vocabulary::create(t);
        EXPECT_EQ(v.words(desc, masks), expected) << "bits " << bits << " masked " << masked << " " << toString(level);
      }
      limitSimdLevel(top);
    }
}

TEST(Vocabulary, BowVectorWeightsCountsByIdfDropsZeroWeightWordsAndSumsToOne) {
  VocabularyTree t = twoLevelTree();
  t.wordWeights = {2.0f, 0.0f, 1.0f, 4.0f};
  const Vocabulary v = Vocabulary::create(t);
  // Words 0, 0, 1, 2: tf-idf 0 -> 2 * 2 = 4, word 1 dropped (weight 0), 2 -> 1; sum 5.
  const BowVector bow = v.bowVector({2, 0, 1, 0});
  ASSERT_EQ(bow.size(), 2u);
  EXPECT_EQ(bow[0].word, 0u);
  EXPECT_FLOAT_EQ(bow[0].value, 0.8f);
  EXPECT_EQ(bow[1].word, 2u);
  EXPECT_FLOAT_EQ(bow[1].value, 0.2f);
  t.weighting = Weighting::Binary;
  const BowVector binary = Vocabulary::create(t).bowVector({2, 0, 1, 0});
  ASSERT_EQ(binary.size(), 2u);
  EXPECT_FLOAT_EQ(binary[0].value, 0.5f);
  EXPECT_THROW(v.bowVector({4}), std::invalid_argument);
  EXPECT_TRUE(v.bowVector({}).empty());
}

TEST(Vocabulary, TransformGroupsFeaturesByTheirNodeAtTheDirectIndexDepth) {
  const Vocabulary v = Vocabulary::create(twoLevelTree());
  const cv::Mat desc = rows32({0xFFFFFFFEu, 0x1u, 0x00007FFFu, 0xFFFF0001u, 0x0u});
  const BowTransform depth1 = v.transform(desc, cv::noArray(), {1});
  EXPECT_EQ(depth1.words, (std::vector<uint32_t>{2, 0, 1, 3, 0}));
  ASSERT_EQ(depth1.direct.size(), 2u);
  EXPECT_EQ(depth1.direct[0].node, 1u);  // A
  EXPECT_EQ(depth1.direct[0].features, (std::vector<int>{1, 2, 4}));
  EXPECT_EQ(depth1.direct[1].node, 2u);  // B
  EXPECT_EQ(depth1.direct[1].features, (std::vector<int>{0, 3}));
  const BowVector expected = v.bowVector(depth1.words);
  ASSERT_EQ(depth1.bow.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(depth1.bow[i].word, expected[i].word);
    EXPECT_EQ(depth1.bow[i].value, expected[i].value);
  }
  // Below the leaves' depth every word is its own entry.
  const BowTransform deep = v.transform(desc, cv::noArray(), {5});
  ASSERT_EQ(deep.direct.size(), 4u);
  EXPECT_EQ(deep.direct[0].node, 3u);
  EXPECT_EQ(deep.direct[0].features, (std::vector<int>{1, 4}));
  EXPECT_THROW(v.transform(desc, cv::noArray(), {0}), std::invalid_argument);
}

TEST(Vocabulary, RefusesDescriptorsOfAnotherWidthAndMasksOfAnotherSize) {
  const Vocabulary v = Vocabulary::create(randomTree(3, 2, 256, true, 1));
  const cv::Mat wide(5, 64, CV_8UC1, cv::Scalar(0));
  try {
    v.words(wide);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("width 64 bytes (512 bits) differs from the vocabulary's 32 bytes (256 bits)"),
              std::string::npos)
        << e.what();
  }
  const cv::Mat desc(5, 32, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(v.words(desc, cv::Mat(4, 32, CV_8UC1)), std::invalid_argument);
  EXPECT_THROW(v.words(desc, cv::Mat(5, 32, CV_16UC1)), std::invalid_argument);
  EXPECT_THROW(v.words(cv::Mat(5, 30, CV_8UC1)), std::invalid_argument);
  EXPECT_TRUE(v.transform(cv::Mat()).words.empty());
}

namespace {

std::string createProblem(const VocabularyTree& t) {
  try {
    Vocabulary::create(t);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Vocabulary, CreateNamesTheRuleATreeBreaks) {
  // A fresh tree each time: copies of a VocabularyTree share their cv::Mat rows.
  EXPECT_EQ(createProblem(twoLevelTree()), "");
  VocabularyTree t = twoLevelTree();
  t.childBegin[1] = 2;  // A's children would be B and A1: B gets two parents
  EXPECT_NE(createProblem(t).find("node 2 is the child of two nodes"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.depth = 1;
  EXPECT_NE(createProblem(t).find("deeper than the depth 1"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.branching = 1;
  EXPECT_NE(createProblem(t).find("branching 1"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.wordWeights[2] = std::nanf("");
  EXPECT_NE(createProblem(t).find("word 2 has weight"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.wordWeights.pop_back();
  EXPECT_NE(createProblem(t).find("3 weights for 4 words"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.centroids.at<uint8_t>(0, 0) = 1;
  EXPECT_NE(createProblem(t).find("root carries a centroid"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.masked = true;
  t.masks = cv::Mat(7, 4, CV_8UC1, cv::Scalar(255));
  t.masks.row(0).setTo(0);
  t.masks.row(4).setTo(0);
  EXPECT_NE(createProblem(t).find("node 4 has an empty mask"), std::string::npos) << createProblem(t);
  t = twoLevelTree();
  t.bits = 40;
  EXPECT_NE(createProblem(t).find("bits must be 32..512"), std::string::npos) << createProblem(t);
}
