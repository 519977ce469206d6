// The atomic file writer every tool and saveCamera use (mdbrief/internal/base/io/atomic_file.hpp): the
// target changes only when the new content is complete, and no temporary is left behind; a
// failed write (file size limit, full disk) keeps the old file; nodes that are not regular
// files are never replaced; several files are replaced together.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "test_data.hpp"
#include "write_limits.hpp"

namespace fs = std::filesystem;
using mdbrief::internal::checkOutputPath;
using mdbrief::internal::writeAtomically;
using mdbrief::internal::writeFileAtomically;
using mdbrief::internal::writeFilesAtomically;
using mdbrief::testing::FileSizeLimit;
using mdbrief::testing::readFile;
using mdbrief::testing::SmallTmpfs;
using mdbrief::testing::TempDir;

namespace {

std::vector<std::string> fileNames(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The message of the std::runtime_error that f throws ("" and a test failure if none).
template <class F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a std::runtime_error";
  return "";
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

TEST(AtomicFile, AWriteBeyondTheFileSizeLimitKeepsTheOldFile) {
  TempDir dir("atomic_fsize");
  const fs::path target = dir.path / "table.csv";
  writeFileAtomically(target, "kept\n");
  std::string message;
  {
    const FileSizeLimit limit(4096);
    message = errorOf([&] { writeFileAtomically(target, std::string(10000, 'x')); });
  }
  EXPECT_NE(message.find(target.string()), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_EQ(readFile(target), "kept\n");
  EXPECT_EQ(fileNames(dir.path), std::vector<std::string>{"table.csv"});
}

TEST(AtomicFile, AFullDiskKeepsTheOldFile) {
  SmallTmpfs disk("atomic", 64 * 1024);
  if (!disk.mounted()) GTEST_SKIP() << disk.skipReason();
  const fs::path target = disk.path / "table.csv";
  writeFileAtomically(target, "kept\n");
  disk.fill();
  const std::string message = errorOf([&] { writeFileAtomically(target, std::string(10000, 'x')); });
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  EXPECT_EQ(readFile(target), "kept\n");
  EXPECT_EQ(fileNames(disk.path), (std::vector<std::string>{"filler", "table.csv"}));
}

TEST(AtomicFile, NodesThatAreNotRegularFilesAreNeverReplaced) {
  TempDir dir("atomic_nodes");
  const fs::path fifo = dir.path / "out.yml";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path folder = dir.path / "folder.png";
  fs::create_directories(folder);
  std::vector<fs::path> nodes{fifo, folder};
  // A character device like /dev/null: only root may make one.
  const fs::path device = dir.path / "null.yml";
  if (::mknod(device.c_str(), S_IFCHR | 0600, makedev(1, 3)) == 0) nodes.push_back(device);
  for (const fs::path& node : nodes) {
    const fs::file_type type = fs::symlink_status(node).type();
    for (const std::string& message :
         {errorOf([&] { writeFileAtomically(node, "x"); }), errorOf([&] { checkOutputPath(node); }),
          errorOf([&] { writeFilesAtomically({{dir.path / "other.txt", "y"}, {node, "x"}}); })}) {
      EXPECT_NE(message.find(node.string()), std::string::npos) << message;
      EXPECT_NE(message.find("not a regular file; refusing to replace it"), std::string::npos) << message;
    }
    EXPECT_EQ(fs::symlink_status(node).type(), type) << node;
  }
  EXPECT_EQ(fileNames(dir.path).size(), nodes.size()) << "no temporary, nothing else written";
}

TEST(AtomicFile, CheckOutputPathAcceptsNewAndRegularFilesAndLeavesNothing) {
  TempDir dir("atomic_check");
  checkOutputPath(dir.path / "new.yml");
  writeFileAtomically(dir.path / "old.yml", "old");
  checkOutputPath(dir.path / "old.yml");
  EXPECT_EQ(fileNames(dir.path), std::vector<std::string>{"old.yml"});
  const std::string missing = errorOf([&] { checkOutputPath(dir.path / "missing" / "x.yml"); });
  EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;
}

// Issue 45: the cleanup removed any file named like a temporary, and a live writer's temporary
// in another pid namespace. Now only a temporary whose writer's lock is free goes.
TEST(AtomicFile, OnlyTemporariesWhoseWritersLockIsFreeAreRemovedByTheNextWrite) {
  TempDir dir("atomic_orphans");
  const fs::path target = dir.path / "patches.h5";
  const std::string stale = ".patches.tmp-0123456789abcdef.h5";  // a killed writer's: nobody locks it
  const std::string held = ".patches.tmp-fedcba9876543210.h5";   // a live writer's, locked
  const std::string foreign = ".patches.tmp2024-07.h5";          // the user's file, named alike
  const std::string otherTarget = ".other.tmp-0123456789abcdef.h5";
  for (const auto& name : {stale, held, foreign, otherTarget}) std::ofstream(dir.path / name) << "partial";
  // The live writer: another process holds the lock until the pipe closes.
  int ready[2], done[2];
  ASSERT_EQ(::pipe(ready), 0);
  ASSERT_EQ(::pipe(done), 0);
  const std::string heldPath = (dir.path / held).string();
  const pid_t writer = ::fork();
  if (writer == 0) {
    ::close(done[1]);
    const int fd = ::open(heldPath.c_str(), O_RDONLY);
    char c = ::flock(fd, LOCK_EX) == 0 ? 'y' : 'n';
    if (::write(ready[1], &c, 1) != 1 || ::read(done[0], &c, 1) < 0) ::_exit(1);
    ::_exit(0);
  }
  char locked = 0;
  ASSERT_EQ(::read(ready[0], &locked, 1), 1);
  ASSERT_EQ(locked, 'y');
  writeFileAtomically(target, "new");
  EXPECT_EQ(readFile(target), "new");
  std::vector<std::string> expected{held, foreign, otherTarget, "patches.h5"};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(fileNames(dir.path), expected);
  // The writer gone, its lock is free: the next write removes its temporary.
  ::close(done[1]);
  ::waitpid(writer, nullptr, 0);
  writeFileAtomically(target, "newer");
  expected.erase(std::find(expected.begin(), expected.end(), held));
  EXPECT_EQ(fileNames(dir.path), expected);
  for (const int fd : {ready[0], ready[1], done[0]}) ::close(fd);
}

TEST(AtomicFiles, ReplaceTheWholeSetOrNothing) {
  TempDir dir("atomic_set");
  const fs::path a = dir.path / "set.json", b = dir.path / "set.hpp", c = dir.path / "registry.hpp";
  writeFilesAtomically({{a, "old a"}, {b, "old b"}});
  EXPECT_EQ(readFile(a), "old a");
  EXPECT_EQ(readFile(b), "old b");
  // The second file cannot be written: the first keeps its old content, the third is not made.
  std::string message;
  {
    const FileSizeLimit limit(4096);
    message = errorOf([&] { writeFilesAtomically({{a, "new a"}, {b, std::string(10000, 'b')}, {c, "new c"}}); });
  }
  EXPECT_NE(message.find(b.string()), std::string::npos) << message;
  EXPECT_EQ(readFile(a), "old a");
  EXPECT_EQ(readFile(b), "old b");
  EXPECT_EQ(fileNames(dir.path), (std::vector<std::string>{"set.hpp", "set.json"}));
  writeFilesAtomically({{a, "new a"}, {b, "new b"}, {c, "new c"}});
  EXPECT_EQ(readFile(a) + readFile(b) + readFile(c), "new anew bnew c");
  EXPECT_EQ(fileNames(dir.path), (std::vector<std::string>{"registry.hpp", "set.hpp", "set.json"}));
}

// Issue 29: `match a.yml b.yml -o a.yml` replaced its input. An output is refused when it is an
// input under any name (itself, a symbolic link, a hard link, a path through a linked folder),
// and two outputs that are one file, existing or still to be made, are refused.
TEST(OutputsApart, AnOutputThatIsAnInputOrAnotherOutputIsRefused) {
  TempDir dir("outputs_apart");
  const fs::path input = dir.path / "a.yml", other = dir.path / "b.yml";
  std::ofstream(input) << "input";
  std::ofstream(other) << "other";
  fs::create_symlink(input, dir.path / "link.yml");
  fs::create_hard_link(input, dir.path / "hard.yml");
  fs::create_directory_symlink(dir.path, dir.path / "same_dir");
  using mdbrief::internal::checkOutputsApart;
  for (const fs::path& alias : {input, dir.path / "link.yml", dir.path / "hard.yml", dir.path / "same_dir" / "a.yml",
                                dir.path / "." / "a.yml"}) {
    const std::string message = errorOf([&] { checkOutputsApart({other, input}, {alias}); });
    EXPECT_NE(message.find(alias.string() + ": the output is the same file as the input " + input.string()),
              std::string::npos)
        << message;
  }
  const fs::path fresh = dir.path / "new.yml";
  const std::string message = errorOf([&] { checkOutputsApart({input}, {fresh, dir.path / "same_dir" / "new.yml"}); });
  EXPECT_NE(message.find("the same file as the output " + fresh.string()), std::string::npos) << message;
  EXPECT_NE(errorOf([&] { checkOutputsApart({}, {other, dir.path / "." / "b.yml"}); }).find("one would overwrite"),
            std::string::npos);
  // Distinct files, missing inputs and left-out (empty) paths pass; nothing was written.
  EXPECT_NO_THROW(checkOutputsApart({input, dir.path / "missing.yml", ""}, {fresh, other, ""}));
  EXPECT_EQ(readFile(input), "input");
  EXPECT_EQ(readFile(other), "other");
  EXPECT_FALSE(fs::exists(fresh));
}

// Issue 29: `-o link.yml` replaced the link with a file and left its target stale. Writes go
// through a symbolic link, one file or a set: the link stays, its target gets the content.
TEST(AtomicFile, ASymbolicLinkIsWrittenThrough) {
  TempDir dir("atomic_link");
  fs::create_directory(dir.path / "real");
  const fs::path target = dir.path / "real" / "out.yml", link = dir.path / "link.yml";
  std::ofstream(target) << "old";
  fs::create_symlink(target, link);
  writeFileAtomically(link, "new");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(readFile(target), "new");
  writeFilesAtomically({{link, "set"}, {dir.path / "other.yml", "other"}});
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(readFile(target), "set");
  EXPECT_EQ(fileNames(dir.path / "real"), std::vector<std::string>{"out.yml"});
  EXPECT_EQ(fileNames(dir.path), (std::vector<std::string>{"link.yml", "other.yml", "real"}));
}
