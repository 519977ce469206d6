#pragma once
// Progress of the long stages: on a terminal a bar redrawn in place with rate and ETA, otherwise
// (logs, pipes) a plain line every 10 %. Thread-safe: update() may be called from TBB workers.
#include <chrono>
#include <cstddef>
#include <iosfwd>
#include <mutex>
#include <string>

namespace mdbrief {

class ProgressReporter {
 public:
  // tty: draw a bar (pass isatty(fileno(stderr)) for stderr).
  ProgressReporter(std::ostream& out, bool tty) : out_(out), tty_(tty) {}
  // done of total units of `stage`; a new stage name restarts the clock.
  void update(const std::string& stage, size_t done, size_t total);
  // Ends the current bar's line (terminal).
  void finish();

 private:
  std::ostream& out_;
  bool tty_;
  std::mutex mutex_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
  int lastDecile_ = -1;
  bool open_ = false;
};

}  // namespace mdbrief
