#pragma once
// mdbrief-pattern-random: writes the random BRIEF (G II) test set as a pattern header, its JSON
// copy and the regenerated registry (random_pattern.hpp has the distribution). In the library so
// tests run the tool in-process and walk its flags.
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mdbrief::train {

// The tool's flags on an app that holds what they are parsed into (tests/test_cli_file_flags.cpp
// walks them); runPatternRandomCli parses this app.
std::unique_ptr<CLI::App> patternRandomCommandLine();

// args without the program name. Returns the exit code: 0 success, 2 bad input or a failed
// write (message on err).
int runPatternRandomCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace mdbrief::train
