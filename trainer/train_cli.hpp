#pragma once
// mdbrief-train: the command line over train() (training.hpp): its flags are TrainOptions'
// field table (train_options.hpp). In the library so tests can run the whole tool in-process.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mdbrief::train {

// The tool's flags on an app that holds what they are parsed into (tests/test_cli_file_flags.cpp
// walks them); runTrainCli parses this app.
std::unique_ptr<CLI::App> trainCommandLine();

// args without the program name. --out is required and must name an existing folder (the
// patterns folder whose registry is rewritten). Returns the exit code by the tools' rule
// (toolkit/tool_errors.hpp): 0 success, 2 bad input or a file that cannot be read or written
// (message on err naming the option or file and the problem), 1 an internal error. Progress and
// summary go to out; progressTty draws the progress as a bar.
int runTrainCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                bool progressTty = false);

}  // namespace mdbrief::train
