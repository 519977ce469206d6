// The vocabulary's binary file: a round trip keeps every byte, and a missing, truncated,
// foreign, newer, damaged or inconsistent file is refused with its path and the problem.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "mdbrief/file_format_error.hpp"
#include "mdbrief/internal/framed_file.hpp"
#include "mdbrief/vocabulary.hpp"
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
