#include "trainer/train_cli.hpp"

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <ostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <sys/resource.h>

#include "mdbrief/pattern_io.hpp"
#include "patchextract/patch_extraction.hpp"
#include "trainer/candidate_tests.hpp"
#include "trainer/progress_reporter.hpp"
#include "trainer/trainer.hpp"

namespace mdbrief::train {

namespace fs = std::filesystem;

namespace {

struct TrainSettings {
  std::vector<std::string> images;
  std::string detector = "orb";
  std::string camera;
  size_t patches = 20000;
  size_t tests = 512;
  uint32_t seed = 1;
  std::string name;
  std::string out = "patterns";
  std::string patchesFile;      // reuse this HDF5 patch set instead of extracting
  std::string savePatches;      // also write the extracted patches here
  int keypointsPerImage = 1000;
  bool renderThroughCamera = false;
  bool makeDefault = false;
};

// The command as recorded in the header: every setting that changes the result, none of the
// output locations, so the same training gives the same bytes wherever it is written.
std::string recordedCommand(const TrainSettings& s) {
  std::ostringstream c;
  c << "mdbrief-train";
  if (!s.patchesFile.empty()) {
    c << " --patches-file " << s.patchesFile;
  } else {
    for (const auto& dir : s.images) c << " --images " << dir;
    c << " --detector " << s.detector;
    if (!s.camera.empty()) c << " --camera " << s.camera;
    if (s.renderThroughCamera) c << " --render-through-camera";
    c << " --patches " << s.patches << " --seed " << s.seed;
    if (s.keypointsPerImage != 1000) c << " --keypoints-per-image " << s.keypointsPerImage;
  }
  c << " --tests " << s.tests << " --name " << s.name;
  return c.str();
}

std::string fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

double peakMemoryMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;  // Linux: kilobytes
}

}  // namespace

int runTrainCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                bool progressTty) {
  TrainSettings s;
  CLI::App app{"Learn a binary test set (ORB's greedy scheme, paper \"Off-line Learning\") and "
               "write patterns/<name>.hpp, <name>.json and registry.hpp"};
  app.add_option("--images", s.images, "image folder (repeatable, recursive); default " +
                                            std::string(kDefaultImageFolder));
  app.add_option("--detector", s.detector, "orb | akaze | surf")->capture_default_str();
  app.add_option("--camera", s.camera, "calibration YAML: patches on the tangent plane (fisheye)");
  app.add_option("--patches", s.patches, "patch budget")->capture_default_str();
  app.add_option("--tests", s.tests, "tests to learn (multiple of 32)")->capture_default_str();
  app.add_option("--seed", s.seed, "seed of the patch choice")->capture_default_str();
  app.add_option("--name", s.name, "registry name (default <detector>_<perspective|fisheye>_<tests>)");
  app.add_option("--out", s.out, "existing patterns folder")->capture_default_str();
  app.add_option("--patches-file", s.patchesFile, "reuse an HDF5 patch set (mdbrief-patchextract)");
  app.add_option("--save-patches", s.savePatches, "also write the extracted patches (HDF5)");
  app.add_option("--keypoints-per-image", s.keypointsPerImage, "detector budget per image")
      ->capture_default_str();
  app.add_flag("--render-through-camera", s.renderThroughCamera,
               "use each photo as a plane seen through --camera (synthetic fisheye images)");
  app.add_flag("--make-default", s.makeDefault, "make the learned set the registry's default");

  app.set_config("--config", "", "read these options from a TOML/INI file (configs/training/)");

  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e, out, err);
    return code == 0 ? 0 : 2;
  }

  const auto wall0 = std::chrono::steady_clock::now();
  ProgressReporter progress(out, progressTty);
  try {
    if (s.tests < 32 || s.tests % 32 != 0)
      throw std::invalid_argument("--tests " + std::to_string(s.tests) +
                                  ": must be a positive multiple of 32");
    if (s.tests > kCandidateCount) throw std::invalid_argument("--tests exceeds the candidates");
    if (!fs::is_directory(s.out))
      throw std::invalid_argument(s.out + ": output folder does not exist");
    if (!s.patchesFile.empty() && (!s.images.empty() || !s.camera.empty()))
      throw std::invalid_argument("--patches-file cannot be combined with --images or --camera");
    if (!s.camera.empty() && !fs::is_regular_file(s.camera))
      throw std::invalid_argument(s.camera + ": calibration file does not exist");
    const DetectorKind detector = parseDetector(s.detector);
    if (s.name.empty())
      s.name = s.detector + (s.camera.empty() ? "_perspective_" : "_fisheye_") +
               std::to_string(s.tests);

    PatchSet patches;
    ExtractionReport report;
    if (!s.patchesFile.empty()) {
      patches = readPatchSet(s.patchesFile);
      out << "patches: " << patches.count() << " from " << s.patchesFile << "\n";
    } else {
      if (s.images.empty()) s.images.push_back(kDefaultImageFolder);
      ExtractionOptions eo;
      for (const auto& d : s.images) eo.imageDirs.emplace_back(d);
      eo.detector = detector;
      eo.patches = s.patches;
      eo.seed = s.seed;
      eo.cameraPath = s.camera;
      eo.keypointsPerImage = s.keypointsPerImage;
      eo.renderThroughCamera = s.renderThroughCamera;
      patches = extractPatches(eo, report, [&](const char* stage, size_t d, size_t t) {
        progress.update(stage, d, t);
      });
      progress.finish();
      if (!s.savePatches.empty()) writePatchSet(patches, s.savePatches);
    }
    if (patches.count() < s.tests)
      throw std::invalid_argument("only " + std::to_string(patches.count()) +
                                  " patches, fewer than the " + std::to_string(s.tests) +
                                  " requested tests");

    const PatchMatrix matrix{patches.pixels.data(), patches.count()};
    GreedyOptions go;
    go.tests = s.tests;
    const LearnedTests learned = learnTests(matrix, go, [&](const char* stage, size_t d, size_t t) {
      progress.update(stage, d, t);
    });
    progress.finish();

    PatternDocument doc;
    doc.name = s.name;
    doc.generator = recordedCommand(s);
    doc.tests = learned.tests;
    const std::string source =
        s.patchesFile.empty()
            ? std::to_string(report.imagesUsed) + " images (" + std::to_string(report.skipped.size()) +
                  " skipped)"
            : "patch file " + fs::path(s.patchesFile).filename().string();
    doc.description = "Learned (ORB greedy scheme): " + std::to_string(learned.tests.size()) +
                      " tests, " + std::to_string(patches.count()) + " " + s.detector +
                      (s.camera.empty() ? "" : " fisheye") + " patches from " + source +
                      (s.renderThroughCamera ? " rendered through the camera" : "");
    doc.provenance = {
        "Patches: " + std::to_string(patches.count()) + ", detector " + s.detector + ", camera " +
            (s.camera.empty() ? "none (perspective)" : s.camera) + ", seed " + std::to_string(s.seed) +
            ", source " + source + ".",
        "Data digest (FNV-1a 64 of the patch pixels): " + patchDigest(matrix) + ".",
        "Candidates: " + std::to_string(learned.candidates) +
            " (32x32 patch without its border, 3 < d < 29); greedy passes " +
            std::to_string(learned.passes) + ", final t_c " + fixed(learned.finalThreshold, 1) + ".",
        "Per test: mean = fraction of patches where the test is 1; max corr = highest",
        "correlation |2/P sum|t_i - t_j| - 1| with another test of this set."};
    for (size_t i = 0; i < learned.tests.size(); ++i)
      doc.testComments.push_back("mean " + fixed(learned.mean[i], 2) + " max corr " +
                                 fixed(learned.maxCorrelation[i], 2));
    writePattern(doc, s.out, {true, s.makeDefault});

    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    out << "summary\n";
    if (s.patchesFile.empty()) {
      out << "  images: " << report.imagesFound << " found, " << report.imagesUsed << " used, "
          << report.skipped.size() << " skipped\n";
      std::map<std::string, size_t> reasons;
      for (const auto& sk : report.skipped) ++reasons[sk.reason];
      for (const auto& [reason, n] : reasons) out << "    skipped (" << reason << "): " << n << "\n";
      out << "  extraction: " << fixed(report.seconds, 2) << " s, " << report.usableKeypoints
          << " usable keypoints\n";
    }
    out << "  patches: " << patches.count() << " (digest " << patchDigest(matrix) << ")\n"
        << "  candidates: " << learned.candidates << "\n"
        << "  responses: " << fixed(learned.times.evaluateSeconds, 2) << " s ("
        << fixed(learned.responseBytes / 1048576.0, 0) << " MiB bit matrix)\n"
        << "  sort: " << fixed(learned.times.sortSeconds, 2) << " s\n"
        << "  greedy: " << fixed(learned.times.greedySeconds, 2) << " s, " << learned.passes
        << " passes, final t_c " << fixed(learned.finalThreshold, 1) << "\n"
        << "  tests kept: " << learned.tests.size() << " -> " << (fs::path(s.out) / (s.name + ".hpp")).string()
        << "\n"
        << "  wall time: " << fixed(wall, 2) << " s, peak memory " << fixed(peakMemoryMiB(), 0)
        << " MiB\n";
  } catch (const std::exception& e) {
    progress.finish();
    err << "error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}

}  // namespace mdbrief::train
