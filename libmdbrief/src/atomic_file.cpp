#include "mdbrief/internal/atomic_file.hpp"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace mdbrief::internal {

namespace fs = std::filesystem;

namespace {

// Unique within the process by the counter and between processes by the pid.
fs::path temporaryPath(const fs::path& target) {
  static std::atomic<unsigned long> counter{0};
  const std::string name = target.filename().string();
  const size_t dot = name.find('.', 1);  // a leading dot belongs to the name
  const std::string stem = name.substr(0, dot);
  const std::string extensions = dot == std::string::npos ? "" : name.substr(dot);
  const std::string tag = ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return target.parent_path() / ("." + stem + tag + extensions);
}

}  // namespace

void writeAtomically(const fs::path& target, const std::function<void(const fs::path& temp)>& write) {
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(target.string() + ": output folder " + folder.string() + " does not exist");
  const fs::path temp = temporaryPath(target);
  try {
    write(temp);
  } catch (...) {
    fs::remove(temp, ec);
    throw;
  }
  fs::rename(temp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw std::runtime_error(target.string() + ": cannot replace: " + ec.message());
  }
}

void writeFileAtomically(const fs::path& target, std::string_view content) {
  writeAtomically(target, [&](const fs::path& temp) {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(target.string() + ": cannot create " + temp.string());
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.close();
    if (!out) throw std::runtime_error(target.string() + ": write failed");
  });
}

}  // namespace mdbrief::internal
