// mdbrief-patchextract: see patchextract/patchextract_cli.hpp and docs/training.md.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

#include "patchextract/patchextract_cli.hpp"
#include "toolkit/file_size_signal.hpp"
#include "toolkit/opencv_log.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  mdbrief::ignoreFileSizeSignal();
  const std::vector<std::string> args(argv + 1, argv + argc);
  return mdbrief::train::runPatchExtractCli(args, std::cout, std::cerr, isatty(fileno(stdout)) != 0);
}
