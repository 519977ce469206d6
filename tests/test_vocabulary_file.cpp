// The vocabulary's binary file: a round trip keeps every byte, a loaded vocabulary outlives its
// file being replaced or removed, and a missing, truncated, foreign, newer, damaged or
// inconsistent file is refused with its path and the problem.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <limits>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/framed_file.hpp"
#include "mdbrief/base/simd_level.hpp"
#include "mdbrief/recognition/vocabulary.hpp"
#include "test_data.hpp"
#include "vocabulary_trees.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using mdbrief::testing::randomTree;
using mdbrief::testing::readFile;
using mdbrief::testing::TempDir;

namespace {

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// The FileFormatError of loading `bytes` from a file; fails the test when there is none.
std::string loadProblem(const TempDir& dir, const std::string& bytes) {
  const fs::path p = dir.path / "v.mdbvoc";
  writeBytes(p, bytes);
  try {
    Vocabulary::load(p.string());
  } catch (const FileFormatError& e) {
    EXPECT_EQ(e.path(), p.string());
    EXPECT_EQ(std::string(e.what()), p.string() + ": " + e.problem());
    return e.problem();
  }
  ADD_FAILURE() << "loaded";
  return "";
}

template <typename T>
void poke(std::string& bytes, size_t at, T value) {
  std::memcpy(&bytes[at], &value, sizeof value);
}

}  // namespace

TEST(VocabularyFile, SaveLoadKeepsEveryByteAndTheContent) {
  TempDir dir("vocab_file");
  for (const bool masked : {false, true}) {
    VocabularyTree t = randomTree(4, 3, 256, masked, 3);
    t.trainingImages = {9, 3, 3, 5};
    t.weighting = Weighting::Idf;
    const Vocabulary v = Vocabulary::create(t);
    const fs::path p = dir.path / (masked ? "masked.mdbvoc" : "plain.mdbvoc");
    v.save(p.string());
    EXPECT_EQ(readFile(p), v.fileBytes());
    const Vocabulary back = Vocabulary::load(p.string());
    EXPECT_EQ(back.fileBytes(), v.fileBytes());
    EXPECT_EQ(back.fingerprint(), v.fingerprint());
    EXPECT_EQ(back.masked(), masked);
    EXPECT_EQ(back.weighting(), Weighting::Idf);
    EXPECT_EQ(back.trainingImages(), (std::vector<uint64_t>{3, 5, 9})) << "sorted, without repeats";
    EXPECT_EQ(back.wordCount(), 64u);
    VocabularyTree u = back.tree();
    EXPECT_EQ(u.childBegin, t.childBegin);
    EXPECT_EQ(u.childCount, t.childCount);
    EXPECT_EQ(u.wordWeights, t.wordWeights);
    EXPECT_EQ(cv::norm(u.centroids, t.centroids, cv::NORM_L1), 0.0);
    if (masked) {
      EXPECT_EQ(cv::norm(u.masks, t.masks, cv::NORM_L1), 0.0);
    }
    // The same content gives the same bytes; another weight another fingerprint.
    EXPECT_EQ(Vocabulary::create(u).fileBytes(), v.fileBytes());
    u.wordWeights[0] += 1;
    EXPECT_NE(Vocabulary::create(u).fingerprint(), v.fingerprint());
  }
}

TEST(VocabularyFile, RefusesMissingForeignTruncatedNewerAndDamagedFiles) {
  TempDir dir("vocab_bad");
  const std::string good = Vocabulary::create(randomTree(3, 2, 256, true, 5)).fileBytes();
  EXPECT_EQ(loadProblem(dir, good.substr(0, 10)).find("truncated: 10 bytes"), 0u);
  EXPECT_NE(loadProblem(dir, good.substr(0, good.size() - 8)).find("truncated"), std::string::npos);
  EXPECT_NE(loadProblem(dir, good + "x").find("trailing data"), std::string::npos);
  EXPECT_NE(loadProblem(dir, "10 6  0 0\n0 0 1 2 3 4 0\n" + std::string(40, ' ')).find("not a vocabulary file"),
            std::string::npos);
  std::string newer = good;
  poke<uint32_t>(newer, 8, 2);
  EXPECT_NE(loadProblem(dir, newer).find("version 2 is not one this library reads"), std::string::npos);
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(loadProblem(dir, flipped).find("checksum mismatch"), std::string::npos);

  try {
    Vocabulary::load((dir.path / "none.mdbvoc").string());
    ADD_FAILURE() << "loaded";
  } catch (const FileFormatError& e) {
    EXPECT_EQ(e.problem(), "no such file");
  }
  try {
    Vocabulary::load(dir.path.string());
    ADD_FAILURE() << "loaded";
  } catch (const FileFormatError& e) {
    EXPECT_EQ(e.problem(), "is a folder, not a file");
  }
}

