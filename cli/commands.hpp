#pragma once
// The subcommands of the `mdbrief` command line. Each file command_<name>.cpp defines one
// add<Name>Command, which registers the subcommand, its flags and its callback on the app;
// main.cpp lists them (one line each) and hands them to runCli().
// Bad input detected by a command (a missing or unreadable file, an inconsistent argument) is
// an InputError (toolkit/tool_errors.hpp), whose message starts with the file or flag at fault.
#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

#include "toolkit/tool_errors.hpp"

namespace mdbrief::cli {

using CommandAdder = std::function<void(CLI::App&)>;

// Parses argv and runs the chosen subcommand. Returns the process exit code by the tools' rule
// (toolkit/tool_errors.hpp): 0 on success and for --help, 2 for bad usage or bad input, 1 for an
// internal error; the message is one line on stderr. OpenCV's log is silenced first
// (toolkit/opencv_log.hpp).
int runCli(int argc, char** argv, const std::vector<CommandAdder>& commands);

void addExtractCommand(CLI::App& app);
void addMatchCommand(CLI::App& app);
void addDrawCommand(CLI::App& app);
void addCameraCommand(CLI::App& app);
void addSimCommand(CLI::App& app);   // cli/command_sim.cpp (eval/ library)
void addEvalCommand(CLI::App& app);  // cli/command_eval.cpp (eval/ library)
void addBenchCommand(CLI::App& app);

}  // namespace mdbrief::cli
