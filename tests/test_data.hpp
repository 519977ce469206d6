#pragma once
// Where tests find data. Real data in ../shared/data and the opencv-doc photos are optional:
// tests that need them skip with a one-line reason when they are absent
// (MDBRIEF_SKIP_WITHOUT_DATA), and fail instead under MDBRIEF_NO_SKIPS=1, which CI sets
// (.ci/run): a machine without the data must not pass by skipping. The other skips are for what
// a machine cannot offer (a tmpfs mount, /proc, another OpenCV): they stay skips.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
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

// MDBRIEF_NO_SKIPS=1: a test without its data fails instead of skipping.
inline bool skipsFail() {
  const char* value = std::getenv("MDBRIEF_NO_SKIPS");
  return value && std::string(value) == "1";
}

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

// GTEST_SKIP() << reason, for a test whose data (../shared/data, opencv-doc) is missing; under
// MDBRIEF_NO_SKIPS=1 a failure with the same reason.
#define MDBRIEF_SKIP_WITHOUT_DATA(reason)                                        \
  do {                                                                           \
    if (::mdbrief::testing::skipsFail())                                         \
      GTEST_FAIL() << reason << " (a failure, not a skip: MDBRIEF_NO_SKIPS=1)"; \
    GTEST_SKIP() << reason;                                                      \
  } while (false)

#define MDBRIEF_REQUIRE_SHARED_DATA(var)                                                   \
  const auto var##_opt = ::mdbrief::testing::sharedDataDir();                              \
  if (!var##_opt) MDBRIEF_SKIP_WITHOUT_DATA("../shared/data not found (set MDBRIEF_DATA)"); \
  const std::filesystem::path var = *var##_opt
