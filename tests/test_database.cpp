// The image database: queries rank by l1Score (to the last bit), return at most the asked number
// best first, save/load keeps the answers, and a file of another vocabulary or a damaged one is
// refused with its path and the problem.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "mdbrief/recognition/database.hpp"
#include "mdbrief/base/file_format_error.hpp"
#include "mdbrief/internal/base/io/framed_file.hpp"
#include "test_data.hpp"
#include "vocabulary_trees.hpp"

namespace fs = std::filesystem;
using namespace mdbrief;
using mdbrief::testing::randomTree;
using mdbrief::testing::TempDir;

namespace {

// Images as random descriptors; image i + 10 repeats image i with a quarter of its rows changed.
std::vector<cv::Mat> images(int count, int rows, uint32_t seed) {
  cv::RNG rng(seed);
  std::vector<cv::Mat> out;
  for (int i = 0; i < count; ++i) {
    cv::Mat d(rows, 32, CV_8UC1);
    rng.fill(d, cv::RNG::UNIFORM, 0, 256);
    out.push_back(d);
  }
  for (int i = 0; i < count; ++i) {
    cv::Mat d = out[i].clone();
    rng.fill(d.rowRange(0, rows / 4), cv::RNG::UNIFORM, 0, 256);
    out.push_back(d);
  }
  return out;
}

}  // namespace

TEST(Database, QueriesRankByL1ScoreBestFirstAndFindTheNearDuplicate) {
  const Vocabulary v = Vocabulary::create(randomTree(8, 3, 256, false, 11));
  const std::vector<cv::Mat> imgs = images(10, 200, 4);
  Database db(v);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(db.addDescriptors(imgs[i]), static_cast<uint32_t>(i));
  EXPECT_EQ(db.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    const BowVector q = v.transform(imgs[10 + i]).bow;
    const std::vector<QueryResult> r = db.query(q, 4);
    ASSERT_EQ(r.size(), 4u);
    EXPECT_EQ(r[0].entry, static_cast<uint32_t>(i));
    for (size_t k = 0; k < r.size(); ++k) {
      EXPECT_EQ(r[k].score, l1Score(q, db.entry(r[k].entry))) << "bit-exact l1Score";
      if (k > 0) {
        EXPECT_GE(r[k - 1].score, r[k].score);
      }
    }
    // Against itself: score 1 (up to rounding), first.
    const std::vector<QueryResult> self = db.query(db.entry(i), 1);
    EXPECT_EQ(self[0].entry, static_cast<uint32_t>(i));
    EXPECT_NEAR(self[0].score, 1.0f, 1e-5f);
  }
}

TEST(Database, EqualScoresGoToTheLowerEntryAndDisjointEntriesAreLeftOut) {
  VocabularyTree t = randomTree(4, 1, 32, false, 1);  // 4 words
  Database db(Vocabulary::create(t));
  db.add(BowVector{{0, 0.5f}, {1, 0.5f}});
  db.add(BowVector{{2, 1.0f}});
  db.add(BowVector{{0, 0.5f}, {1, 0.5f}});
  const std::vector<QueryResult> r = db.query(BowVector{{0, 1.0f}}, 10);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].entry, 0u);
  EXPECT_EQ(r[1].entry, 2u);
  EXPECT_EQ(r[0].score, 0.5f);
  EXPECT_THROW(db.add(BowVector{{1, 0.5f}, {0, 0.5f}}), std::invalid_argument);
  EXPECT_THROW(db.add(BowVector{{4, 1.0f}}), std::invalid_argument);
  EXPECT_THROW(db.add(BowVector{{0, 0.0f}}), std::invalid_argument);
  EXPECT_THROW(db.query(BowVector{{0, 1.0f}}, 0), std::invalid_argument);
  EXPECT_THROW(db.entry(3), std::out_of_range);
}

TEST(Database, SaveLoadKeepsTheAnswersAndRefusesAnotherVocabularyOrADamagedFile) {
  TempDir dir("database");
  const Vocabulary v = Vocabulary::create(randomTree(6, 3, 256, true, 2));
  const std::vector<cv::Mat> imgs = images(8, 150, 9);
  Database db(v);
  for (int i = 0; i < 8; ++i) db.addDescriptors(imgs[i]);
  const fs::path p = dir.path / "db.mdbdb";
  db.save(p.string());
  const Database back = Database::load(p.string(), v);
  ASSERT_EQ(back.size(), db.size());
  EXPECT_EQ(back.fileBytes(), db.fileBytes());
  for (int i = 8; i < 16; ++i) {
    const BowVector q = v.transform(imgs[i]).bow;
    const auto a = db.query(q, 3), b = back.query(q, 3);
    ASSERT_EQ(a.size(), b.size());
    for (size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].entry, b[k].entry);
      EXPECT_EQ(a[k].score, b[k].score);
    }
  }
  const auto problem = [&](const std::string& bytes, const Vocabulary& with) -> std::string {
    const fs::path bad = dir.path / "bad.mdbdb";
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << bytes;
    try {
      Database::load(bad.string(), with);
    } catch (const FileFormatError& e) {
      EXPECT_EQ(e.path(), bad.string());
      return e.problem();
    }
    return "loaded";
  };
  const std::string good = db.fileBytes();
  EXPECT_NE(problem(good, Vocabulary::create(randomTree(6, 3, 256, true, 3))).find("made with another vocabulary"),
            std::string::npos);
  EXPECT_NE(problem(good.substr(0, good.size() - 4), v).find("truncated"), std::string::npos);
  std::string entries = good;
  const uint32_t many = 1000;
  std::memcpy(&entries[44], &many, 4);
  internal::repairChecksum(entries);
  EXPECT_NE(problem(entries, v).find("need"), std::string::npos);
  EXPECT_NE(problem(v.fileBytes(), v).find("not a database file"), std::string::npos);
}
