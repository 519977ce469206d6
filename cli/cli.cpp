#include <iostream>
#include <string>

#include "cli/commands.hpp"
#include "toolkit/command_line.hpp"
#include "toolkit/opencv_log.hpp"

namespace mdbrief::cli {

int runCli(int argc, char** argv, const std::vector<CommandAdder>& commands) {
  silenceOpenCvLogUnlessAsked();
  CLI::App app{"Binary descriptors (BRIEF, dBRIEF, mdBRIEF) for calibrated fisheye and wide-angle cameras.",
               "mdbrief"};
  app.require_subcommand(1);
  for (const auto& add : commands) add(app);
  refuseBadSimdEnvironment(app);
  return runSubcommands(app, std::vector<std::string>(argv + 1, argv + argc), std::cout, std::cerr, "mdbrief");
}

}  // namespace mdbrief::cli
