// The atomic file writer every tool and saveCamera use (mdbrief/internal/atomic_file.hpp): the
// target changes only when the new content is complete, and no temporary is left behind.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mdbrief/internal/atomic_file.hpp"
#include "test_data.hpp"

namespace fs = std::filesystem;
using mdbrief::internal::writeAtomically;
using mdbrief::internal::writeFileAtomically;
using mdbrief::testing::readFile;
using mdbrief::testing::TempDir;

namespace {

std::vector<std::string> fileNames(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST(AtomicFile, WritesANewFileAndReplacesAnExistingOne) {
  TempDir dir("atomic_replace");
  const fs::path target = dir.path / "table.csv";
  writeFileAtomically(target, "first\n");
  EXPECT_EQ(readFile(target), "first\n");
  writeFileAtomically(target, "second\n");
  EXPECT_EQ(readFile(target), "second\n");
  EXPECT_EQ(fileNames(dir.path), std::vector<std::string>{"table.csv"});
}

TEST(AtomicFile, AFailingWriterLeavesTheOldFileAndNoTemporary) {
  TempDir dir("atomic_failure");
  const fs::path target = dir.path / "table.csv";
  writeFileAtomically(target, "kept\n");
  EXPECT_THROW(writeAtomically(target,
                               [](const fs::path& temp) {
                                 std::ofstream(temp) << "half";
                                 throw std::runtime_error("writer failed");
                               }),
               std::runtime_error);
  EXPECT_EQ(readFile(target), "kept\n");
  EXPECT_EQ(fileNames(dir.path), std::vector<std::string>{"table.csv"});

  // Without an old file, a failure leaves nothing at all.
  const fs::path fresh = dir.path / "fresh.csv";
  EXPECT_THROW(writeAtomically(fresh, [](const fs::path& temp) {
    std::ofstream(temp) << "half";
    throw std::invalid_argument("bad input");
  }),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(fresh));
  EXPECT_EQ(fileNames(dir.path), std::vector<std::string>{"table.csv"});
}

TEST(AtomicFile, TemporariesAreHiddenUniqueAndKeepTheExtensions) {
  TempDir dir("atomic_names");
  const fs::path target = dir.path / "features.yml.gz";
  std::vector<fs::path> temps;
  for (int i = 0; i < 2; ++i)
    writeAtomically(target, [&](const fs::path& temp) {
      temps.push_back(temp);
      std::ofstream(temp) << i;
    });
  ASSERT_EQ(temps.size(), 2u);
  EXPECT_NE(temps[0], temps[1]);
  for (const auto& t : temps) {
    EXPECT_EQ(t.parent_path(), dir.path);
    const std::string name = t.filename().string();
    EXPECT_EQ(name.rfind(".features.tmp", 0), 0u) << name;
    EXPECT_EQ(name.substr(name.size() - 7), ".yml.gz") << name;
  }
  EXPECT_EQ(readFile(target), "1");
}

TEST(AtomicFile, ErrorsNameTheTargetAndLeaveNothingBehind) {
  TempDir dir("atomic_errors");
  const fs::path missing = dir.path / "missing" / "out.txt";
  try {
    writeFileAtomically(missing, "x");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  // A folder in the way: the rename fails, the temporary is removed.
  const fs::path blocked = dir.path / "blocked";
  fs::create_directories(blocked / "inside");
  try {
    writeFileAtomically(blocked, "x");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(blocked.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(fileNames(dir.path), std::vector<std::string>{"blocked"});
}
