#pragma once
// Where tests find data. Real data in ../shared/data is optional: tests that need it call
// sharedDataDir() and GTEST_SKIP() with a one-line reason when it is absent.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace mdbrief::testing {

// MDBRIEF_DATA (env) or <source>/../shared/data.
inline std::optional<std::filesystem::path> sharedDataDir() {
  if (const char* env = std::getenv("MDBRIEF_DATA"); env && *env) {
    if (std::filesystem::is_directory(env)) return std::filesystem::path(env);
    return std::nullopt;
  }
  const auto p = std::filesystem::path(MDBRIEF_SOURCE_DIR) / ".." / "shared" / "data";
  if (std::filesystem::is_directory(p)) return std::filesystem::weakly_canonical(p);
  return std::nullopt;
}

// Debian's opencv-doc sample photos (installed by scripts/setup-deps.sh).
inline std::optional<std::filesystem::path> opencvDocDataDir() {
  const std::filesystem::path p = "/usr/share/doc/opencv-doc/examples/data";
  if (std::filesystem::is_directory(p)) return p;
  return std::nullopt;
}

inline std::filesystem::path sourceDir() { return MDBRIEF_SOURCE_DIR; }

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
