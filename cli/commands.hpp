#pragma once
// The subcommands of the `mdbrief` command line. Each file command_<name>.cpp defines one
// add<Name>Command, which registers the subcommand, its flags and its callback on the app;
// main.cpp lists them (one line each) and hands them to runCli().
#include <functional>
#include <stdexcept>
#include <vector>

#include <CLI/CLI.hpp>

namespace mdbrief::cli {

// Bad input detected by a command (a missing or unreadable file, an inconsistent argument).
// The message is one line starting with the file or flag at fault; runCli prints it and
// returns 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using CommandAdder = std::function<void(CLI::App&)>;

// Parses argv and runs the chosen subcommand. Returns the process exit code: 0 on success
// (and for --help), 2 for bad usage or bad input (one line on stderr), 1 for an unexpected
// internal error. OpenCV's log is silenced first (toolkit/opencv_log.hpp).
int runCli(int argc, char** argv, const std::vector<CommandAdder>& commands);

void addExtractCommand(CLI::App& app);
void addMatchCommand(CLI::App& app);
void addDrawCommand(CLI::App& app);
void addCameraCommand(CLI::App& app);
void addSimCommand(CLI::App& app);   // cli/command_sim.cpp (eval/ library)
void addEvalCommand(CLI::App& app);  // cli/command_eval.cpp (eval/ library)
void addBenchCommand(CLI::App& app);

}  // namespace mdbrief::cli
