#include "trainer/train_cli.hpp"

#include <exception>
#include <memory>
#include <optional>
#include <ostream>

#include <CLI/CLI.hpp>

#include "mdbrief/internal/base/io/input_file.hpp"
#include "toolkit/command_line.hpp"
#include "toolkit/input_file_flag.hpp"
#include "toolkit/option_flags.hpp"
#include "toolkit/progress_reporter.hpp"
#include "toolkit/tool_errors.hpp"
#include "trainer/training.hpp"

namespace mdbrief::train {
namespace {

// The files named by --config in args (CLI11 reads them while parsing).
std::vector<std::string> configFiles(const std::vector<std::string>& args) {
  const std::string flag = "--config", prefix = flag + "=";
  std::vector<std::string> files;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == flag && i + 1 < args.size()) files.push_back(args[i + 1]);
    if (args[i].rfind(prefix, 0) == 0) files.push_back(args[i].substr(prefix.size()));
  }
  return files;
}

// The flags are TrainOptions' table; the input files among them are checked before any work,
// as every tool's (toolkit/input_file_flag.hpp).
struct TrainApp : CLI::App {
  TrainApp()
      : CLI::App("Learn a binary test set (ORB's greedy scheme, paper \"Off-line Learning\", or a selection by "
                 "matching stability) and write <out>/<name>.hpp, <name>.json and registry.hpp",
                 "mdbrief-train") {
    flags.add(*this, trainOptionFields());
    // Required: the registry it rewrites belongs to a patterns folder the user names.
    get_option("--out")->required();
    get_option("--images")->description(get_option("--images")->get_description() + "; default " +
                                        kDefaultImageFolder);
    for (const char* flag : {"--camera", "--held-out", "--patches-file"}) get_option(flag)->check(inputFileCheck());
    // CLI11 reads the file while parsing, before any check: runTrainCli checks it first.
    set_config("--config", "", "read these options from a TOML/INI file (configs/training/)")->check(inputFileCheck());
    // A misspelt key (patchs = 300) left the default in use without a word.
    allow_config_extras(CLI::config_extras_mode::error);
  }

  OptionFlags<TrainOptions> flags;
};

}  // namespace

std::unique_ptr<CLI::App> trainCommandLine() { return std::make_unique<TrainApp>(); }

int runTrainCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progressTty) {
  TrainApp app;
  // CLI11 reads a --config file without bound: /dev/zero or a FIFO hung the parse. 1 MiB is far
  // more than every option takes.
  for (const std::string& file : configFiles(args)) {
    try {
      if (const std::string problem = internal::inputFileProblem(file); !problem.empty())
        throw std::runtime_error("--config: " + file + ": " + problem);
      internal::readInputFile(file, std::uintmax_t{1} << 20, "configuration file");
    } catch (const std::runtime_error& e) {
      err << "error: " << oneLine(e.what()) << "\n";
      return kExitBadInput;
    }
  }
  if (const std::optional<int> code = parseArguments(app, args, out, err)) return *code;

  ProgressReporter progress(out, progressTty);
  return runTool("error: ", err, [&] {
    try {
      asInputErrors([&] {
        const TrainOptions options = app.flags.apply(TrainOptions{}, [](const TrainOptions& o) { validate(o); });
        const TrainResult result = train(options, [&](const char* stage, size_t done, size_t total) {
          progress.update(stage, done, total);
        });
        progress.finish();
        printTrainSummary(options, result, out);
      });
    } catch (...) {
      progress.finish();  // the message starts on a line of its own
      throw;
    }
    return kExitSuccess;
  });
}

}  // namespace mdbrief::train
