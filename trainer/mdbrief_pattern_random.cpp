// mdbrief-pattern-random: see trainer/pattern_random_cli.hpp and docs/training.md.
#include <iostream>
#include <string>
#include <vector>

#include "toolkit/file_size_signal.hpp"
#include "toolkit/opencv_log.hpp"
#include "trainer/pattern_random_cli.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  mdbrief::ignoreFileSizeSignal();
  const std::vector<std::string> args(argv + 1, argv + argc);
  return mdbrief::train::runPatternRandomCli(args, std::cout, std::cerr);
}
