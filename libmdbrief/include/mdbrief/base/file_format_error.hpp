#pragma once
// The error a reader of the library's binary and text files (vocabulary.hpp, database.hpp,
// vocabulary_text.hpp) throws for a file it cannot use: missing, truncated, foreign, of another
// version, corrupted, or inconsistent. The message is "<path>: <problem>", so tools print it as
// is and exit 2.
#include <stdexcept>
#include <string>

namespace mdbrief {

class FileFormatError : public std::runtime_error {
 public:
  FileFormatError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem), path_(path), problem_(problem) {}
  const std::string& path() const noexcept { return path_; }
  const std::string& problem() const noexcept { return problem_; }

 private:
  std::string path_;
  std::string problem_;
};

}  // namespace mdbrief