TEST(VocabularyFile, RefusesInconsistentContentBehindARightChecksum) {
  TempDir dir("vocab_content");
  const VocabularyTree t = randomTree(3, 2, 256, true, 5);  // 13 nodes, 9 words
  const std::string good = Vocabulary::create(t).fileBytes();
  const auto damaged = [&](size_t at, uint32_t value) {
    std::string b = good;
    poke<uint32_t>(b, at, value);
    internal::repairChecksum(b);
    return loadProblem(dir, b);
  };
  // Header fields (bytes 32..63): bits, flags, branching, depth, weighting, nodes, words, images.
  EXPECT_NE(damaged(32, 100).find("bits 100"), std::string::npos);
  EXPECT_NE(damaged(40, 1).find("branching 1"), std::string::npos);
  EXPECT_NE(damaged(52, 1000000).find("need"), std::string::npos) << "sizes checked against the file's size";
  EXPECT_NE(damaged(52, 0xFFFFFFFFu).find("the file has"), std::string::npos);
  EXPECT_NE(damaged(56, 14).find("words for 13 nodes"), std::string::npos);
  // childBegin of the root (first u32 after the header): its children would start at itself.
  EXPECT_NE(damaged(64, 0).find("node 0: children 0..2"), std::string::npos);
  // childCount of node 1 (at 64 + 13 * 4 rounded to 8 = 120, + 4): 9 children > branching 3.
  EXPECT_NE(damaged(124, 9).find("node 1 has 9 children"), std::string::npos);
  // A leaf's childBegin (node 4 of the 13) set.
  EXPECT_NE(damaged(64 + 4 * 4, 5).find("node 4 is a leaf but its childBegin is 5"), std::string::npos);
}

// The content rules of the load (vocabulary_file.cpp), through a tree: the same checks as a file's.
std::string createProblem(const VocabularyTree& t) {
  try {
    Vocabulary::create(t);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "created";
  return "";
}

TEST(VocabularyFile, RefusesBrokenTreesWeightsAndEmptyMasks) {
  const VocabularyTree good = randomTree(3, 2, 256, true, 5);  // node 0 -> 1..3, 1 -> 4..6, 2 -> 7..9, 3 -> 10..12
  VocabularyTree t = good;
  t.childBegin[2] = 4;
  EXPECT_EQ(createProblem(t), "VocabularyTree: node 4 is the child of two nodes");
  t = good;
  t.childCount[1] = 2;  // node 6 orphaned (still a leaf: the word count holds)
  EXPECT_EQ(createProblem(t), "VocabularyTree: node 6 is no node's child");
  t = good;
  t.depth = 1;
  EXPECT_EQ(createProblem(t), "VocabularyTree: node 1 at depth 1 has children, deeper than the depth 1");
  for (const float bad : {-1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    t = good;
    t.wordWeights[3] = bad;
    EXPECT_EQ(createProblem(t).find("VocabularyTree: word 3 has weight "), 0u) << bad;
  }
  t = good;
  t.wordWeights[3] = -0.0f;
  EXPECT_NO_THROW(Vocabulary::create(t)) << "-0 is >= 0";
  // Masks: counted by a kernel per SIMD level, each of which finds the first empty one.
  const SimdLevel top = supportedSimdLevel();
  for (const SimdLevel level : supportedSimdLevels()) {
    limitSimdLevel(level);
    for (const int bits : {96, 256}) {
      t = randomTree(3, 2, bits, true, 5);
      t.masks.row(5).setTo(0);
      t.masks.row(9).setTo(0);
      EXPECT_EQ(createProblem(t), "VocabularyTree: node 5 has an empty mask") << bits << " " << toString(level);
      t.masks.row(5).setTo(0);
      t.masks.row(5).colRange(bits / 8 - 4, bits / 8).setTo(0x80);  // the last word only
      EXPECT_EQ(createProblem(t), "VocabularyTree: node 9 has an empty mask") << bits << " " << toString(level);
    }
  }
  limitSimdLevel(top);
}

// The file is mapped: the library's writers replace a file by renaming a new one over it, which
// must leave a loaded vocabulary as it was, and so must removing the file.
TEST(VocabularyFile, ALoadedVocabularyOutlivesItsFileBeingReplacedOrRemoved) {
  TempDir dir("vocab_mapped");
  const std::string path = (dir.path / "v.mdbvoc").string();
  const VocabularyTree t = randomTree(4, 3, 256, true, 9);
  Vocabulary::create(t).save(path);
  const Vocabulary loaded = Vocabulary::load(path);
  const std::string bytes = loaded.fileBytes();
  cv::Mat desc(50, 32, CV_8UC1), masks(50, 32, CV_8UC1);
  cv::randu(desc, 0, 256);
  cv::randu(masks, 0, 256);
  const std::vector<uint32_t> words = loaded.words(desc, masks);
  Vocabulary::create(randomTree(4, 3, 256, true, 10)).save(path);
  ASSERT_NE(readFile(path), bytes);
  EXPECT_EQ(loaded.fileBytes(), bytes);
  EXPECT_EQ(loaded.words(desc, masks), words);
  fs::remove(path);
  EXPECT_EQ(loaded.fileBytes(), bytes);
  EXPECT_EQ(loaded.words(desc, masks), words);
}
