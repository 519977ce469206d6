#include "trainer/training.hpp"

#include <chrono>
#include <cstdio>
#include <map>
#include <ostream>
#include <sstream>

#include <sys/resource.h>

#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "trainer/candidate_comparisons.hpp"

namespace mdbrief::train {

namespace fs = std::filesystem;

namespace {

// The command as recorded in the header: every setting that changes the result, none of the
// output locations, so the same training gives the same bytes wherever it is written.
std::string recordedCommand(const TrainOptions& s, int counterparts, const std::string& name) {
  const ExtractionOptions& e = s.extraction;
  std::ostringstream c;
  c << "mdbrief-train";
  if (!s.patchesFile.empty()) {
    c << " --patches-file " << s.patchesFile;
  } else {
    for (const auto& dir : e.imageDirs) c << " --images " << dir.string();
    for (const auto& file : s.heldOutFiles) c << " --held-out " << file;
    c << " --detector " << detectorName(e.detector);
    if (!e.cameraPath.empty()) c << " --camera " << e.cameraPath;
    if (e.cameraFormat != CameraFormat::Auto) c << " --camera-format " << toString(e.cameraFormat);
    if (!e.cameraId.empty()) c << " --camera-id " << e.cameraId;
    if (e.renderThroughCamera) c << " --render-through-camera";
    c << " --patches " << e.patches << " --seed " << e.seed;
    const ExtractionOptions defaults;  // named: a temporary trips GCC 12 -Wmaybe-uninitialized under LTO
    if (e.keypointsPerImage != defaults.keypointsPerImage) c << " --keypoints-per-image " << e.keypointsPerImage;
    const DescriptorOptions placement;
    if (e.placement.form != placement.form) c << " --form " << toString(e.placement.form);
    if (e.placement.orientation != placement.orientation) c << " --orientation " << toString(e.placement.orientation);
    if (counterparts > 0) {
      const ViewChangeOptions d;
      const auto& v = e.viewChange;
      c << " --counterparts " << counterparts;
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
  if (s.selection == SelectionCriterion::Separation) {
    const SeparationOptions d;
    const SeparationOptions& p = s.separation;
    if (p.pool != d.pool) c << " --pool " << p.pool;
    if (p.nonMatchingSigmas != d.nonMatchingSigmas) c << " --non-matching-sigmas " << p.nonMatchingSigmas;
    if (p.matchingSigmas != d.matchingSigmas) c << " --matching-sigmas " << p.matchingSigmas;
    if (p.covarianceWords != d.covarianceWords) c << " --covariance-words " << p.covarianceWords;
  }
  c << " --selection " << selectionCriterionName(s.selection) << " --tests " << s.tests << " --name " << name;
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

std::string schemeName(SelectionCriterion criterion) {
  switch (criterion) {
    case SelectionCriterion::Paper: return "ORB greedy scheme";
    case SelectionCriterion::Stability: return "stability-ranked greedy scheme";
    case SelectionCriterion::Separation: return "separation forward selection";
  }
  return "";
}

// "only N patches, fewer than the T requested tests", why (from the extraction's report: the
// budget, every image held out, images of another size than the camera's, nothing detected)
// and what to do about it.
std::string shortfall(const TrainOptions& s, const TrainResult& r, size_t count) {
  const std::string few =
      "only " + std::to_string(count) + " patches, fewer than the " + std::to_string(s.tests) + " requested tests";
  if (!r.extracted) return few + " in " + s.patchesFile + ": extract more patches, or ask for fewer --tests";
  if (s.extraction.patches < static_cast<size_t>(s.tests))
    return few + ": the --patches budget (" + std::to_string(s.extraction.patches) + ") is below --tests";
  const ExtractionReport& e = r.extraction;
  const std::string images = std::to_string(e.imagesFound) + " image" + (e.imagesFound == 1 ? "" : "s");
  if (e.imagesFound > 0 && e.heldOut == e.imagesFound)
    return few + ": every one of the " + images + " is held out (an evaluation uses it; --held-out lists " +
           "them): train on other images";
  std::vector<const SkippedImage*> skipped;  // for another reason than being held out
  for (const SkippedImage& k : e.skipped)
    if (!k.heldOut) skipped.push_back(&k);
  std::string why = few + ": " + std::to_string(e.imagesUsed) + " of " + images + " gave patches (" +
                    std::to_string(e.heldOut) + " held out, " + std::to_string(skipped.size()) + " skipped)";
  if (!skipped.empty()) {
    why += "; " + skipped.front()->path + ": " + skipped.front()->reason;
    if (skipped.front()->otherSize)
      why += "; give --camera the calibration of these images";
  }
  return why + (e.imagesUsed == 0 && skipped.empty() ? "; nothing was detected: images with more texture"
                                                      : "; more images, or fewer --tests");
}

}  // namespace

TrainResult train(const TrainOptions& s, const TrainProgress& progress) {
  validate(s);
  const auto wall0 = std::chrono::steady_clock::now();
  const SelectionCriterion criterion = s.selection;
  const int counterparts =
      s.extraction.counterparts >= 0 ? s.extraction.counterparts : (needsCounterparts(criterion) ? 1 : 0);
  const std::string name = patternName(s);
  const std::string detector = detectorName(s.extraction.detector);
  const std::string& camera = s.extraction.cameraPath;

  // Outputs that cannot be written fail now, not after minutes of extraction and selection.
  if (!s.out.empty()) checkPatternOutputs(name, s.out, {true, s.makeDefault});
  if (s.patchesFile.empty() && !s.savePatches.empty()) checkPatchSetOutput(s.savePatches);
  std::vector<fs::path> inputs{camera, s.patchesFile};
  inputs.insert(inputs.end(), s.heldOutFiles.begin(), s.heldOutFiles.end());
  std::vector<fs::path> outputs{s.savePatches};
  if (!s.out.empty())
    for (const std::string& file : {name + ".hpp", name + ".json", std::string("registry.hpp")})
      outputs.push_back(fs::path(s.out) / file);
  internal::checkOutputsApart(inputs, outputs);

  TrainResult result;
  PatchSet patches;
  if (!s.patchesFile.empty()) {
    patches = readPatchSet(s.patchesFile);
    if (needsCounterparts(criterion) && patches.counterpartCount() == 0)
      throw std::invalid_argument(s.patchesFile + ": no counterpart patches, which --selection " +
                                  selectionCriterionName(criterion) +
                                  " needs; extract them with mdbrief-patchextract --counterparts 1 (or train "
                                  "from --images)");
  } else {
    ExtractionOptions eo = s.extraction;
    if (eo.imageDirs.empty()) eo.imageDirs.emplace_back(kDefaultImageFolder);
    eo.counterparts = counterparts;
    for (const auto& file : s.heldOutFiles) eo.heldOut.merge(readHeldOutImages(file));
    patches = extractPatches(eo, result.extraction, progress);
    result.extracted = true;
    if (!s.savePatches.empty()) writePatchSet(patches, s.savePatches);
  }
  if (patches.count() < s.tests) throw std::invalid_argument(shortfall(s, result, patches.count()));
  result.patches = patches.count();
  result.counterparts = patches.counterpartCount();

  const PatchMatrix matrix{patches.pixels.data(), patches.count()};
  result.patchDigest = patchDigest(matrix);
  GreedyOptions go = s.greedy;
  go.tests = s.tests;
  const Counterparts pairs{{patches.counterpartPixels.data(), patches.counterpartCount()},
                           patches.counterpartOf.data()};
  result.learned = learnComparisons(matrix, go, criterion, pairs, progress, s.separation, s.streaming);
  const LearnedComparisons& learned = result.learned;

  PatternDocument& doc = result.pattern;
  doc.name = name;
  TrainOptions recorded = s;
  if (result.extracted && recorded.extraction.imageDirs.empty())
    recorded.extraction.imageDirs.emplace_back(kDefaultImageFolder);
  doc.generator = recordedCommand(recorded, counterparts, name);
  doc.tests = learned.tests;
  doc.trainingImages = patches.usedImageDigests();
  if (doc.trainingImages.empty())
    result.warnings.push_back(s.patchesFile +
                              " records no image digests: evaluations cannot check that they never saw the "
                              "training images (re-extract it with this version)");
  const std::string source =
      result.extracted ? std::to_string(result.extraction.imagesUsed) + " images (" +
                             std::to_string(result.extraction.skipped.size()) + " skipped)"
                       : "patch file " + fs::path(s.patchesFile).filename().string();
  doc.description = "Learned (" + schemeName(criterion) + "): " + std::to_string(learned.tests.size()) + " tests, " +
                    std::to_string(patches.count()) + " " + detector + (camera.empty() ? "" : " fisheye") +
                    " patches from " + source + (s.extraction.renderThroughCamera ? " rendered through the camera" : "");
  doc.provenance = {
      "Patches: " + std::to_string(patches.count()) + ", detector " + detector + ", camera " +
          (camera.empty() ? "none (perspective)" : camera) + ", seed " + std::to_string(s.extraction.seed) +
          ", source " + source + ".",
      "Placement: " + patchAttribute(patches, "placement", "not recorded in the patch file") + ".",
      "Data digest (FNV-1a 64 of the patch pixels): " + result.patchDigest + ".",
      "Candidates: " + std::to_string(learned.candidates) + " (32x32 patch without its border, 3 < d < 29); " +
          "selection " + selectionCriterionName(criterion) +
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
  if (!s.out.empty()) {
    writePattern(doc, s.out, {true, s.makeDefault});
    for (const std::string& file : {name + ".hpp", name + ".json", std::string("registry.hpp")})
      result.written.push_back(fs::path(s.out) / file);
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  result.peakMemoryMiB = peakMemoryMiB();
  return result;
}

void printTrainSummary(const TrainOptions& options, const TrainResult& r, std::ostream& out) {
  const LearnedComparisons& learned = r.learned;
  for (const std::string& warning : r.warnings) out << "warning: " << warning << "\n";
  out << "summary\n";
  if (r.extracted) {
    const ExtractionReport& report = r.extraction;
    out << "  images: " << report.imagesFound << " found, " << report.imagesUsed << " used, "
        << report.skipped.size() << " skipped\n";
    std::map<std::string, size_t> reasons;
    for (const auto& sk : report.skipped) ++reasons[sk.reason];
    for (const auto& [reason, n] : reasons) out << "    skipped (" << reason << "): " << n << "\n";
    out << "  held out (evaluation or validation images): " << report.heldOut << " images\n"
        << "  extraction: " << fixed(report.seconds, 2) << " s, " << report.usableKeypoints << " usable keypoints";
    if (r.counterparts > 0) out << " (of " << report.detectedInViews << " before the view check)";
    out << "\n";
  } else {
    out << "  patch file: " << options.patchesFile << "\n";
  }
  out << "  patches: " << r.patches << " (digest " << r.patchDigest << "), " << r.counterparts << " counterparts\n"
      << "  candidates: " << learned.candidates << "\n"
      << "  responses: " << fixed(learned.times.evaluateSeconds, 2) << " s (counted, streamed)\n"
      << "  pairs: " << learned.pairs << " (flip rates " << fixed(learned.times.flipSeconds, 2) << " s)\n"
      << "  sort: " << fixed(learned.times.sortSeconds, 2) << " s\n"
      << "  selection (" << selectionCriterionName(learned.criterion) << "): "
      << fixed(learned.times.greedySeconds, 2) << " s"
      << (learned.passes > 0 ? ", " + std::to_string(learned.passes) + " passes, final t_c " +
                                   fixed(learned.finalThreshold, 1)
                             : std::string())
      << "\n"
      << "  tests kept: " << learned.tests.size();
  if (!r.written.empty()) out << " -> " << r.written.front().string();
  out << "\n"
      << "  wall time: " << fixed(r.seconds, 2) << " s, peak memory " << fixed(r.peakMemoryMiB, 0) << " MiB\n";
}

}  // namespace mdbrief::train
