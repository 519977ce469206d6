#pragma once
// Parsing a tool's arguments in-process, as the tools' run*Cli functions (which the tests call)
// do, under the exit-code rule of every tool (tool_errors.hpp).
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mdbrief/base/simd_level.hpp"
#include "toolkit/tool_errors.hpp"

namespace mdbrief {

// Makes app refuse a bad MDBRIEF_SIMD_LEVEL once the arguments are parsed, before any command
// runs (activeSimdLevel throws std::invalid_argument naming the variable, its value and the
// names), unless the command's --level was given: an explicit level replaces the variable.
inline void refuseBadSimdEnvironment(CLI::App& app) {
  app.parse_complete_callback([&app] {
    for (const CLI::App* command : app.get_subcommands())
      if (const CLI::Option* level = command->get_option_no_throw("--level"); level && level->count() > 0) return;
    activeSimdLevel();
  });
}

// Parses args (without the program name) into app. Empty when the tool goes on; otherwise its
// exit code: 0 after --help, 2 for bad arguments, CLI11's message written to out or err.
inline std::optional<int> parseArguments(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                                         std::ostream& err) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    return app.exit(e, out, err) == 0 ? kExitSuccess : kExitBadInput;
  }
}

// Parses args (without the program name) into app, whose chosen subcommand runs in the parse,
// and returns the exit code: what the subcommand throws is reported by runTool, a refused flag
// as "<tool>: <CLI11's message> (see --help)", --help written to out.
inline int runSubcommands(CLI::App& app, const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                          const std::string& tool) {
  const std::string prefix = tool + ": ";
  return runTool(prefix, err, [&] {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
    try {
      app.parse(reversed);
      return kExitSuccess;
    } catch (const CLI::ParseError& e) {
      if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e, out, err);
      err << prefix << oneLine(e.what()) << " (see --help)\n";
      return kExitBadInput;
    }
  });
}

// A flag's old spelling, kept out of --help: given, the parse fails (exit 2) with "<old> is now
// <replacement>" and the reason, so a script written for an older release says what to change.
inline void addRenamedFlag(CLI::App& app, const std::string& old, const std::string& replacement,
                           const std::string& reason = "") {
  app.add_option_function<std::string>(old, [old, replacement, reason](const std::string&) {
       throw CLI::ValidationError(old, "is now " + replacement + (reason.empty() ? "" : " (" + reason + ")"));
     })->group("");
}

}  // namespace mdbrief
