// `mdbrief camera convert`: a calibration of any format loadCamera reads (Kalibr, basalt,
// ORB-SLAM3, EuRoC / Kimera, OpenCV, COLMAP, OCamCalib, fisheye-calib-adapter, the project's YAML) written as the
// project's YAML (configs/cameras/README.md), to a file or to stdout.
#include <filesystem>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "toolkit/input_file_flag.hpp"
#include "cli/extraction_flags.hpp"
#include "mdbrief/camera/io.hpp"
#include "mdbrief/internal/base/io/atomic_file.hpp"

namespace mdbrief::cli {
namespace {

struct ConvertArgs {
  CameraFileFlags input;
  std::string output;
};

void runConvert(const ConvertArgs& args) {
  if (!args.output.empty()) {
    // The project's format is YAML: `-o out.json` would write YAML into a .json file.
    const std::string extension = std::filesystem::path(args.output).extension().string();
    if (extension != ".yaml" && extension != ".yml")
      throw InputError(args.output + ": the output is the project's YAML and must end in .yaml or .yml");
    try {
      internal::checkOutputPath(args.output);
      internal::checkOutputsApart({args.input.path}, {args.output});
    } catch (const std::runtime_error& e) {
      throw InputError(e.what());
    }
  }
  const CameraFile file = readCalibrationFile(args.input);
  const std::string yaml = cameraToYaml(*file.camera);
  if (args.output.empty()) {
    std::cout << yaml;
    return;
  }
  try {
    internal::writeFileAtomically(args.output, yaml);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
  const cv::Size size = file.camera->imageSize();
  std::cout << args.input.path << " (" << toString(file.format)
            << (args.input.id.empty() ? "" : ", camera " + args.input.id) << "): " << file.camera->modelName() << " "
            << size.width << "x" << size.height << " -> " << args.output << "\n";
}

}  // namespace

void addCameraCommand(CLI::App& app) {
  CLI::App* camera = app.add_subcommand("camera", "Calibration files (configs/cameras/README.md)");
  camera->require_subcommand(1);
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* convert = camera->add_subcommand(
      "convert",
      "Write a calibration of any supported format (Kalibr camchain.yaml, basalt calib.json, ORB-SLAM3 settings, "
      "EuRoC / Kimera sensor.yaml, OpenCV calibration YAML or K and D, COLMAP cameras.txt, OCamCalib calib_results.txt, fisheye-calib-adapter YAML, the "
      "project's YAML) as the project's YAML");
  convert->add_option("input", args->input.path, "Calibration file")
      ->check(inputFileCheck())->required();
  addCameraFileFlags(*convert, args->input, "--camera", "--format");
  convert->add_option("-o,--output", args->output, "Output YAML file (default: stdout)");
  convert->callback([args] { runConvert(*args); });
}

}  // namespace mdbrief::cli
