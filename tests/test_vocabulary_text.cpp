// DBoW2/DBoW3 text vocabularies: a file in DBoW2's node order imports with its words, export and
// import give the same vocabulary back, and every malformed line is refused with the file, the
// line and the problem.
#include <gtest/gtest.h>

#include <fstream>

#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"
#include "test_data.hpp"
#include "vocabulary_trees.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using mdbrief::testing::randomTree;
using mdbrief::testing::readFile;
using mdbrief::testing::TempDir;

namespace {

// k = 2, L = 3, 4-byte descriptors, nodes as DBoW2 numbers them (each node's children together,
// subtrees depth first): root -> 1, 2; 1 -> 3, 4 (leaf); 3 -> 5, 6 (leaves); 2 -> 7, 8 (leaves).
const char* const kSample =
    "2 3 0 0\n"
    "0 0 0 0 0 0 0\n"
    "0 0 255 255 255 255 0\n"
    "1 0 0 0 0 0 0\n"
    "1 1 0 0 255 255 0.25\n"
    "3 1 0 0 0 0 0.5\n"
    "3 1 15 0 0 0 1\n"
    "2 1 255 255 255 255 2\n"
    "2 1 255 255 0 0 4\n";

fs::path write(const TempDir& dir, const std::string& text, const std::string& name = "voc.txt") {
  const fs::path p = dir.path / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc) << text;
  return p;
}

std::string importProblem(const TempDir& dir, const std::string& text) {
  const fs::path p = write(dir, text);
  try {
    importDbow2Text(p.string());
  } catch (const FileFormatError& e) {
    EXPECT_EQ(e.path(), p.string());
    return e.problem();
  }
  ADD_FAILURE() << "imported:\n" << text;
  return "";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

}  // namespace

TEST(VocabularyText, ImportsDbow2NodeOrderWithLeavesAsWordsInNodeOrder) {
  TempDir dir("vtext_sample");
  const Vocabulary v = importDbow2Text(write(dir, kSample).string());
  EXPECT_EQ(v.bits(), 32);
  EXPECT_EQ(v.branching(), 2);
  EXPECT_EQ(v.depth(), 3);
  EXPECT_FALSE(v.masked());
  EXPECT_EQ(v.nodeCount(), 9u);
  ASSERT_EQ(v.wordCount(), 5u);  // nodes 4, 5, 6, 7, 8
  EXPECT_EQ(v.wordNode(0), 4u);
  EXPECT_EQ(v.wordWeight(0), 0.25f);
  EXPECT_EQ(v.wordWeight(4), 4.0f);
  const cv::Mat d = (cv::Mat_<uint8_t>(2, 4) << 14, 0, 0, 0, 255, 255, 1, 0);
  EXPECT_EQ(v.words(d), (std::vector<uint32_t>{2, 4}));
  // Export writes the same text (weights with 9 significant digits, scoring L1).
  EXPECT_EQ(dbow2Text(v), kSample);
}

TEST(VocabularyText, ExportThenImportGivesTheSameVocabulary) {
  TempDir dir("vtext_round");
  for (const int bits : {128, 256, 512}) {
    VocabularyTree t = randomTree(4, 3, bits, false, static_cast<uint32_t>(bits));
    t.weighting = Weighting::Tf;
    t.wordWeights[3] = 0.123456789f;
    const Vocabulary v = Vocabulary::create(t);
    const fs::path p = dir.path / "round.txt";
    exportDbow2Text(v, p.string());
    EXPECT_EQ(readFile(p), dbow2Text(v));
    const Vocabulary back = importDbow2Text(p.string());
    EXPECT_EQ(back.fileBytes(), v.fileBytes()) << bits << " bits";
  }
}

TEST(VocabularyText, RefusesAMaskedVocabulary) {
  const Vocabulary masked = Vocabulary::create(randomTree(2, 2, 256, true, 1));
  EXPECT_THROW(dbow2Text(masked), std::invalid_argument);
}

TEST(VocabularyText, NamesTheLineAndTheProblemOfAMalformedFile) {
  TempDir dir("vtext_bad");
  const std::string s = kSample;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "empty"},
      {"hello world\n", "line 1: expected the header"},
      {replaced(s, "2 3 0 0", "2 3 0 7"), "line 1: weighting 7"},
      {replaced(s, "2 3 0 0", "1 3 0 0"), "line 1: k = 1"},
      {replaced(s, "3 1 15 0 0 0 1", "3 1 256 0 0 0 1"), "line 7: descriptor byte 1 '256' is not an integer in [0, 255]"},
      {replaced(s, "3 1 15 0 0 0 1", "3 1 0.5 0 0 0 1"), "line 7: descriptor byte 1 '0.5'"},
      {replaced(s, "3 1 15 0 0 0 1", "3 1 15 0 0 0 9 1"), "line 7: 5 descriptor bytes, the lines before have 4"},
      {replaced(s, "1 0 0 0 0 0 0", "7 0 0 0 0 0 0"), "line 4: parent 7 of node 3 is not an earlier node"},
      {replaced(s, "3 1 0 0 0 0 0.5", "2 1 0 0 0 0 0.5"), "line 8: node 7: the children of node 2 are not on consecutive lines"},
      {replaced(s, "1 1 0 0 255 255 0.25", "1 0 0 0 255 255 0.25"), "line 5: node 4 is marked an inner node but has no children"},
      {replaced(s, "3 1 15 0 0 0 1", "3 1 15 0 0 0 -1"), "line 7: weight '-1' is not a finite number >= 0"},
      {replaced(s, "3 1 15 0 0 0 1", "3 1 15 0 0 0 nan"), "line 7: weight 'nan'"},
      {replaced(s, "2 3 0 0", "2 2 0 0"), "node 3 at depth 2 has children, deeper than the depth 2"},
      {replaced(s, "0 0 0 0 0 0 0\n", "0 0 0 0 0 0\n"), "line 2: 3 descriptor bytes"},
      {"2 3 0 0\n", "no nodes after the header"},
      {replaced(s, "2 1 255 255 0 0 4", "2 2 255 255 0 0 4"), "line 9: expected the leaf flag"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string problem = importProblem(dir, text);
    EXPECT_NE(problem.find(expected), std::string::npos) << "expected '" << expected << "', got '" << problem << "'";
  }
}
