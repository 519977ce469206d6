// mdbrief-patchextract: image folders -> HDF5 patch set (patchextract/patch_set.hpp), for
// mdbrief-train --patches-file.
#include <exception>
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "patchextract/patch_extraction.hpp"
#include "trainer/progress_reporter.hpp"

int main(int argc, char** argv) {
  using namespace mdbrief::train;
  std::vector<std::string> dirs;
  std::string detector = "orb", out;
  ExtractionOptions o;
  CLI::App app{"Extract 32x32 training patches (HDF5) at ORB, AKAZE or SURF keypoints"};
  app.add_option("--images", dirs, "image folder (repeatable, recursive)")->required();
  app.add_option("--detector", detector, "orb | akaze | surf")->capture_default_str();
  app.add_option("--camera", o.cameraPath, "calibration YAML: patches on the tangent plane");
  app.add_option("--patches", o.patches, "patch budget")->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the patch choice")->capture_default_str();
  app.add_option("--keypoints-per-image", o.keypointsPerImage, "detector budget per image")
      ->capture_default_str();
  app.add_flag("--render-through-camera", o.renderThroughCamera,
               "use each photo as a plane seen through --camera (synthetic fisheye images)");
  app.add_option("--out", out, "output HDF5 file")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  ProgressReporter progress(std::cout, isatty(fileno(stdout)) != 0);
  try {
    o.detector = parseDetector(detector);
    for (const auto& d : dirs) o.imageDirs.emplace_back(d);
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
    std::cout << "patches: " << set.count() << " of " << o.patches << " requested -> " << out
              << " (" << report.seconds << " s)\n";
  } catch (const std::exception& e) {
    progress.finish();
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
