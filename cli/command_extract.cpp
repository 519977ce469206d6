// `mdbrief extract`: detect and describe (or describe given keypoints) and write one
// FileStorage file per image (storage_io.hpp's layout).
#include <iostream>
#include <memory>
#include <set>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/extraction_flags.hpp"
#include "cli/storage_io.hpp"

namespace mdbrief::cli {
namespace {

namespace fs = std::filesystem;

struct ExtractArgs {
  ExtractionFlags flags;
  std::string keypoints;
  std::vector<std::string> images;
  std::string output;
};

// The output file of each image: -o itself for one image, <folder>/<stem>.yml for several.
std::vector<fs::path> outputPaths(const ExtractArgs& args) {
  if (args.images.size() == 1) {
    checkStorageOutput(args.output);
    return {fs::path(args.output)};
  }
  std::error_code ec;
  if (!fs::is_directory(args.output, ec))
    throw InputError(args.output + ": with several images -o must name an existing folder");
  std::vector<fs::path> out;
  std::set<std::string> stems;
  for (const auto& image : args.images) {
    const std::string stem = fs::path(image).stem().string();
    if (!stems.insert(stem).second)
      throw InputError(image + ": another input image has the same name stem '" + stem + "' (outputs would collide)");
    out.push_back(fs::path(args.output) / (stem + ".yml"));
  }
  return out;
}

void runExtract(const ExtractArgs& args) {
  // Check everything cheap before the first (slow) image so a typo fails at once.
  const std::vector<fs::path> outputs = outputPaths(args);
  std::vector<fs::path> inputs(args.images.begin(), args.images.end());
  inputs.insert(inputs.end(), {args.flags.camera.path, args.keypoints});
  checkOutputsApart(inputs, outputs);
  const CameraPtr calibration = loadCalibration(args.flags);
  std::optional<std::vector<cv::KeyPoint>> given;
  if (!args.keypoints.empty()) given = loadKeypoints(args.keypoints);
  // Every image described before any output is written, so that a bad image leaves no output
  // behind; the features are small beside the images.
  std::vector<Features> features;
  for (size_t i = 0; i < args.images.size(); ++i) {
    const cv::Mat image = loadImage(args.images[i], args.flags.strict);
    features.push_back(extractFeatures(args.flags, calibration, args.images[i], image, given));
  }
  writeFeatureFiles(outputs, features);
  for (size_t i = 0; i < args.images.size(); ++i)
    std::cout << args.images[i] << ": " << features[i].keypoints.size() << " keypoints -> " << outputs[i].string()
              << "\n";
}

}  // namespace

void addExtractCommand(CLI::App& app) {
  auto args = std::make_shared<ExtractArgs>();
  CLI::App* cmd = app.add_subcommand(
      "extract",
      "Detect keypoints and describe them (BRIEF, dBRIEF or mdBRIEF). Output: an OpenCV FileStorage file "
      "(.yml, .yml.gz, .json) with nodes keypoints, descriptors (N x bits/8, CV_8U) and masks (mdBRIEF only); "
      "keypoints that cannot be described are left out of all three. Also test_set, test_set_digest and, with "
      "--camera, camera_digest, which match checks; pyramid (the pyramid options, key=value), image_size and "
      "image_digest, which match --refine needs.");
  addExtractionFlags(*cmd, args->flags);
  cmd->add_option("--keypoints", args->keypoints,
                  "Describe the keypoints of node 'keypoints' of this FileStorage file (for every image) instead of "
                  "detecting")
      ->check(inputFileCheck());
  cmd->add_option("images", args->images, "Input images (the calibration's size)")
      ->check(inputFileCheck())->required();
  cmd->add_option("-o,--output", args->output, "Output file; with several images an existing folder (<stem>.yml each)")
      ->required();
  cmd->callback([args] { runExtract(*args); });
}

}  // namespace mdbrief::cli
