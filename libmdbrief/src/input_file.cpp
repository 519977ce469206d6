#include "mdbrief/internal/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
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

}  // namespace mdbrief::internal
