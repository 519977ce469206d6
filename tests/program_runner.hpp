#pragma once
// Running a built program in a child process with a time limit, for the tests of what must never
// hang or run without bound (a FIFO or /dev/zero as input) and of what the environment changes.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace mdbrief::testing {

struct ProgramRun {
  int code = -1;  // -1: killed after the time limit
  std::string out, err;
};

// Runs program with args and environ plus `environment` ("NAME=value", replacing), killed after
// `limit`. Its address space is capped (but under AddressSanitizer, whose shadow memory needs
// terabytes of it), so that a reader without bound fails instead of filling the machine's memory.
inline ProgramRun runProgram(const std::string& program, const std::vector<std::string>& args,
                             std::chrono::seconds limit, const std::vector<std::string>& environment = {}) {
  const std::filesystem::path errFile =
      std::filesystem::temp_directory_path() / ("program_runner_err_" + std::to_string(::getpid()));
  const std::filesystem::path outFile =
      std::filesystem::temp_directory_path() / ("program_runner_out_" + std::to_string(::getpid()));
  std::vector<std::string> all{program};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> variables(environment);
  for (char** e = environ; *e; ++e) {
    const std::string variable = *e;
    const std::string name = variable.substr(0, variable.find('=') + 1);
    if (std::none_of(environment.begin(), environment.end(), [&](const std::string& v) { return v.rfind(name, 0) == 0; }))
      variables.push_back(variable);
  }
  std::vector<char*> envp;
  for (auto& v : variables) envp.push_back(v.data());
  envp.push_back(nullptr);
  ProgramRun run;
  const pid_t child = ::fork();
  if (child == 0) {  // only async-signal-safe calls until exec
#ifndef __SANITIZE_ADDRESS__
    const rlimit cap{rlim_t{2} << 30, rlim_t{2} << 30};
    ::setrlimit(RLIMIT_AS, &cap);
#endif
    const int null = ::open("/dev/null", O_RDWR);
    const int out = ::open(outFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err = ::open(errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (null < 0 || out < 0 || err < 0) ::_exit(127);
    ::dup2(null, 0);
    ::dup2(out, 1);
    ::dup2(err, 2);
    ::execve(program.c_str(), argv.data(), envp.data());
    ::_exit(127);
  }
  if (child < 0) {
    run.err = "cannot start " + program;
    return run;
  }
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (::waitpid(child, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(child, SIGKILL);
      ::waitpid(child, &status, 0);
      run.err = "killed after the time limit";
      std::filesystem::remove(errFile);
      std::filesystem::remove(outFile);
      return run;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::ifstream err(errFile), out(outFile);
  run.err.assign(std::istreambuf_iterator<char>(err), std::istreambuf_iterator<char>());
  run.out.assign(std::istreambuf_iterator<char>(out), std::istreambuf_iterator<char>());
  std::filesystem::remove(errFile);
  std::filesystem::remove(outFile);
  return run;
}

}  // namespace mdbrief::testing
