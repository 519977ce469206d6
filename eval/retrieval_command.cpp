// `mdbrief-eval retrieval`: place recognition with vocabularies (retrieval_experiment.hpp) on the
// Oxford sequences, the rendered fisheye sequences and the poster-dev frames, with photos of a
// folder split into vocabulary training images and distractors.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "benchmark_datasets.hpp"
#include "command_helpers.hpp"
#include "eval_commands.hpp"
#include "retrieval_experiment.hpp"
#include "mdbrief/detect/detector.hpp"
#include "toolkit/option_flags.hpp"
#include "vocabulary/training_features.hpp"

namespace mdbrief::eval {
namespace {

const std::vector<std::string> kRetrievalDatasets{"poster-dev", "oxford", "rendered-fisheye"};

struct Args {
  BenchmarkDataPaths paths;
  std::vector<std::string> datasets;
  std::string photos;  // default: <data>/natural/bsds500
  int trainingCount = 100;
  RetrievalOptions options;
};

}  // namespace

void addRetrievalCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "retrieval", "Place recognition: recall@k of vocabularies (mdBRIEF masked, mdBRIEF mask-blind, ORB) trained "
                   "alike, with distractors; transform and query times, file size and load time against DBoW2 text");
  auto a = std::make_shared<Args>();
  addOpencvDocFlag(cmd, a->paths.opencvDocDir);
  cmd->add_option("--data", a->paths.data, "The shared data folder (default relative to the working directory, or "
                                           "$MDBRIEF_DATA)")
      ->capture_default_str();
  cmd->add_option("--datasets", a->datasets,
                  "Only these data sets: poster-dev, oxford, rendered-fisheye (default: every one found; one "
                  "named here that cannot be read is an error)")
      ->check(CLI::IsMember(kRetrievalDatasets));
  cmd->add_option("--fisheye-camera", a->paths.fisheyeCameras, "Calibrations the rendered fisheye sequences use, file or file#id for one camera of a rig file")
      ->check(inputFileCheck(cameraReferencePath))
      ->capture_default_str();
  cmd->add_option("--photos", a->photos,
                  "Photos, sorted by path: the first --training-count train the vocabularies, the rest are "
                  "distractors in the database (default: <data>/natural/bsds500)");
  cmd->add_option("--training-count", a->trainingCount, "Photos that train the vocabularies")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--branching", a->options.training.branching, "k of every vocabulary")
      ->check(CLI::Range(2, kMaxVocabularyBranching))
      ->capture_default_str();
  cmd->add_option("--depth", a->options.training.depth, "L of every vocabulary")
      ->check(CLI::Range(1, kMaxVocabularyDepth))
      ->capture_default_str();
  cmd->add_option("--seed", a->options.training.seed, "Training seed")->capture_default_str();
  addFieldFlag(*cmd, detectorOptionFields(), "nfeatures", a->options.nfeatures, "every method's budget");
  cmd->add_option("--recall-at", a->options.recallAt, "The k of recall@k")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--out", a->options.outDir,
                  "Output folder: retrieval.csv, retrieval_speed.csv and the vocabularies (binary, DBoW2 text)")
      ->required();
  cmd->callback([a] {
    requireDistinctLabels(a->paths.fisheyeCameras, "--fisheye-camera");
    const std::string photos = a->photos.empty() ? a->paths.data + "/natural/bsds500" : a->photos;
    std::vector<std::filesystem::path> files;
    try {
      files = vocab::imageFiles({photos});
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("--photos: ") + e.what());
    }
    if (files.size() <= static_cast<size_t>(a->trainingCount))
      throw InputError("--photos " + photos + ": " + std::to_string(files.size()) + " images, not more than " +
                       "--training-count " + std::to_string(a->trainingCount) + " (none left as distractors)");
    std::vector<std::string> training, distractors;
    for (size_t i = 0; i < files.size(); ++i)
      (i < static_cast<size_t>(a->trainingCount) ? training : distractors).push_back(files[i].string());

    // The output folder before the data sets and photos are read (minutes on the shared data).
    std::error_code ec;
    std::filesystem::create_directories(a->options.outDir, ec);
    if (ec || !std::filesystem::is_directory(a->options.outDir))
      throw InputError("--out " + a->options.outDir + ": cannot make it a folder" + (ec ? ": " + ec.message() : ""));

    const bool named = !a->datasets.empty();
    std::vector<EvalGroup> groups;
    std::vector<std::string> inputs(training.begin(), training.end());
    inputs.insert(inputs.end(), distractors.begin(), distractors.end());
    for (const auto& value : a->paths.fisheyeCameras) inputs.push_back(parseCameraReference(value).path);
    for (const auto& name : named ? a->datasets : kRetrievalDatasets) {
      std::vector<std::string> read;
      try {
        groups.push_back(loadBenchmarkDataset(name, a->paths, read));
      } catch (const std::exception& e) {
        if (named) throw InputError(name + ": " + e.what());
        std::fprintf(stderr, "retrieval: skipping %s: %s\n", name.c_str(), e.what());
      }
      inputs.insert(inputs.end(), read.begin(), read.end());
    }
    if (groups.empty()) throw InputError("no data set could be read (see the messages above)");
    checkOutputsApart(inputs, retrievalOutputs(a->options));
    asInputErrors([&] { runRetrieval(groups, training, distractors, a->options); });
  });
}

}  // namespace mdbrief::eval
