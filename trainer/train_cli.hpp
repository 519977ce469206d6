#pragma once
// mdbrief-train: the command line over train() (training.hpp): its flags are TrainOptions'
// field table (train_options.hpp). In the library so tests can run the whole tool in-process.
#include <iosfwd>
#include <string>
#include <vector>

namespace mdbrief::train {

// args without the program name. --out is required and must name an existing folder (the
// patterns folder whose registry is rewritten). Returns the exit code: 0 success, 2 bad input or
// a failed step (message on err naming the option or file and the problem). Progress and
// summary go to out; progressTty draws the progress as a bar.
int runTrainCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                bool progressTty = false);

}  // namespace mdbrief::train
