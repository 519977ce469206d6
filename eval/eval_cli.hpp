#pragma once
// The mdbrief-eval program (mdbrief_eval.cpp) as a function, so that the tests run it in-process
// and see its exit code, by the tools' rule (toolkit/tool_errors.hpp): 0 success, 2 bad usage or
// input (the message names the option or file), 1 internal error.
#include <ostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace mdbrief::eval {

// Registers every subcommand of mdbrief-eval on app (the tests walk them).
void addEvalCommands(CLI::App& app);

// args without the program's name. --help and parse errors are written to `out` / `err` (the
// subcommands' own progress goes to stdout).
int runEvalCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace mdbrief::eval
