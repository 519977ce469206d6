#include "mdbrief/internal/base/io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>

namespace mdbrief::internal {

namespace fs = std::filesystem;

namespace {

struct NameParts {
  std::string stem;        // up to the first dot after the first character
  std::string extensions;  // the rest, e.g. ".yml.gz"
};

NameParts nameParts(const fs::path& target) {
  const std::string name = target.filename().string();
  const size_t dot = name.find('.', 1);  // a leading dot belongs to the name
  return {name.substr(0, dot), dot == std::string::npos ? "" : name.substr(dot)};
}

// 64 random bits per name (a per-process random start and a counter), so that a name is new in
// the folder whoever else writes there; creation with O_EXCL makes sure.
fs::path temporaryPath(const fs::path& target) {
  static const unsigned long long start = (static_cast<unsigned long long>(std::random_device{}()) << 32) ^
                                          std::random_device{}() ^ static_cast<unsigned long long>(::getpid());
  static std::atomic<unsigned long long> counter{0};
  char tag[32];
  std::snprintf(tag, sizeof tag, ".tmp-%016llx", start + 0x9e3779b97f4a7c15ULL * counter++);
  const NameParts parts = nameParts(target);
  return target.parent_path() / ("." + parts.stem + tag + parts.extensions);
}

fs::path folderOf(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

std::string systemReason(int error) { return std::generic_category().message(error); }

// Whether name is that of a temporary of target: "." + stem + ".tmp-" + 16 lowercase hex digits
// + the extensions. Other names, whatever they look like, are never touched.
bool isTemporaryName(const std::string& name, const NameParts& parts) {
  const std::string prefix = "." + parts.stem + ".tmp-";
  constexpr size_t kDigits = 16;
  if (name.size() != prefix.size() + kDigits + parts.extensions.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(prefix.size() + kDigits, std::string::npos, parts.extensions) != 0)
    return false;
  return name.substr(prefix.size(), kDigits).find_first_not_of("0123456789abcdef") == std::string::npos;
}

std::string typeName(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory: return "a folder";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::socket: return "a socket";
    default: return "not a regular file";
  }
}

// Where the new content goes: a symbolic link is written through, as editors do, so the link
// stays and its target gets the content (renaming over the link replaced it and left the target
// stale, while a link to a device was followed and refused). A dangling link is replaced.
fs::path resolvedTarget(const fs::path& target) {
  std::error_code ec;
  if (!fs::is_symlink(target, ec)) return target;
  const fs::path resolved = fs::canonical(target, ec);
  return ec ? target : resolved;
}

// The checks of checkOutputPath that need no file to be created.
void requireReplaceable(const fs::path& target) {
  const fs::path folder = folderOf(target);
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(target.string() + ": output folder " + folder.string() + " does not exist");
  const fs::file_status status = fs::status(target, ec);
  if (ec && status.type() != fs::file_type::not_found)
    throw std::runtime_error(target.string() + ": cannot check the output: " + ec.message());
  if (status.type() != fs::file_type::not_found && status.type() != fs::file_type::regular)
    throw std::runtime_error(target.string() + ": the output exists and is " + typeName(status.type()) +
                             ", not a regular file; refusing to replace it");
}

// Closes fd, once, at scope exit unless close() was called.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  FileDescriptor(FileDescriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  FileDescriptor& operator=(FileDescriptor&& other) noexcept {
    if (this != &other) {
      if (fd_ >= 0) ::close(fd_);
      fd_ = std::exchange(other.fd_, -1);
    }
    return *this;
  }
  int get() const { return fd_; }
  // The error number of a failed close, 0 on success.
  int close() {
    const int result = ::close(fd_);
    fd_ = -1;
    return result == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

int openFile(const fs::path& path, int flags, mode_t mode = 0) {
  int fd;
  do fd = ::open(path.c_str(), flags | O_CLOEXEC, mode);
  while (fd < 0 && errno == EINTR);
  return fd;
}

// Takes the lock of fd (blocking unless `wait` is false) and checks that path still names fd's
// file: a cleaner that took the lock first may have removed the name (removeStaleTemporaries).
bool lockedAndNamed(int fd, const fs::path& path, bool wait) {
  int result;
  do result = ::flock(fd, LOCK_EX | (wait ? 0 : LOCK_NB));
  while (result != 0 && errno == EINTR);
  struct stat opened {}, named {};
  return result == 0 && ::fstat(fd, &opened) == 0 && ::lstat(path.c_str(), &named) == 0 &&
         opened.st_dev == named.st_dev && opened.st_ino == named.st_ino;
}

// A file this process made under a temporary name, locked (flock) for as long as the object
// lives: the lock is what tells a live writer's temporary from one a killed writer left. The
// destructor removes the name unless release() was called (after the rename).
class LockedTemporary {
 public:
  LockedTemporary(fs::path path, FileDescriptor fd) : path_(std::move(path)), fd_(std::move(fd)) {}
  LockedTemporary(LockedTemporary&&) = default;
  LockedTemporary& operator=(LockedTemporary&&) = delete;
  ~LockedTemporary() {
    // Removed while the lock is held, so no cleaner can have taken the name meanwhile.
    if (fd_.get() >= 0 && !released_) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
  }
  const fs::path& path() const { return path_; }
  // The name is the target's now (renamed): the destructor only unlocks.
  void release() { released_ = true; }

 private:
  fs::path path_;
  FileDescriptor fd_;
  bool released_ = false;
};

// A new empty temporary of target, locked; none when the folder takes no new file (`error` says
// why).
std::optional<LockedTemporary> createTemporary(const fs::path& target, int& error) {
  for (;;) {
    fs::path temp = temporaryPath(target);
    FileDescriptor fd(openFile(temp, O_WRONLY | O_CREAT | O_EXCL, 0666));
    if (fd.get() < 0 && errno == EEXIST) continue;
    if (fd.get() < 0) {
      error = errno;
      return std::nullopt;
    }
    if (lockedAndNamed(fd.get(), temp, true)) return LockedTemporary(std::move(temp), std::move(fd));
  }
}

// createTemporary, or std::runtime_error naming target and the reason.
LockedTemporary createTemporaryOrThrow(const fs::path& target, const fs::path& real) {
  int error = 0;
  std::optional<LockedTemporary> temp = createTemporary(real, error);
  if (!temp)
    throw std::runtime_error(target.string() + ": cannot create a temporary in " + folderOf(real).string() + ": " +
                             systemReason(error));
  return std::move(*temp);
}

// A second name (a hard link) of the existing file `real` under a temporary name, locked as
// createTemporary's; the previous content for the way back of writeFilesAtomically.
LockedTemporary linkTemporary(const fs::path& real, const fs::path& target) {
  for (;;) {
    fs::path link = temporaryPath(real);
    std::error_code ec;
    fs::create_hard_link(real, link, ec);
    if (ec == std::errc::file_exists) continue;
    if (ec) fs::copy_file(real, link, ec);  // a file system without hard links
    if (ec) throw std::runtime_error(target.string() + ": cannot keep the previous content: " + ec.message());
    FileDescriptor fd(openFile(link, O_RDONLY | O_NOFOLLOW));
    if (fd.get() >= 0 && lockedAndNamed(fd.get(), link, true)) return LockedTemporary(std::move(link), std::move(fd));
  }
}

// Temporaries of target whose writer is gone: their lock is free (the kernel drops a killed
// process's locks, whatever its pid namespace). Files named otherwise, files of other users and
// temporaries whose writer holds the lock stay.
void removeStaleTemporaries(const fs::path& target) {
  const NameParts parts = nameParts(target);
  std::error_code ec;
  for (fs::directory_iterator it(folderOf(target), ec), end; !ec && it != end; it.increment(ec)) {
    if (!isTemporaryName(it->path().filename().string(), parts)) continue;
    FileDescriptor fd(openFile(it->path(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK));
    struct stat info {};
    if (fd.get() < 0 || ::fstat(fd.get(), &info) != 0 || !S_ISREG(info.st_mode) || info.st_uid != ::geteuid())
      continue;
    if (lockedAndNamed(fd.get(), it->path(), false)) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

// Writes content to the temporary temp (createTemporary's), checks every step and makes it durable.
void writeDurably(const fs::path& target, const fs::path& temp, std::string_view content) {
  FileDescriptor fd(openFile(temp, O_WRONLY | O_TRUNC));
  if (fd.get() < 0)
    throw std::runtime_error(target.string() + ": cannot create " + temp.string() + ": " + systemReason(errno));
  for (size_t done = 0; done < content.size();) {
    const ssize_t n = ::write(fd.get(), content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw std::runtime_error(target.string() + ": write failed after " + std::to_string(done) + " of " +
                               std::to_string(content.size()) + " bytes: " + systemReason(n < 0 ? errno : EIO));
    done += static_cast<size_t>(n);
  }
  if (::fsync(fd.get()) != 0) throw std::runtime_error(target.string() + ": fsync failed: " + systemReason(errno));
  if (const int error = fd.close(); error != 0)
    throw std::runtime_error(target.string() + ": closing the file failed: " + systemReason(error));
}

// fsync of a file another writer has closed (a read-only descriptor is enough on Linux).
void syncFile(const fs::path& target, const fs::path& temp) {
  FileDescriptor fd(openFile(temp, O_RDONLY));
  if (fd.get() < 0)
    throw std::runtime_error(target.string() + ": the writer left no file " + temp.string() + ": " +
                             systemReason(errno));
  if (::fsync(fd.get()) != 0) throw std::runtime_error(target.string() + ": fsync failed: " + systemReason(errno));
}

// Makes the renames in folder durable. Best effort: a failure changes nothing that is visible.
void syncFolder(const fs::path& folder) {
  FileDescriptor fd(openFile(folder, O_RDONLY | O_DIRECTORY));
  if (fd.get() >= 0) ::fsync(fd.get());
}

void renameOrThrow(const fs::path& temp, const fs::path& target) {
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) throw std::runtime_error(target.string() + ": cannot replace: " + ec.message());
}

// Who a path is: an existing file by device and inode (after following links), a file still to
// be made by its folder's device and inode and its name; none when even the folder cannot be
// reached (the writer reports that).
struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  std::string name;  // empty for an existing file
  bool operator==(const FileIdentity& other) const {
    return device == other.device && inode == other.inode && name == other.name;
  }
};

std::optional<FileIdentity> identityOf(const fs::path& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0) return FileIdentity{info.st_dev, info.st_ino, ""};
  if (errno != ENOENT || ::stat(folderOf(path).c_str(), &info) != 0) return std::nullopt;
  return FileIdentity{info.st_dev, info.st_ino, path.filename().string()};
}

}  // namespace

void checkOutputsApart(const std::vector<fs::path>& inputs, const std::vector<fs::path>& outputs) {
  std::vector<std::pair<FileIdentity, const fs::path*>> seen;  // the inputs, then the outputs so far
  for (const fs::path& input : inputs)
    if (const auto id = input.empty() ? std::nullopt : identityOf(input)) seen.emplace_back(*id, &input);
  const size_t inputCount = seen.size();
  for (const fs::path& output : outputs) {
    const auto id = output.empty() ? std::nullopt : identityOf(output);
    if (!id) continue;
    for (size_t i = 0; i < seen.size(); ++i) {
      if (!(seen[i].first == *id)) continue;
      if (i < inputCount)
        throw std::runtime_error(output.string() + ": the output is the same file as the input " +
                                 seen[i].second->string() + "; refusing to overwrite an input");
      throw std::runtime_error(output.string() + ": the output is the same file as the output " +
                               seen[i].second->string() + "; one would overwrite the other");
    }
    seen.emplace_back(*id, &output);
  }
}

void checkOutputPath(const fs::path& target) {
  requireReplaceable(target);
  int error = 0;
  if (!createTemporary(target, error))
    throw std::runtime_error(target.string() + ": cannot create a file in " + folderOf(target).string() + ": " +
                             systemReason(error));
}

void writeAtomically(const fs::path& target, const std::function<void(const fs::path& temp)>& write) {
  requireReplaceable(target);
  const fs::path real = resolvedTarget(target);
  removeStaleTemporaries(real);
  LockedTemporary temp = createTemporaryOrThrow(target, real);
  write(temp.path());
  syncFile(target, temp.path());
  renameOrThrow(temp.path(), real);
  temp.release();
  syncFolder(folderOf(real));
}

void writeFileAtomically(const fs::path& target, std::string_view content) {
  writeAtomically(target, [&](const fs::path& temp) { writeDurably(target, temp, content); });
}

void writeFilesAtomically(const std::vector<FileContent>& files) {
  struct Step {
    const FileContent* file;
    fs::path real;  // where the content goes (resolvedTarget)
    LockedTemporary temp;
    std::optional<LockedTemporary> backup;  // a second name of the previous content, for the way back
    bool renamed = false;
  };
  std::vector<Step> steps;
  steps.reserve(files.size());
  for (const FileContent& file : files) {
    requireReplaceable(file.target);
    fs::path real = resolvedTarget(file.target);
    removeStaleTemporaries(real);
    LockedTemporary temp = createTemporaryOrThrow(file.target, real);
    steps.push_back({&file, std::move(real), std::move(temp), std::nullopt});
  }
  // The temporaries and backups not renamed go with `steps` (LockedTemporary's destructor).
  try {
    for (const Step& step : steps) writeDurably(step.file->target, step.temp.path(), step.file->content);
    for (Step& step : steps) {
      std::error_code ec;
      if (fs::exists(step.real, ec)) step.backup.emplace(linkTemporary(step.real, step.file->target));
    }
    for (Step& step : steps) {
      renameOrThrow(step.temp.path(), step.real);
      step.temp.release();
      step.renamed = true;
    }
  } catch (...) {
    for (Step& step : steps) {
      if (!step.renamed) continue;
      std::error_code ec;
      if (!step.backup) {
        fs::remove(step.real, ec);
        continue;
      }
      fs::rename(step.backup->path(), step.real, ec);
      if (!ec) step.backup->release();
    }
    throw;
  }
  std::vector<fs::path> folders;
  for (const Step& step : steps) folders.push_back(folderOf(step.real));
  std::sort(folders.begin(), folders.end());
  folders.erase(std::unique(folders.begin(), folders.end()), folders.end());
  for (const fs::path& folder : folders) syncFolder(folder);
}

}  // namespace mdbrief::internal
