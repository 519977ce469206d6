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

#include "toolkit/pattern_writer.hpp"
#include "patchextract/patch_extraction.hpp"
#include "patchextract/placement_flags.hpp"
#include "patchextract/view_change_flags.hpp"
#include "trainer/candidate_tests.hpp"
#include "toolkit/progress_reporter.hpp"
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
  std::string selection = "paper";
  int counterparts = -1;        // -1: 1 when the criterion needs pairs, else 0
  ViewChangeOptions viewChange;
  PlacementFlags placement;
  GreedyOptions greedy;
  std::vector<std::string> heldOut;  // extra held-out lists
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
    for (const auto& file : s.heldOut) c << " --held-out " << file;
    c << " --detector " << s.detector;
    if (!s.camera.empty()) c << " --camera " << s.camera;
    if (s.renderThroughCamera) c << " --render-through-camera";
    c << " --patches " << s.patches << " --seed " << s.seed;
    if (s.keypointsPerImage != 1000) c << " --keypoints-per-image " << s.keypointsPerImage;
    const PlacementFlags p;
    if (s.placement.form != p.form) c << " --form " << s.placement.form;
    if (s.placement.orientation != p.orientation) c << " --orientation " << s.placement.orientation;
    if (s.counterparts > 0) {
      const ViewChangeOptions d;
      const auto& v = s.viewChange;
      c << " --counterparts " << s.counterparts;
      if (v.maxTiltDeg != d.maxTiltDeg) c << " --view-tilt " << v.maxTiltDeg;
      if (v.maxRollDeg != d.maxRollDeg) c << " --view-roll " << v.maxRollDeg;
      if (v.maxZoom != d.maxZoom) c << " --view-zoom " << v.maxZoom;
      if (v.maxBlurSigma != d.maxBlurSigma) c << " --view-blur " << v.maxBlurSigma;
      if (v.maxNoiseSigma != d.maxNoiseSigma) c << " --view-noise " << v.maxNoiseSigma;
    }
  }
  const GreedyOptions g;
  if (s.greedy.startThreshold != g.startThreshold) c << " --correlation-start " << s.greedy.startThreshold;
  if (s.greedy.thresholdStep != g.thresholdStep) c << " --correlation-step " << s.greedy.thresholdStep;
  c << " --selection " << s.selection << " --tests " << s.tests << " --name " << s.name;
  return c.str();
}

