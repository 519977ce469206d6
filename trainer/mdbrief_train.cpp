// mdbrief-train: see trainer/train_cli.hpp and docs/training.md.
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

#include "toolkit/file_size_signal.hpp"
#include "toolkit/opencv_log.hpp"
#include "trainer/train_cli.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  mdbrief::ignoreFileSizeSignal();
  const std::vector<std::string> args(argv + 1, argv + argc);
  return mdbrief::train::runTrainCli(args, std::cout, std::cerr, isatty(fileno(stdout)) != 0);
}
