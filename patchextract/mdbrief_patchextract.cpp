// mdbrief-patchextract: image folders -> HDF5 patch set (patchextract/patch_set.hpp), for
// mdbrief-train --patches-file.
#include <exception>
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>
#include <unistd.h>

#include "patchextract/patch_extraction.hpp"
#include "patchextract/placement_flags.hpp"
#include "patchextract/view_change_flags.hpp"
#include "toolkit/progress_reporter.hpp"

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
  app.add_option("--counterparts", o.counterparts,
                 "changed views per image: stability data for mdbrief-train --selection stability|separation")
      ->capture_default_str();
  addViewChangeFlags(app, o.viewChange);
  PlacementFlags placement;
  addPlacementFlags(app, placement);
  std::vector<std::string> heldOut;
  app.add_option("--held-out", heldOut,
                 "file of image digests never to extract from, in addition to the shipped evaluations' images");
  app.add_option("--out", out, "output HDF5 file")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  mdbrief::ProgressReporter progress(std::cout, isatty(fileno(stdout)) != 0);
  try {
    o.detector = parseDetector(detector);
    o.placement = placementOf(placement);
    for (const auto& d : dirs) o.imageDirs.emplace_back(d);
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
  } catch (const std::exception& e) {
    progress.finish();
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
