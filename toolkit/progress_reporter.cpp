#include "toolkit/progress_reporter.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace mdbrief {

void ProgressReporter::update(const std::string& stage, size_t done, size_t total) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (stage != stage_) {
    if (open_ && tty_) out_ << "\n";
    stage_ = stage;
    start_ = now;
    lastDraw_ = now - std::chrono::seconds(1);
    lastDecile_ = -1;
    open_ = true;
  }
  if (total == 0) return;
  const double fraction = std::min(1.0, double(done) / double(total));
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  const double eta = rate > 0 ? (total - std::min(done, total)) / rate : 0.0;
  char line[160];
  if (tty_) {
    // Redrawing more often than 10 times a second only costs time.
    if (done < total && now - lastDraw_ < std::chrono::milliseconds(100)) return;
    lastDraw_ = now;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::snprintf(line, sizeof line, "\r%-9s [%s%s] %5.1f%% %zu/%zu  %.0f/s  ETA %.0fs   ",
                  stage.c_str(), std::string(filled, '#').c_str(),
                  std::string(kWidth - filled, '.').c_str(), 100 * fraction, done, total, rate, eta);
    out_ << line << std::flush;
  } else {
    const int decile = static_cast<int>(fraction * 10);
    if (decile <= lastDecile_) return;
    lastDecile_ = decile;
    std::snprintf(line, sizeof line, "%s: %3d%% (%zu/%zu, %.0f/s, ETA %.0fs)\n", stage.c_str(),
                  decile * 10, done, total, rate, eta);
    out_ << line << std::flush;
  }
}

void ProgressReporter::finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (open_ && tty_) out_ << "\n" << std::flush;
  open_ = false;
  stage_.clear();
}

}  // namespace mdbrief
