#pragma once
// Under a file size limit (`ulimit -f`) a write past it raises SIGXFSZ, whose default action
// kills the process (exit 153) before the writer can remove its temporary or report anything.
// Ignored, the write fails with EFBIG instead: the checked writers (mdbrief/internal/base/io/atomic_file.hpp)
// remove the temporary, keep the previous file, and the tool exits 2 naming the file.
namespace mdbrief {

// For the tools' entry points only: a library must not change its host's signal handling.
void ignoreFileSizeSignal();

}  // namespace mdbrief
