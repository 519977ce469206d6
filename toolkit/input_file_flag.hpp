#pragma once
// The one check every tool's input-file flag goes through, at parse time: before any work, a
// folder, a FIFO, a device (/dev/zero) or a missing file is a parse error naming the flag and the
// file (exit 2), never a read without bound or an open that blocks (issue 45: `bench --image`
// read /dev/zero until memory ran out and blocked on a FIFO). Header only, like option_flags.hpp:
// its users link CLI11 and mdbrief_internal. The tests find the flags by the validator's name
// (kInputFileCheck) and feed each of them bad files.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "mdbrief/internal/base/io/input_file.hpp"

namespace mdbrief {

inline constexpr const char* kInputFileCheck = "INPUT_FILE";

// pathOf picks the file out of a value that says more, e.g. "name=file#id"; by default the value
// is the path.
inline CLI::Validator inputFileCheck(std::function<std::string(const std::string&)> pathOf = {}) {
  return CLI::Validator(
      [pathOf](std::string& value) -> std::string {
        const std::string path = pathOf ? pathOf(value) : value;
        const std::string problem = internal::inputFileProblem(path);
        return problem.empty() ? "" : path + ": " + problem;
      },
      "", kInputFileCheck);
}

}  // namespace mdbrief
