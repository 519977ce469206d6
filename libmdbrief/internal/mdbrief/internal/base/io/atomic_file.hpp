#pragma once
// Replacing files only once their new content is complete and on disk, so that an interrupted
// or failed run (a full disk, a file size limit, a signal) leaves the previous file (or none)
// instead of a half-written one. Used by the library (saveCamera) and by the tools through the
// build-only target mdbrief_internal; not installed.
//
// Every write goes the same way: a temporary in the target's folder (same file system, so the
// rename is atomic), every write and the flush checked, fsync, rename over the target, then an
// fsync of the folder (best effort: some file systems refuse it on a folder). Temporaries are
// hidden and unique per call ("." + first part of the name + ".tmp-" + 16 random hex digits + the
// rest, e.g. ".img1.tmp-3f09a1c47be2d805.png"): they keep target's extensions, from which
// writers such as cv::imwrite pick the format. The writer holds an flock on its temporary for
// the temporary's lifetime. A process killed while writing cannot remove its temporary, but the
// kernel drops its lock: the next write of the same target removes the temporaries of that exact
// form whose lock it can take. Nothing else is removed: not a file named otherwise (even
// ".x.tmp2024-07.yml"), not another user's, not a live writer's, whatever its pid namespace. A
// target that is a symbolic link is written through, as editors do: the link stays and the file
// it points to is replaced (in that file's folder).
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace mdbrief::internal {

// Throws std::runtime_error naming target when a write to it would fail or do harm: its folder
// does not exist or no file can be created there (checked by creating and removing a
// temporary), or target exists and is not a regular file (a folder, a device such as /dev/null,
// a FIFO), which the rename would replace. For tools that check their outputs before the work.
void checkOutputPath(const std::filesystem::path& target);

// Throws std::runtime_error naming both paths when an output is the same file as an input (the
// write would destroy the input) or two outputs are one file (the second would replace the
// first). Files are compared by device and inode, so a symbolic or hard link to an input counts
// as the input; an output that does not exist yet compares by its folder's identity and its name.
// Empty paths (an optional flag left out) are skipped. For tools, before the work.
void checkOutputsApart(const std::vector<std::filesystem::path>& inputs,
                       const std::vector<std::filesystem::path>& outputs);

// Calls write(temp) with a fresh temporary path, then makes it durable and renames it over
// target. write must report its own failures by throwing. If write throws or anything after it
// fails, the temporary is removed, target is left as it was and the exception propagates. Throws
// std::runtime_error naming target when its folder does not exist, target is not a regular file,
// or the sync or the rename fails.
void writeAtomically(const std::filesystem::path& target,
                     const std::function<void(const std::filesystem::path& temp)>& write);

// writeAtomically with content as the file's bytes. Throws std::runtime_error naming target and
// the system's reason (e.g. "No space left on device", "File too large") when the temporary
// cannot be created or written.
void writeFileAtomically(const std::filesystem::path& target, std::string_view content);

struct FileContent {
  std::filesystem::path target;
  std::string content;
};

// Replaces several files as one: every temporary is written and synced first, then the renames
// follow; if one of them fails, the files already renamed get their previous content back (or
// are removed when they did not exist). So a failure leaves the previous set, a success the new
// one; only a crash between the renames can leave a mix. Targets must be distinct. Throws
// std::runtime_error as writeFileAtomically does.
void writeFilesAtomically(const std::vector<FileContent>& files);

}  // namespace mdbrief::internal
