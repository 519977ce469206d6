// mdbrief-eval: reproduces the paper's experiments (sim, eval, timing); see docs/RESULTS.md and
// scripts/reproduce.sh. Exit codes: 0 success, 2 bad usage or input, 1 internal error.
#include <algorithm>
#include <iostream>

#include "eval_commands.hpp"
#include "toolkit/opencv_log.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  CLI::App app{"Reproduction of the mdBRIEF paper's experiments", "mdbrief-eval"};
  app.require_subcommand(1);
  mdbrief::eval::addSimCommand(app);
  mdbrief::eval::addEvalCommand(app);
  mdbrief::eval::addPipelinesCommand(app);
  mdbrief::eval::addTrackerCommand(app);
  mdbrief::eval::addMapPosterPointsCommand(app);
  mdbrief::eval::addRetrievalCommand(app);
  mdbrief::eval::addTimingCommand(app);
  mdbrief::eval::addExportUserSampleCommand(app);
  mdbrief::eval::addExportRotatedViewsCommand(app);
  mdbrief::eval::addHeldOutImagesCommand(app);
  auto oneLine = [](std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
  };
  try {
    app.parse(argc, argv);
    return 0;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::cerr << "mdbrief-eval: " << oneLine(e.what()) << " (see --help)\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "mdbrief-eval: " << oneLine(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "mdbrief-eval: internal error: " << oneLine(e.what()) << "\n";
    return 1;
  }
}
