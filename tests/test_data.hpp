#pragma once
// Where tests find data. Real data in ../shared/data is optional: tests that need it call
// sharedDataDir() and GTEST_SKIP() with a one-line reason when it is absent.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "toolkit/data_folders.hpp"

namespace mdbrief::testing {

// MDBRIEF_DATA (env) or <source>/../shared/data.
inline std::optional<std::filesystem::path> sharedDataDir() {
  return sharedDataFolder(std::filesystem::path(MDBRIEF_SOURCE_DIR) / ".." / "shared" / "data");
}

// Debian's opencv-doc sample photos (installed by scripts/setup-deps.sh; MDBRIEF_OPENCV_DOC).
inline std::optional<std::filesystem::path> opencvDocDataDir() { return opencvDocFolder(); }

inline std::filesystem::path sourceDir() { return MDBRIEF_SOURCE_DIR; }

// Expects call() to throw std::invalid_argument whose message contains `text`.
template <typename Call>
void expectInvalidArgument(Call&& call, const std::string& text) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    return;
  }
  ADD_FAILURE() << "no exception; expected one mentioning " << text;
}

// A fresh scratch folder, removed with its contents at scope exit. The process id keeps test
// executables that ctest runs in parallel apart.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& tag)
      : path(std::filesystem::temp_directory_path() / ("mdbrief_test_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace mdbrief::testing

#define MDBRIEF_REQUIRE_SHARED_DATA(var)                                          \
  const auto var##_opt = ::mdbrief::testing::sharedDataDir();                     \
  if (!var##_opt) GTEST_SKIP() << "../shared/data not found (set MDBRIEF_DATA)"; \
  const std::filesystem::path var = *var##_opt
