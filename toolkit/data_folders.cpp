#include "toolkit/data_folders.hpp"

#include <cstdlib>

namespace mdbrief {

namespace fs = std::filesystem;

namespace {

std::optional<fs::path> existingFolder(const char* environmentVariable, const fs::path& fallback) {
  const char* env = std::getenv(environmentVariable);
  const fs::path folder = env && *env ? fs::path(env) : fallback;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return std::nullopt;
  return fs::weakly_canonical(folder, ec);
}

}  // namespace

std::optional<fs::path> sharedDataFolder(const fs::path& fallback) { return existingFolder("MDBRIEF_DATA", fallback); }

std::optional<fs::path> opencvDocFolder() { return existingFolder("MDBRIEF_OPENCV_DOC", kDebianOpencvDocData); }

}  // namespace mdbrief
