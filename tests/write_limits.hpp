#pragma once
// Making writes fail on purpose, for the tests of what a failed write leaves behind: a file size
// limit (RLIMIT_FSIZE, any user) and a small tmpfs that fills up (needs root and permission to
// mount; tests skip with the reason otherwise).
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace mdbrief::testing {

// While alive, no file of this process may grow beyond `bytes`: a write past it fails with
// EFBIG ("File too large") instead of killing the process with SIGXFSZ, as under
// `bash -c "trap '' XFSZ; ulimit -f ..."`.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &previous_);
    previousHandler_ = ::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = previous_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &previous_);
    ::signal(SIGXFSZ, previousHandler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit previous_{};
  sighandler_t previousHandler_;
};

// A tmpfs of `bytes` mounted on a fresh folder for the object's lifetime. mounted() is false
// (and skipReason() says why) when this process may not mount.
class SmallTmpfs {
 public:
  SmallTmpfs(const std::string& tag, size_t bytes)
      : path(std::filesystem::temp_directory_path() / ("mdbrief_test_tmpfs_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
    if (::geteuid() != 0) {
      reason_ = "not root: cannot mount a small tmpfs";
      return;
    }
    const std::string options = "size=" + std::to_string(bytes);
    if (::mount("tmpfs", path.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) != 0)
      reason_ = std::string("mounting a tmpfs is not permitted here: ") + std::strerror(errno);
    else
      mounted_ = true;
  }
  ~SmallTmpfs() {
    if (mounted_) ::umount2(path.c_str(), MNT_DETACH);
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  SmallTmpfs(const SmallTmpfs&) = delete;
  SmallTmpfs& operator=(const SmallTmpfs&) = delete;

  bool mounted() const { return mounted_; }
  const std::string& skipReason() const { return reason_; }

  // Takes all the space that is still free, so the next write that needs a new block fails
  // with ENOSPC.
  void fill() const {
    std::ofstream filler(path / "filler", std::ios::binary);
    const std::vector<char> block(4096, 'f');
    while (filler.write(block.data(), static_cast<std::streamsize>(block.size())) && filler.flush()) {
    }
  }

  const std::filesystem::path path;

 private:
  bool mounted_ = false;
  std::string reason_;
};

// The names in dir that look like temporaries of the atomic writer (".<stem>.tmp-<16 hex digits>...").
inline std::vector<std::string> temporaryFiles(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name[0] == '.' && name.find(".tmp") != std::string::npos) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace mdbrief::testing
