#pragma once
// Why a path cannot be read as an input file, so that a folder, a FIFO or a symlink loop is
// reported as what it is and not as a missing file. Internal to the build, as atomic_file.hpp.
#include <cstdint>
#include <filesystem>
#include <string>

namespace mdbrief::internal {

// "" when path is a regular file this process can open for reading; otherwise the reason, e.g.
// "no such file", "is a folder, not a file", "is a FIFO, not a regular file", "too many levels
// of symbolic links (a symlink loop?)", "cannot open: Permission denied". Never blocks: a FIFO
// or a device is refused before anything opens it.
std::string inputFileProblem(const std::filesystem::path& path);

// The bytes of a small input file (a list, a configuration) after inputFileProblem's checks and
// a size limit, so that /dev/zero, a FIFO or a huge file is refused instead of read without
// bound. Throws std::runtime_error "<path>: <kind>: <problem>", e.g. "l.txt: held-out list: is a
// character device, not a regular file" or "...: 70000000 bytes, over the 64 MiB a held-out list
// may have".
std::string readInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes, const std::string& kind);

}  // namespace mdbrief::internal
