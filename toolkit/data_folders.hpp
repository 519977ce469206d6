#pragma once
// Where the benchmarks and the tests find the optional data of the machine: the shared data
// folder (real images, ../shared/data) and Debian's opencv-doc sample photos.
#include <filesystem>
#include <optional>

namespace mdbrief {

// Where scripts/setup-deps.sh installs the opencv-doc sample photos on Debian.
inline const char* const kDebianOpencvDocData = "/usr/share/doc/opencv-doc/examples/data";

// MDBRIEF_DATA (environment) if set, else `fallback`; nullopt when that is not a folder.
std::optional<std::filesystem::path> sharedDataFolder(const std::filesystem::path& fallback);

// MDBRIEF_OPENCV_DOC (environment) if set, else kDebianOpencvDocData; nullopt when that is not
// a folder.
std::optional<std::filesystem::path> opencvDocFolder();

}  // namespace mdbrief
