#include "mdbrief/internal/base/io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace mdbrief::internal {

std::string inputFileProblem(const std::filesystem::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    switch (errno) {
      case ENOENT: return "no such file";
      case ENOTDIR: return "no such file (a part of the path is not a folder)";
      case ELOOP: return "too many levels of symbolic links (a symlink loop?)";
      default: return "cannot access: " + std::generic_category().message(errno);
    }
  }
  if (S_ISDIR(info.st_mode)) return "is a folder, not a file";
  if (S_ISFIFO(info.st_mode)) return "is a FIFO, not a regular file";
  if (S_ISCHR(info.st_mode)) return "is a character device, not a regular file";
  if (S_ISBLK(info.st_mode)) return "is a block device, not a regular file";
  if (S_ISSOCK(info.st_mode)) return "is a socket, not a regular file";
  if (!S_ISREG(info.st_mode)) return "is not a regular file";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return "cannot open: " + std::generic_category().message(errno);
  ::close(fd);
  return "";
}

std::string readInputFile(const std::filesystem::path& path, std::uintmax_t maxBytes, const std::string& kind) {
  const auto fail = [&](const std::string& problem) {
    return std::runtime_error(path.string() + ": " + kind + ": " + problem);
  };
  if (const std::string problem = inputFileProblem(path); !problem.empty()) throw fail(problem);
  const auto tooLarge = [&](std::uintmax_t bytes) {
    return fail(std::to_string(bytes) + " bytes, over the " + std::to_string(maxBytes >> 20) + " MiB a " + kind +
                " may have");
  };
  std::error_code ec;
  if (const std::uintmax_t bytes = std::filesystem::file_size(path, ec); !ec && bytes > maxBytes) throw tooLarge(bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fail("cannot open");
  // Bounded again while reading: the file may have grown since its size was taken.
  std::string bytes;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    bytes.append(chunk, static_cast<size_t>(in.gcount()));
    if (bytes.size() > maxBytes) throw tooLarge(bytes.size());
  }
  if (in.bad()) throw fail("cannot read");
  return bytes;
}

}  // namespace mdbrief::internal
