#include "mdbrief/internal/base/io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <optional>
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

// Unique within the process by the counter and between processes by the pid.
fs::path temporaryPath(const fs::path& target) {
  static std::atomic<unsigned long> counter{0};
  const NameParts parts = nameParts(target);
  const std::string tag = ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return target.parent_path() / ("." + parts.stem + tag + parts.extensions);
}

fs::path folderOf(const fs::path& target) { return target.has_parent_path() ? target.parent_path() : fs::path("."); }

std::string systemReason(int error) { return std::generic_category().message(error); }

// The pid in the name of a temporary of target, or nothing for any other name.
std::optional<pid_t> temporaryOwner(const std::string& name, const NameParts& parts) {
  const std::string prefix = "." + parts.stem + ".tmp";
  if (name.size() <= prefix.size() + parts.extensions.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - parts.extensions.size(), parts.extensions.size(), parts.extensions) != 0)
    return std::nullopt;
  const std::string tag = name.substr(prefix.size(), name.size() - prefix.size() - parts.extensions.size());
  const size_t dash = tag.find('-');
  if (dash == 0 || dash == std::string::npos || dash > 9 || dash + 1 == tag.size() ||
      tag.find_first_not_of("0123456789-") != std::string::npos || tag.find('-', dash + 1) != std::string::npos)
    return std::nullopt;
  return static_cast<pid_t>(std::stol(tag.substr(0, dash)));
}

// Temporaries of target left by killed processes. A pid that runs again (reused, or a writer in
// another pid namespace) keeps its files: only certainly orphaned ones go.
void removeOrphanedTemporaries(const fs::path& target) {
  const NameParts parts = nameParts(target);
  std::error_code ec;
  for (fs::directory_iterator it(folderOf(target), ec), end; !ec && it != end; it.increment(ec)) {
    const std::optional<pid_t> owner = temporaryOwner(it->path().filename().string(), parts);
    if (owner && *owner != ::getpid() && ::kill(*owner, 0) != 0 && errno == ESRCH) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
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

// Writes content to the new file temp, checks every step and makes it durable.
void writeDurably(const fs::path& target, const fs::path& temp, std::string_view content) {
  FileDescriptor fd(openFile(temp, O_WRONLY | O_CREAT | O_EXCL, 0666));
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

void removeQuietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove(path, ignored);
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
  const fs::path probe = temporaryPath(target);
  FileDescriptor fd(openFile(probe, O_WRONLY | O_CREAT | O_EXCL, 0666));
  if (fd.get() < 0)
    throw std::runtime_error(target.string() + ": cannot create a file in " + folderOf(target).string() + ": " +
                             systemReason(errno));
  fd.close();
  removeQuietly(probe);
}

void writeAtomically(const fs::path& target, const std::function<void(const fs::path& temp)>& write) {
  requireReplaceable(target);
  const fs::path real = resolvedTarget(target);
  removeOrphanedTemporaries(real);
  const fs::path temp = temporaryPath(real);
  try {
    write(temp);
    syncFile(target, temp);
    renameOrThrow(temp, real);
  } catch (...) {
    removeQuietly(temp);
    throw;
  }
  syncFolder(folderOf(real));
}

void writeFileAtomically(const fs::path& target, std::string_view content) {
  writeAtomically(target, [&](const fs::path& temp) { writeDurably(target, temp, content); });
}

void writeFilesAtomically(const std::vector<FileContent>& files) {
  struct Step {
    const FileContent* file;
    fs::path real;  // where the content goes (resolvedTarget)
    fs::path temp;
    std::optional<fs::path> backup;  // a second name of the previous content, for the way back
    bool renamed = false;
  };
  std::vector<Step> steps;
  for (const FileContent& file : files) {
    requireReplaceable(file.target);
    const fs::path real = resolvedTarget(file.target);
    removeOrphanedTemporaries(real);
    steps.push_back({&file, real, temporaryPath(real), std::nullopt});
  }
  const auto removeLeftovers = [&] {
    for (const Step& step : steps) {
      if (!step.renamed) removeQuietly(step.temp);
      if (step.backup) removeQuietly(*step.backup);
    }
  };
  try {
    for (const Step& step : steps) writeDurably(step.file->target, step.temp, step.file->content);
    for (Step& step : steps) {
      std::error_code ec;
      if (!fs::exists(step.real, ec)) continue;
      step.backup = temporaryPath(step.real);
      fs::create_hard_link(step.real, *step.backup, ec);
      if (ec) fs::copy_file(step.real, *step.backup, ec);  // a file system without hard links
      if (ec)
        throw std::runtime_error(step.file->target.string() + ": cannot keep the previous content: " + ec.message());
    }
    for (Step& step : steps) {
      renameOrThrow(step.temp, step.real);
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
      fs::rename(*step.backup, step.real, ec);
      if (!ec) step.backup.reset();
    }
    removeLeftovers();
    throw;
  }
  removeLeftovers();
  std::vector<fs::path> folders;
  for (const Step& step : steps) folders.push_back(folderOf(step.real));
  std::sort(folders.begin(), folders.end());
  folders.erase(std::unique(folders.begin(), folders.end()), folders.end());
  for (const fs::path& folder : folders) syncFolder(folder);
}

}  // namespace mdbrief::internal
