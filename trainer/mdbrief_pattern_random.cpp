// mdbrief-pattern-random: writes the random BRIEF (G II) test set as a pattern header, its JSON
// copy and the regenerated registry (see trainer/random_pattern.hpp for the distribution). Exit
// codes by the tools' rule (toolkit/tool_errors.hpp).
#include <filesystem>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "toolkit/file_size_signal.hpp"
#include "toolkit/opencv_log.hpp"
#include "toolkit/tool_errors.hpp"
#include "trainer/pattern_writer.hpp"
#include "trainer/random_pattern.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  mdbrief::ignoreFileSizeSignal();
  mdbrief::train::RandomPatternOptions options;
  std::filesystem::path out = "patterns";
  bool makeDefault = false;
  CLI::App app{"Write the random Gaussian BRIEF test set (G II) as a pattern header + JSON"};
  app.add_option("--tests", options.tests, "number of tests, a multiple of 32")
      ->check(CLI::Range(32, 4096))
      ->capture_default_str();
  app.add_option("--seed", options.seed, "std::mt19937 seed")->capture_default_str();
  app.add_option("--name", options.name, "registry name (default brief_random_<tests>)");
  app.add_option("--out", out, "existing patterns folder")->capture_default_str();
  app.add_flag("--make-default", makeDefault, "make this set the registry's default");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? mdbrief::kExitSuccess : mdbrief::kExitBadInput;
  }
  return mdbrief::runTool("error: ", std::cerr, [&] {
    if (options.tests % 32 != 0)
      throw mdbrief::InputError("--tests " + std::to_string(options.tests) + " is not a multiple of 32");
    mdbrief::asInputErrors([&] {
      const auto doc = mdbrief::train::randomPatternDocument(options);
      mdbrief::writePattern(doc, out, {true, makeDefault});
      std::cout << "wrote " << (out / (doc.name + ".hpp")).string() << " (" << doc.tests.size()
                << " tests), " << (out / (doc.name + ".json")).string() << " and "
                << (out / "registry.hpp").string() << "\n";
    });
    return mdbrief::kExitSuccess;
  });
}
