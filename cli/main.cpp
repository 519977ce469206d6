// The `mdbrief` executable: every subcommand registered here, one line each.
#include "cli/commands.hpp"

int main(int argc, char** argv) {
  using namespace mdbrief::cli;
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
