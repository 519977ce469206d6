#pragma once
// Replacing a file only once its new content is complete, so that an interrupted or failed run
// leaves the previous file (or none) instead of a half-written one. Used by the library
// (saveCamera) and by the tools through the build-only target mdbrief_internal; not installed.
#include <filesystem>
#include <functional>
#include <string_view>

namespace mdbrief::internal {

// Calls write(temp) with a fresh temporary path in target's folder (same file system, so the
// rename is atomic), then renames it over target. The temporary is hidden and unique per call
// ("." + first part of the name + ".tmp<pid>-<n>" + the rest, e.g. ".img1.tmp42-0.png"): it
// keeps target's extensions, from which writers such as cv::imwrite pick the format. If
// write throws or the rename fails, the temporary is removed, target is left as it was and the
// exception propagates. Throws std::runtime_error naming target when its folder does not
// exist or the rename fails.
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& write);

// writeAtomically with content as the file's bytes. Throws std::runtime_error naming target
// when the temporary cannot be created or written.
void writeFileAtomically(const std::filesystem::path& target, std::string_view content);

}  // namespace mdbrief::internal
