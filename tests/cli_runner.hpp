#pragma once
// Running the `mdbrief` command line in-process (cli::runCli) with its output captured, for the
// command-line tests.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/commands.hpp"

namespace mdbrief::testing {

struct CliResult {
  int code = -1;
  std::string out;
  std::string err;
};

inline CliResult runMdbrief(std::vector<std::string> args) {
  args.insert(args.begin(), "mdbrief");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  CliResult r;
  r.code = cli::runCli(static_cast<int>(argv.size()), argv.data(),
                       {cli::addExtractCommand, cli::addMatchCommand, cli::addDrawCommand, cli::addCameraCommand,
                        cli::addBenchCommand});
  r.err = ::testing::internal::GetCapturedStderr();
  r.out = ::testing::internal::GetCapturedStdout();
  return r;
}

// Exit code 2 and a message that names `what`, ending the output with one line.
inline void expectOneLineNaming(const CliResult& r, const std::string& what) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << "message does not name '" << what << "': " << r.err;
  // One line (OpenCV may log its own warnings before; ours is the last line).
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.back(), '\n');
}

}  // namespace mdbrief::testing
