#pragma once
// mdbrief-train: patch extraction (or a saved patch file), training, and the pattern header +
// JSON + registry. In the library so tests can run the whole tool in-process.
#include <iosfwd>
#include <string>
#include <vector>

namespace mdbrief::train {

inline constexpr const char* kDefaultImageFolder = "/usr/share/doc/opencv-doc/examples/data";

// args without the program name. Returns the exit code: 0 success, 2 bad input or a failed
// step (message on err naming the file and the problem). Progress and summary go to out;
// progressTty draws the progress as a bar.
int runTrainCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                bool progressTty = false);

}  // namespace mdbrief::train
