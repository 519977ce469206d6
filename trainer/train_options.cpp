#include "trainer/train_options.hpp"

#include <filesystem>
#include <stdexcept>

#include "mdbrief/internal/base/io/input_file.hpp"
#include "trainer/pattern_writer.hpp"
#include "trainer/candidate_comparisons.hpp"

namespace mdbrief::train {

using R = FieldRange;

const OptionTable<TrainOptions>& trainOptionFields() {
  using O = TrainOptions;
  static const OptionTable<O> table = [] {
    OptionTable<O> t;
    appendNested(t, extractionOptionFields(), "extraction", "", [](auto& o) -> auto& { return o.extraction; });
    for (auto& f : t)
      if (f.member == "extraction.counterparts") {
        f.doc = "changed views per image for the matching pairs; -1 = 1 when the selection criterion needs them, else 0";
        f.range = [](const O&) { return R::closed(-1, kMaxCounterparts); };
      }
    const OptionTable<O> rest = {
        textListField<O>("heldOutFiles", "", "held_out", "--held-out",
                         "files of image digests never to train on (\"<digest> <label>\" lines), in addition to the "
                         "shipped evaluations' images (configs/held-out-images.txt, always left out)",
                         [](auto& o) -> auto& { return o.heldOutFiles; }),
        textField<O>("patchesFile", "", "patches_file", "--patches-file",
                     "reuse an HDF5 patch set (mdbrief-patchextract) instead of extracting",
                     [](auto& o) -> auto& { return o.patchesFile; }),
        textField<O>("savePatches", "", "save_patches", "--save-patches", "also write the extracted patches (HDF5)",
                     [](auto& o) -> auto& { return o.savePatches; }),
        // The descriptor uses at most 512 tests (DescriptorOptions::bits).
        integerField<O>("tests", "", "tests", "--tests", "tests to learn", R{32, 512, false, false, 32},
                        [](auto& o) -> auto& { return o.tests; }),
        choiceField<O>("selection", "", "selection", "--selection",
                       "ranking of the selection: paper (variance, the paper's greedy scheme), stability "
                       "(2 var - flip rate, then the paper's greedy) or separation (forward selection by the "
                       "separation of matching and non-matching distances); docs/training.md",
                       kSelectionCriterionNames, [](auto& o) -> auto& { return o.selection; }),
        realField<O>("greedy.startThreshold", "", "correlation_start", "--correlation-start",
                     "paper, stability: correlation threshold t_c of the first greedy pass", R::openLow(0, 1),
                     [](auto& o) -> auto& { return o.greedy.startThreshold; }),
        realField<O>("greedy.thresholdStep", "", "correlation_step", "--correlation-step",
                     "paper, stability: t_c increase per greedy pass", R::openLow(0, 1),
                     [](auto& o) -> auto& { return o.greedy.thresholdStep; }),
        integerField<O>("separation.pool", "", "pool", "--pool",
                        "separation: candidates considered, the best by 2 var - flip rate (raised to the tests if fewer)",
                        R::closed(1, static_cast<double>(kCandidateCount)),
                        [](auto& o) -> auto& { return o.separation.pool; }),
        realField<O>("separation.nonMatchingSigmas", "", "non_matching_sigmas", "--non-matching-sigmas",
                     "separation: sigmas of the non-matching distance below its mean", R::closed(0, 10),
                     [](auto& o) -> auto& { return o.separation.nonMatchingSigmas; }),
        realField<O>("separation.matchingSigmas", "", "matching_sigmas", "--matching-sigmas",
                     "separation: sigmas of the matching distance above its mean", R::closed(0, 10),
                     [](auto& o) -> auto& { return o.separation.matchingSigmas; }),
        // 65536 words are 4 M samples, far below any standard error the selection can use.
        integerField<O>("separation.covarianceWords", "", "covariance_words", "--covariance-words",
                        "separation: 64-patch words the covariances are estimated on", R::closed(1, 65536),
                        [](auto& o) -> auto& { return o.separation.covarianceWords; }),
        // Time and memory only: the learned tests are the same for every block size
        // (tests/test_trainer.cpp), so the pattern's recorded command leaves them out.
        integerField<O>("streaming.chunkWords", "", "chunk_words", "--chunk-words",
                        "64-patch words per transposed block every candidate is evaluated on (time and memory only)",
                        R::closed(1, 4096), [](auto& o) -> auto& { return o.streaming.chunkWords; }),
        integerField<O>("streaming.candidateBatch", "", "candidate_batch", "--candidate-batch",
                        "candidates whose responses are computed together (time and memory only)",
                        R::closed(1, static_cast<double>(kCandidateCount)),
                        [](auto& o) -> auto& { return o.streaming.candidateBatch; }),
        textField<O>("name", "", "name", "--name",
                     "registry name (default <detector>_<perspective|fisheye>_<tests>)",
                     [](auto& o) -> auto& { return o.name; }),
        textField<O>("out", "", "out", "--out",
                     "existing patterns folder to write <name>.hpp, <name>.json and registry.hpp into",
                     [](auto& o) -> auto& { return o.out; }),
        flagField<O>("makeDefault", "", "make_default", "--make-default",
                     "make the learned set the registry's default", [](auto& o) -> auto& { return o.makeDefault; }),
    };
    t.insert(t.end(), rest.begin(), rest.end());
    return t;
  }();
  return table;
}

void validate(const TrainOptions& options) {
  validateFields(trainOptionFields(), options, "TrainOptions");
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!options.out.empty() && !fs::is_directory(options.out, ec))
    throw std::invalid_argument(options.out + (fs::exists(options.out, ec) ? ": the output folder is a file, not a folder"
                                                                           : ": output folder does not exist"));
  // Before the work, also without out (Python's train returned a set its save() refused).
  if (!options.name.empty()) requirePatternName(options.name);
  if (options.makeDefault && options.out.empty())
    throw std::invalid_argument("make_default needs out (a patterns folder whose registry it changes)");
  const ExtractionOptions& e = options.extraction;
  const DescriptorOptions placement;
  const bool placementSet = e.placement.form != placement.form || e.placement.orientation != placement.orientation;
  if (!options.patchesFile.empty() && (!e.imageDirs.empty() || !e.cameraPath.empty() || placementSet))
    throw std::invalid_argument("--patches-file cannot be combined with --images, --camera, --form or --orientation");
  if (!e.cameraPath.empty())
    if (const std::string problem = internal::inputFileProblem(e.cameraPath); !problem.empty())
      throw std::invalid_argument(e.cameraPath + ": calibration file: " + problem);
}

std::string patternName(const TrainOptions& options) {
  if (!options.name.empty()) return options.name;
  return detectorName(options.extraction.detector) +
         (options.extraction.cameraPath.empty() ? "_perspective_" : "_fisheye_") + std::to_string(options.tests);
}

}  // namespace mdbrief::train
