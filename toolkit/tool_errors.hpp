#pragma once
// The error type and the exit-code rule of every tool (mdbrief, mdbrief-eval, mdbrief-train,
// mdbrief-train-vocabulary, mdbrief-patchextract, mdbrief-pattern-random):
//   0  success, and --help;
//   2  bad usage or bad input, which the user can correct: a flag CLI11 refuses, an InputError,
//      or any std::invalid_argument (the library's refusal of an argument). The message is one
//      line and starts with the flag or file at fault;
//   1  an internal error: any other exception (a bug, memory exhausted, OpenCV failing on input
//      that was checked). The message says "internal error".
// The library reports a file it cannot read or write as a std::runtime_error naming the file;
// where a tool reads or writes the user's files it turns those into InputErrors (asInputErrors).
#include <algorithm>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace mdbrief {

// Bad input detected by a tool: a missing or unreadable file, an inconsistent argument.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

inline constexpr int kExitSuccess = 0;
inline constexpr int kExitInternalError = 1;
inline constexpr int kExitBadInput = 2;

// Library messages (OpenCV's in particular) can span lines; the tools promise one.
inline std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Runs `body` (which returns an exit code) under the rule above: an exception's message goes to
// err after `prefix` (e.g. "mdbrief: "), and its kind gives the exit code.
template <typename Body>
int runTool(std::string_view prefix, std::ostream& err, Body&& body) {
  try {
    return body();
  } catch (const std::invalid_argument& e) {  // InputError among them
    err << prefix << oneLine(e.what()) << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    err << prefix << "internal error: " << oneLine(e.what()) << "\n";
    return kExitInternalError;
  }
}

// Runs `body`, turning the library's file errors (std::runtime_error naming the file) into
// InputErrors, so that the tool exits 2. OpenCV's own failures (cv::Exception, not a
// runtime_error) stay internal errors: the inputs were checked before they reached OpenCV.
template <typename Body>
void asInputErrors(Body&& body) {
  try {
    body();
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

}  // namespace mdbrief
