#pragma once
// mdbrief-patchextract: image folders -> HDF5 patch set (patch_set.hpp), for mdbrief-train
// --patches-file. Its flags are ExtractionOptions' field table (patch_extraction.hpp). In the
// library so tests run the whole tool in-process and walk its flags.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mdbrief::train {

// The tool's flags on an app that holds what they are parsed into (tests/test_cli_file_flags.cpp
// walks them); the program parses this app.
std::unique_ptr<CLI::App> patchExtractCommandLine();

// args without the program name. Returns the exit code: 0 success, 2 bad input or a failed
// step (message on err naming the option or file). Progress and the summary go to out;
// progressTty draws the progress as a bar.
int runPatchExtractCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                       bool progressTty = false);

}  // namespace mdbrief::train
