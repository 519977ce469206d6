// mdbrief-patchextract: image folders -> HDF5 patch set (patchextract/patch_set.hpp), for
// mdbrief-train --patches-file. Exit codes by the tools' rule (toolkit/tool_errors.hpp).
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "patchextract/patch_extraction.hpp"
#include "toolkit/file_size_signal.hpp"
#include "toolkit/opencv_log.hpp"
#include "toolkit/option_flags.hpp"
#include "toolkit/progress_reporter.hpp"
#include "toolkit/tool_errors.hpp"

int main(int argc, char** argv) {
  mdbrief::silenceOpenCvLogUnlessAsked();
  mdbrief::ignoreFileSizeSignal();
  using namespace mdbrief::train;
  std::string out;
  std::vector<std::string> heldOut;
  mdbrief::OptionFlags<ExtractionOptions> flags;
  CLI::App app{"Extract 32x32 training patches (HDF5) at ORB, AKAZE or SURF keypoints", "mdbrief-patchextract"};
  const ExtractionOptions defaults;  // named: a temporary trips GCC 12 -Wmaybe-uninitialized under LTO
  flags.add(app, extractionOptionFields(), defaults);
  app.get_option("--images")->required();
  app.add_option("--held-out", heldOut,
                 "file of image digests never to extract from, in addition to the shipped evaluations' images");
  app.add_option("--out", out, "output HDF5 file")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? mdbrief::kExitSuccess : mdbrief::kExitBadInput;
  }
  mdbrief::ProgressReporter progress(std::cout, isatty(fileno(stdout)) != 0);
  const auto extract = [&] {
    checkPatchSetOutput(out, {heldOut.begin(), heldOut.end()});  // before the extraction, not after it
    ExtractionOptions o = flags.apply(defaults, [](const ExtractionOptions& e) { validate(e); });
    for (const auto& file : heldOut) o.heldOut.merge(readHeldOutImages(file));
    ExtractionReport report;
    const PatchSet set = extractPatches(o, report, [&](const char* stage, size_t d, size_t t) {
      progress.update(stage, d, t);
    });
    progress.finish();
    writePatchSet(set, out);
    std::map<std::string, size_t> reasons;
    for (const auto& s : report.skipped) ++reasons[s.reason];
    std::cout << "images: " << report.imagesFound << " found, " << report.imagesUsed << " used, "
              << report.skipped.size() << " skipped\n";
    for (const auto& [reason, n] : reasons) std::cout << "  skipped (" << reason << "): " << n << "\n";
    std::cout << "held out (evaluation or validation images): " << report.heldOut << " images\n";
    std::cout << "patches: " << set.count() << " of " << o.patches << " requested, " << set.counterpartCount()
              << " counterparts -> " << out
              << " (" << report.seconds << " s)\n";
  };
  return mdbrief::runTool("error: ", std::cerr, [&] {
    try {
      mdbrief::asInputErrors(extract);
    } catch (...) {
      progress.finish();  // the message starts on a line of its own
      throw;
    }
    return mdbrief::kExitSuccess;
  });
}
