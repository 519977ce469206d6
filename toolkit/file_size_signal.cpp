#include "toolkit/file_size_signal.hpp"

#include <csignal>

namespace mdbrief {

void ignoreFileSizeSignal() { std::signal(SIGXFSZ, SIG_IGN); }

}  // namespace mdbrief
