#include <algorithm>
#include <iostream>
#include <string>

#include <opencv2/core.hpp>

#include "cli/commands.hpp"
#include "toolkit/command_line.hpp"
#include "toolkit/opencv_log.hpp"

namespace mdbrief::cli {
namespace {

// Library messages (OpenCV's in particular) can span lines; the CLI promises one.
std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

int runCli(int argc, char** argv, const std::vector<CommandAdder>& commands) {
  silenceOpenCvLogUnlessAsked();
  CLI::App app{"Binary descriptors (BRIEF, dBRIEF, mdBRIEF) for calibrated fisheye and wide-angle cameras.",
               "mdbrief"};
  app.require_subcommand(1);
  for (const auto& add : commands) add(app);
  refuseBadSimdEnvironment(app);
  try {
    app.parse(argc, argv);
    return 0;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help
    std::cerr << "mdbrief: " << oneLine(e.what()) << " (see --help)\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "mdbrief: " << oneLine(e.what()) << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "mdbrief: " << oneLine(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "mdbrief: internal error: " << oneLine(e.what()) << "\n";
    return 1;
  }
}

}  // namespace mdbrief::cli
