#include "eval_cli.hpp"

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
  return runSubcommands(app, args, out, err, "mdbrief-eval");
}

}  // namespace mdbrief::eval
