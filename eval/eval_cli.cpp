#include "eval_cli.hpp"

#include <algorithm>

#include "eval_commands.hpp"
#include "toolkit/command_line.hpp"

namespace mdbrief::eval {

void addEvalCommands(CLI::App& app) {
  addSimCommand(app);
  addEvalCommand(app);
  addPipelinesCommand(app);
  addTrackerCommand(app);
  addMapPosterPointsCommand(app);
  addRetrievalCommand(app);
  addTimingCommand(app);
  addExportUserSampleCommand(app);
  addExportRotatedViewsCommand(app);
  addHeldOutImagesCommand(app);
}

int runEvalCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"Reproduction of the mdBRIEF paper's experiments", "mdbrief-eval"};
  app.require_subcommand(1);
  addEvalCommands(app);
  refuseBadSimdEnvironment(app);
  auto oneLine = [](std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
  };
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
    return 0;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e, out, err);
    err << "mdbrief-eval: " << oneLine(e.what()) << " (see --help)\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    err << "mdbrief-eval: " << oneLine(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << "mdbrief-eval: internal error: " << oneLine(e.what()) << "\n";
    return 1;
  }
}

}  // namespace mdbrief::eval
