#include "trainer/train_cli.hpp"

#include <exception>
#include <optional>
#include <ostream>

#include <CLI/CLI.hpp>

#include "toolkit/command_line.hpp"
#include "toolkit/option_flags.hpp"
#include "toolkit/progress_reporter.hpp"
#include "trainer/training.hpp"

namespace mdbrief::train {

int runTrainCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progressTty) {
  CLI::App app{"Learn a binary test set (ORB's greedy scheme, paper \"Off-line Learning\", or a selection by "
               "matching stability) and write <out>/<name>.hpp, <name>.json and registry.hpp",
               "mdbrief-train"};
  OptionFlags<TrainOptions> flags;
  flags.add(app, trainOptionFields());
  // Required: the registry it rewrites belongs to a patterns folder the user names.
  app.get_option("--out")->required();
  app.get_option("--images")->description(app.get_option("--images")->get_description() + "; default " +
                                          kDefaultImageFolder);
  app.set_config("--config", "", "read these options from a TOML/INI file (configs/training/)");

  if (const std::optional<int> code = parseArguments(app, args, out, err)) return *code;

  ProgressReporter progress(out, progressTty);
  try {
    const TrainOptions options = flags.apply(TrainOptions{}, [](const TrainOptions& o) { validate(o); });
    const TrainResult result = train(options, [&](const char* stage, size_t done, size_t total) {
      progress.update(stage, done, total);
    });
    progress.finish();
    printTrainSummary(options, result, out);
  } catch (const std::exception& e) {
    progress.finish();
    err << "error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace mdbrief::train
