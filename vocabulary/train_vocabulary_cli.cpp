#include "vocabulary/train_vocabulary_cli.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>

#include <CLI/CLI.hpp>
#include <tbb/parallel_for.h>

#include "mdbrief/camera/io.hpp"
#include "mdbrief/describe/descriptor.hpp"
#include "mdbrief/detect/detector.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"
#include "mdbrief/internal/base/size_text.hpp"
#include "mdbrief/recognition/vocabulary_text.hpp"
#include "toolkit/command_line.hpp"
#include "toolkit/input_file_flag.hpp"
#include "toolkit/option_flags.hpp"
#include "toolkit/progress_reporter.hpp"
#include "toolkit/tool_errors.hpp"
#include "vocabulary/descriptor_npy.hpp"
#include "vocabulary/training_features.hpp"

namespace mdbrief::vocab {

namespace {

namespace fs = std::filesystem;

struct Args {
  std::vector<std::string> images, descriptors, masks, heldOut;
  std::string camera, out, dbow2Text;
  std::string cameraFormat = toString(CameraFormat::Auto), cameraId;
  std::string extractor = "mdbrief", preset = "tracking", weighting = "tf-idf";
  int bits = 0, nfeatures = FeatureOptions{}.nfeatures;
  bool plain = false;
  VocabularyTrainingOptions training;
};

// The training images described (image input), in file order. Errors are reported for the
// first image in that order, whatever the threads met first.
std::vector<TrainingImage> describeImages(const Args& a, const std::vector<fs::path>& files,
                                          const FeatureOptions& features, ProgressReporter& progress) {
  CameraPtr camera;
  if (!a.camera.empty()) camera = loadCamera(a.camera, {parseCameraFormat(a.cameraFormat), a.cameraId});
  train::HeldOutImages heldOut = train::shippedHeldOutImages();
  for (const auto& list : a.heldOut) heldOut.merge(train::readHeldOutImages(list));
  std::vector<TrainingImage> images(files.size());
  std::vector<std::string> errors(files.size());
  std::atomic<size_t> done{0};
  tbb::parallel_for(size_t(0), files.size(), [&](size_t i) {
    try {
      uint64_t digest = 0;
      const cv::Mat grey = readTrainingImage(files[i], heldOut, digest);
      if (camera && features.kind == FeatureKind::MdBrief && grey.size() != camera->imageSize())
        throw std::invalid_argument(files[i].string() + ": " + internal::sizeText(grey.size()) + ", but --camera " +
                                    a.camera + " is calibrated for " + internal::sizeText(camera->imageSize()));
      images[i] = describeImage(grey, features, camera);
      images[i].digest = digest;
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
    progress.update("describing images", ++done, files.size());
  });
  for (const auto& e : errors)
    if (!e.empty()) throw std::invalid_argument(e);
  return images;
}

std::vector<TrainingImage> readDescriptorFiles(const Args& a) {
  if (!a.masks.empty() && a.masks.size() != a.descriptors.size())
    throw std::invalid_argument("--masks: " + std::to_string(a.masks.size()) + " files for " +
                                std::to_string(a.descriptors.size()) + " --descriptors files (one per image, in order)");
  std::vector<TrainingImage> images(a.descriptors.size());
  for (size_t i = 0; i < images.size(); ++i) {
    images[i].descriptors = readDescriptorNpy(a.descriptors[i]);
    if (a.masks.empty()) continue;
    images[i].masks = readDescriptorNpy(a.masks[i]);
    if (images[i].masks.size() != images[i].descriptors.size())
      throw std::invalid_argument(a.masks[i] + ": " + std::to_string(images[i].masks.rows) + " x " +
                                  std::to_string(images[i].masks.cols) + " masks for the " +
                                  std::to_string(images[i].descriptors.rows) + " x " +
                                  std::to_string(images[i].descriptors.cols) + " descriptors of " + a.descriptors[i]);
  }
  return images;
}

void run(Args& a, std::ostream& out, bool progressTty) {
  const auto start = std::chrono::steady_clock::now();
  if (a.images.empty() == a.descriptors.empty())
    throw std::invalid_argument("give either --images (with --camera or photos) or --descriptors");
  FeatureOptions features;
  features.kind = parseName(a.extractor, kFeatureKindNames, "--extractor");
  features.preset = parsePreset(a.preset);
  features.bits = a.bits;
  features.nfeatures = a.nfeatures;
  if (!a.images.empty()) mdBriefOptions(features);  // the options describeImage uses, checked before any work
  a.training.weighting = parseWeighting(a.weighting);
  // ORB descriptors have no masks; descriptor files without masks neither.
  a.training.masked = !a.plain && features.kind == FeatureKind::MdBrief && (a.descriptors.empty() || !a.masks.empty());
  internal::checkOutputPath(a.out);
  if (!a.dbow2Text.empty()) {
    if (a.training.masked)
      throw std::invalid_argument("--dbow2-text: the DBoW2 text format has no masks; train a plain vocabulary (--plain)");
    internal::checkOutputPath(a.dbow2Text);
  }
  if (a.camera.empty() && (!a.cameraId.empty() || a.cameraFormat != toString(CameraFormat::Auto)))
    throw std::invalid_argument("--camera-format and --camera-id need --camera (the calibration file they describe)");
  const std::vector<fs::path> files = a.images.empty() ? std::vector<fs::path>{} : imageFiles(a.images);
  std::vector<fs::path> inputs(files.begin(), files.end());
  for (const auto* list : {&a.descriptors, &a.masks, &a.heldOut})
    inputs.insert(inputs.end(), list->begin(), list->end());
  inputs.push_back(a.camera);
  internal::checkOutputsApart(inputs, {a.out, a.dbow2Text});

  ProgressReporter progress(out, progressTty);
  const std::vector<TrainingImage> images =
      a.images.empty() ? readDescriptorFiles(a) : describeImages(a, files, features, progress);
  size_t descriptors = 0;
  for (const auto& im : images) descriptors += static_cast<size_t>(im.descriptors.rows);
  const Vocabulary v = trainVocabulary(images, a.training, [&](const std::string& stage, size_t done, size_t total) {
    progress.update(stage, done, total);
  });
  progress.finish();
  // Both files as one set: a failed text leaves the previous binary too.
  std::vector<internal::FileContent> written{{a.out, v.fileBytes()}};
  if (!a.dbow2Text.empty()) written.push_back({a.dbow2Text, dbow2Text(v)});
  internal::writeFilesAtomically(written);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  char line[512];
  std::snprintf(line, sizeof line,
                "%s: %zu words, %zu nodes (k = %d, L = %d), %s, %d bits, %s weights, from %zu images (%zu descriptors); "
                "%zu bytes; %.1f s\n",
                a.out.c_str(), v.wordCount(), v.nodeCount(), v.branching(), v.depth(), v.masked() ? "masked" : "plain",
                v.bits(), toString(v.weighting()).c_str(), images.size(), descriptors, v.fileBytes().size(), seconds);
  out << line;
}

// The tool's flags, bound to its arguments; the input files among them are checked before any
// work, as every tool's (toolkit/input_file_flag.hpp).
struct TrainVocabularyApp : CLI::App {
  TrainVocabularyApp()
      : CLI::App("Train a vocabulary of binary words (hierarchical k-majority, masked for mdBRIEF) from images or "
                 "descriptor files; docs/vocabulary.md",
                 "mdbrief-train-vocabulary") {
    add_option("--images", a.images, "Training images: folders (searched recursively) or files");
    add_option("--camera", a.camera,
               "Calibration of every image (default: each photo as the pinhole of f = its width, "
               "scenes/photo_camera.hpp)")
        ->check(inputFileCheck());
    add_option("--camera-format", a.cameraFormat,
               "Format of the calibration file; auto recognises it from the content (configs/cameras/README.md)")
        ->check(CLI::IsMember(namesOf(kCameraFormatNames)))
        ->capture_default_str();
    add_option("--camera-id", a.cameraId,
               "The camera of a calibration file that holds several: Kalibr cam0, cam1, ...; basalt's index; "
               "ORB-SLAM3 1 or 2; COLMAP's CAMERA_ID");
    add_option("--extractor", a.extractor, "Features: the library's (mdbrief) or cv::ORB's (orb; a plain vocabulary)")
        ->check(CLI::IsMember(namesOf(kFeatureKindNames)))
        ->capture_default_str();
    add_option("--preset", a.preset, "mdbrief: the preset whose detector and descriptor run")
        ->check(CLI::IsMember(namesOf(kPresetNames)))
        ->capture_default_str();
    // The library's flags, from its option tables (toolkit/option_flags.hpp addFieldFlag).
    addFieldFlag(*this, descriptorOptionFields(), "bits", a.bits, "--extractor mdbrief")->default_str("the preset's");
    addRenamedFlag(*this, "--features", "--extractor", "--nfeatures is the number of keypoints");
    addFieldFlag(*this, detectorOptionFields(), "nfeatures", a.nfeatures, "--extractor orb's too");
    add_option("--descriptors", a.descriptors,
               "Instead of images: .npy descriptor files (uint8, N x bytes), one per image")
        ->check(inputFileCheck());
    add_option("--masks", a.masks, "The descriptors' masks, .npy files in the same order (a masked vocabulary)")
        ->check(inputFileCheck());
    add_flag("--plain", a.plain, "Train a plain vocabulary: Hamming distances, masks ignored");
    add_option("--branching", a.training.branching, "k: children per node")
        ->check(CLI::Range(2, kMaxVocabularyBranching))
        ->capture_default_str();
    add_option("--depth", a.training.depth, "L: levels (at most k^L words)")
        ->check(CLI::Range(1, kMaxVocabularyDepth))
        ->capture_default_str();
    add_option("--rounds", a.training.clustering.maxRounds, "k-majority rounds per node at most")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    add_option("--mask-agreement", a.training.clustering.maskAgreement,
               "Masked: share of a word's members that must trust a bit and agree on it for the word to trust it")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    add_option("--weighting", a.weighting, "Word weighting")
        ->check(CLI::IsMember(namesOf(kWeightingNames)))
        ->capture_default_str();
    add_option("--seed", a.training.seed, "Random seed (the same inputs and seed give the same file)")
        ->capture_default_str();
    add_option("--held-out", a.heldOut,
               "More held-out lists (configs/held-out-images.txt's format) whose images are refused, besides the "
               "compiled-in evaluation images")
        ->check(inputFileCheck());
    add_option("--out", a.out, "The vocabulary file to write")->required();
    add_option("--dbow2-text", a.dbow2Text, "Also write the vocabulary as a DBoW2 text file (plain only)");
  }

  Args a;
};

}  // namespace

std::unique_ptr<CLI::App> trainVocabularyCommandLine() { return std::make_unique<TrainVocabularyApp>(); }

int runTrainVocabularyCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
                          bool progressTty) {
  TrainVocabularyApp app;
  Args& a = app.a;
  if (const std::optional<int> code = parseArguments(app, args, out, err)) return *code;
  return runTool("mdbrief-train-vocabulary: ", err, [&] {
    asInputErrors([&] { run(a, out, progressTty); });  // files: unreadable input, failed write
    return kExitSuccess;
  });
}

}  // namespace mdbrief::vocab
