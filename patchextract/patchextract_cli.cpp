#include "patchextract/patchextract_cli.hpp"

#include <exception>
#include <map>
#include <optional>
#include <ostream>

#include <CLI/CLI.hpp>

#include "patchextract/patch_extraction.hpp"
#include "toolkit/command_line.hpp"
#include "toolkit/input_file_flag.hpp"
#include "toolkit/option_flags.hpp"
#include "toolkit/progress_reporter.hpp"
#include "toolkit/tool_errors.hpp"

namespace mdbrief::train {
namespace {

struct PatchExtractApp : CLI::App {
  PatchExtractApp() : CLI::App("Extract 32x32 training patches (HDF5) at ORB, AKAZE or SURF keypoints", "mdbrief-patchextract") {
    flags.add(*this, extractionOptionFields(), defaults);
    get_option("--images")->required();
    // Checked before any work, as every tool's input files (toolkit/input_file_flag.hpp).
    get_option("--camera")->check(inputFileCheck());
    add_option("--held-out", heldOut,
               "file of image digests never to extract from, in addition to the shipped evaluations' images")
        ->check(inputFileCheck());
    add_option("--out", out, "output HDF5 file")->required();
  }

  const ExtractionOptions defaults;  // named: a temporary trips GCC 12 -Wmaybe-uninitialized under LTO
  OptionFlags<ExtractionOptions> flags;
  std::vector<std::string> heldOut;
  std::string out;
};

}  // namespace

std::unique_ptr<CLI::App> patchExtractCommandLine() { return std::make_unique<PatchExtractApp>(); }

int runPatchExtractCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err, bool progressTty) {
  PatchExtractApp app;
  if (const std::optional<int> code = parseArguments(app, args, out, err)) return *code;
  ProgressReporter progress(out, progressTty);
  const auto extract = [&] {
    checkPatchSetOutput(app.out, {app.heldOut.begin(), app.heldOut.end()});  // before the extraction, not after it
    ExtractionOptions o = app.flags.apply(app.defaults, [](const ExtractionOptions& e) { validate(e); });
    for (const auto& file : app.heldOut) o.heldOut.merge(readHeldOutImages(file));
    ExtractionReport report;
    const PatchSet set = extractPatches(o, report, [&](const char* stage, size_t d, size_t t) {
      progress.update(stage, d, t);
    });
    progress.finish();
    writePatchSet(set, app.out);
    std::map<std::string, size_t> reasons;
    for (const auto& s : report.skipped) ++reasons[s.reason];
    out << "images: " << report.imagesFound << " found, " << report.imagesUsed << " used, " << report.skipped.size()
        << " skipped\n";
    for (const auto& [reason, n] : reasons) out << "  skipped (" << reason << "): " << n << "\n";
    out << "held out (evaluation or validation images): " << report.heldOut << " images\n";
    out << "patches: " << set.count() << " of " << o.patches << " requested, " << set.counterpartCount()
        << " counterparts -> " << app.out << " (" << report.seconds << " s)\n";
  };
  return runTool("error: ", err, [&] {
    try {
      asInputErrors(extract);
    } catch (...) {
      progress.finish();  // the message starts on a line of its own
      throw;
    }
    return kExitSuccess;
  });
}

}  // namespace mdbrief::train
