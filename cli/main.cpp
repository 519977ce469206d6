// The `mdbrief` executable: every subcommand registered here, one line each.
#include "cli/commands.hpp"
#include "toolkit/file_size_signal.hpp"

int main(int argc, char** argv) {
  using namespace mdbrief::cli;
  mdbrief::ignoreFileSizeSignal();
  return runCli(argc, argv, {
                                addExtractCommand,
                                addMatchCommand,
                                addDrawCommand,
                                addCameraCommand,
                                addSimCommand,
                                addEvalCommand,
                                addBenchCommand,
                            });
}
