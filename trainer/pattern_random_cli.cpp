#include "trainer/pattern_random_cli.hpp"

#include <exception>
#include <filesystem>
#include <optional>
#include <ostream>

#include <CLI/CLI.hpp>

#include "toolkit/command_line.hpp"
#include "toolkit/tool_errors.hpp"
#include "trainer/pattern_writer.hpp"
#include "trainer/random_pattern.hpp"

namespace mdbrief::train {
namespace {

struct PatternRandomApp : CLI::App {
  PatternRandomApp()
      : CLI::App("Write the random Gaussian BRIEF test set (G II) as a pattern header + JSON", "mdbrief-pattern-random") {
    add_option("--tests", options.tests, "number of tests, a multiple of 32")
        ->check(CLI::Range(32, 4096))
        ->capture_default_str();
    add_option("--seed", options.seed, "std::mt19937 seed")->capture_default_str();
    add_option("--name", options.name, "registry name (default brief_random_<tests>)");
    add_option("--out", out, "existing patterns folder")->capture_default_str();
    add_flag("--make-default", makeDefault, "make this set the registry's default");
  }

  RandomPatternOptions options;
  std::filesystem::path out = "patterns";
  bool makeDefault = false;
};

}  // namespace

std::unique_ptr<CLI::App> patternRandomCommandLine() { return std::make_unique<PatternRandomApp>(); }

int runPatternRandomCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  PatternRandomApp app;
  if (const std::optional<int> code = parseArguments(app, args, out, err)) return *code;
  if (app.options.tests % 32 != 0) {
    err << "error: --tests " << app.options.tests << " is not a multiple of 32\n";
    return kExitBadInput;
  }
  return runTool("error: ", err, [&] {
    asInputErrors([&] {
      const auto doc = randomPatternDocument(app.options);
      writePattern(doc, app.out, {true, app.makeDefault});
      out << "wrote " << (app.out / (doc.name + ".hpp")).string() << " (" << doc.tests.size() << " tests), "
          << (app.out / (doc.name + ".json")).string() << " and " << (app.out / "registry.hpp").string() << "\n";
    });
    return kExitSuccess;
  });
}

}  // namespace mdbrief::train