std::string fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// A setting of the extraction as the patch set records it, or `missing`.
std::string patchAttribute(const PatchSet& patches, const std::string& key, const std::string& missing) {
  for (const auto& [k, value] : patches.attributes)
    if (k == key) return value;
  return missing;
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
  app.add_option("--selection", s.selection,
                 "ranking of the greedy selection: paper (variance, the paper's scheme) | stability "
                 "(2 var - flip rate, then the paper's greedy) | separation (forward selection by the Fisher-like "
                 "separation of matching and non-matching distances); see docs/training.md")
      ->capture_default_str();
  app.add_option("--held-out", s.heldOut,
                 "file of image digests never to train on (\"<digest> <label>\" lines), in addition to the "
                 "shipped evaluations' images (configs/held-out-images.txt, always left out)");
  app.add_option("--correlation-start", s.greedy.startThreshold, "greedy: t_c of the first pass (paper: 0.2)")
      ->capture_default_str();
  app.add_option("--correlation-step", s.greedy.thresholdStep, "greedy: t_c increase per pass (paper: 0.1)")
      ->capture_default_str();
  app.add_option("--counterparts", s.counterparts,
                 "changed views per image for the stability data (default: 1 if --selection needs it, else 0)");
  addViewChangeFlags(app, s.viewChange);
  addPlacementFlags(app, s.placement);

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
    const bool placementSet =
        s.placement.form != PlacementFlags{}.form || s.placement.orientation != PlacementFlags{}.orientation;
    if (!s.patchesFile.empty() && (!s.images.empty() || !s.camera.empty() || placementSet))
      throw std::invalid_argument("--patches-file cannot be combined with --images, --camera, --form or --orientation");
    if (!s.camera.empty() && !fs::is_regular_file(s.camera))
      throw std::invalid_argument(s.camera + ": calibration file does not exist");
    const DetectorKind detector = parseDetector(s.detector);
    const SelectionCriterion criterion = parseSelectionCriterion(s.selection);
    if (s.counterparts < 0) s.counterparts = needsCounterparts(criterion) ? 1 : 0;
    if (s.name.empty())
      s.name = s.detector + (s.camera.empty() ? "_perspective_" : "_fisheye_") +
               std::to_string(s.tests);

    PatchSet patches;
    ExtractionReport report;
    if (!s.patchesFile.empty()) {
      patches = readPatchSet(s.patchesFile);
      out << "patches: " << patches.count() << " (" << patches.counterpartCount() << " counterparts) from "
          << s.patchesFile << "\n";
      if (needsCounterparts(criterion) && patches.counterpartCount() == 0)
        throw std::invalid_argument(s.patchesFile + ": no counterpart patches, which --selection " + s.selection +
                                    " needs; extract them with mdbrief-patchextract --counterparts 1 (or train "
                                    "from --images)");
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
      eo.counterparts = s.counterparts;
      for (const auto& file : s.heldOut) eo.heldOut.merge(readHeldOutImages(file));
      eo.viewChange = s.viewChange;
      eo.placement = placementOf(s.placement);
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
    GreedyOptions go = s.greedy;
    go.tests = s.tests;
    const Counterparts pairs{{patches.counterpartPixels.data(), patches.counterpartCount()},
                             patches.counterpartOf.data()};
    const LearnedTests learned =
        learnTests(matrix, go, criterion, pairs, [&](const char* stage, size_t d, size_t t) {
          progress.update(stage, d, t);
        });
    progress.finish();

    PatternDocument doc;
    doc.name = s.name;
    doc.generator = recordedCommand(s);
    doc.tests = learned.tests;
    doc.trainingImages = patches.usedImageDigests();
    if (doc.trainingImages.empty())
      out << "warning: " << s.patchesFile << " records no image digests: evaluations cannot check that they never "
          << "saw the training images (re-extract it with this version)\n";
    const std::string source =
        s.patchesFile.empty()
            ? std::to_string(report.imagesUsed) + " images (" + std::to_string(report.skipped.size()) +
                  " skipped)"
            : "patch file " + fs::path(s.patchesFile).filename().string();
    const std::string scheme = criterion == SelectionCriterion::Paper       ? "ORB greedy scheme"
                               : criterion == SelectionCriterion::Stability ? "stability-ranked greedy scheme"
                                                                            : "separation forward selection";
    doc.description = "Learned (" + scheme + "): " + std::to_string(learned.tests.size()) +
                      " tests, " + std::to_string(patches.count()) + " " + s.detector +
                      (s.camera.empty() ? "" : " fisheye") + " patches from " + source +
                      (s.renderThroughCamera ? " rendered through the camera" : "");
    doc.provenance = {
        "Patches: " + std::to_string(patches.count()) + ", detector " + s.detector + ", camera " +
            (s.camera.empty() ? "none (perspective)" : s.camera) + ", seed " + std::to_string(s.seed) +
            ", source " + source + ".",
        "Placement: " + patchAttribute(patches, "placement", "not recorded in the patch file") + ".",
        "Data digest (FNV-1a 64 of the patch pixels): " + patchDigest(matrix) + ".",
        "Candidates: " + std::to_string(learned.candidates) + " (32x32 patch without its border, 3 < d < 29); " +
            "selection " + s.selection +
            (learned.passes > 0 ? ", greedy passes " + std::to_string(learned.passes) + ", final t_c " +
                                      fixed(learned.finalThreshold, 1)
                                : std::string()) +
            ".",
        "Matching pairs: " + std::to_string(learned.pairs) +
            (learned.pairs > 0 ? " (" + patchAttribute(patches, "counterparts", "counterparts of a patch file") + ")"
                               : "") +
            ".",
        "Per test: mean = fraction of patches where the test is 1; max corr = highest",
        "correlation |2/P sum|t_i - t_j| - 1| with another test of this set" +
            std::string(learned.flipRate.empty() ? "." : "; flip = fraction of matching pairs where it differs.")};
    for (size_t i = 0; i < learned.tests.size(); ++i)
      doc.testComments.push_back("mean " + fixed(learned.mean[i], 2) + " max corr " +
                                 fixed(learned.maxCorrelation[i], 2) +
                                 (learned.flipRate.empty() ? "" : " flip " + fixed(learned.flipRate[i], 2)));
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
      out << "  held out (evaluation or validation images): " << report.heldOut << " images\n"
          << "  extraction: " << fixed(report.seconds, 2) << " s, " << report.usableKeypoints
          << " usable keypoints";
      if (s.counterparts > 0) out << " (of " << report.detectedInViews << " before the view check)";
      out << "\n";
    }
    out << "  patches: " << patches.count() << " (digest " << patchDigest(matrix) << ")\n"
        << "  candidates: " << learned.candidates << "\n"
        << "  responses: " << fixed(learned.times.evaluateSeconds, 2) << " s ("
        << fixed(learned.responseBytes / 1048576.0, 0) << " MiB bit matrix)\n"
        << "  pairs: " << learned.pairs << " (flip rates " << fixed(learned.times.flipSeconds, 2) << " s)\n"
        << "  sort: " << fixed(learned.times.sortSeconds, 2) << " s\n"
        << "  selection (" << s.selection << "): " << fixed(learned.times.greedySeconds, 2) << " s"
        << (learned.passes > 0 ? ", " + std::to_string(learned.passes) + " passes, final t_c " +
                                     fixed(learned.finalThreshold, 1)
                               : std::string())
        << "\n"
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
