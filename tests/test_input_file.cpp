// Inputs that are not files (mdbrief/internal/base/io/input_file.hpp): each named for what it is, a FIFO
// refused without being opened.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "mdbrief/internal/base/io/input_file.hpp"
#include "test_data.hpp"

namespace fs = std::filesystem;
using mdbrief::internal::inputFileProblem;
using mdbrief::testing::TempDir;

TEST(InputFile, NamesWhatIsThereInsteadOfAFile) {
  TempDir dir("input_file");
  std::ofstream(dir.path / "file.yml") << "x";
  EXPECT_EQ(inputFileProblem(dir.path / "file.yml"), "");
  EXPECT_EQ(inputFileProblem(dir.path / "none.yml"), "no such file");
  EXPECT_EQ(inputFileProblem(dir.path), "is a folder, not a file");
  ASSERT_EQ(::mkfifo((dir.path / "fifo.yml").c_str(), 0600), 0);
  EXPECT_EQ(inputFileProblem(dir.path / "fifo.yml"), "is a FIFO, not a regular file");  // without blocking
  fs::create_symlink("loop.yml", dir.path / "loop.yml");
  EXPECT_NE(inputFileProblem(dir.path / "loop.yml").find("symbolic links"), std::string::npos);
  EXPECT_EQ(inputFileProblem("/dev/null"), "is a character device, not a regular file");
  EXPECT_NE(inputFileProblem(dir.path / "file.yml" / "x").find("no such file"), std::string::npos);
}
