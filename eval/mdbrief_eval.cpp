// mdbrief-eval: reproduces the paper's experiments (sim, eval, timing); see docs/RESULTS.md and
// scripts/reproduce.sh. Exit codes: 0 success, 2 bad usage or input, 1 internal error
// (toolkit/tool_errors.hpp).
#include <iostream>

#include "eval_cli.hpp"
#include "toolkit/file_size_signal.hpp"
#include "toolkit/opencv_log.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  mdbrief::ignoreFileSizeSignal();
  return mdbrief::eval::runEvalCli(std::vector<std::string>(argv + 1, argv + argc), std::cout, std::cerr);
}
