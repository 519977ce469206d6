#pragma once
// The real and rendered data sets the image-pair benchmarks share (the tracker benchmark, place
// recognition): the poster-dev fisheye frames, the Oxford sequences, the rendered fisheye
// sequences and the turned-lens photos, each loaded as one group of sequences.
#include <string>
#include <vector>

#include "command_helpers.hpp"
#include "pr_experiment.hpp"

namespace mdbrief::eval {

inline const std::vector<std::string> kBenchmarkDatasets{"poster-dev", "oxford", "rendered-fisheye", "turned-lens"};

struct BenchmarkDataPaths {
  std::string data = sharedData();  // the shared data folder
  std::string opencvDocDir;         // the opencv-doc photos (textures of the rendered sequences)
  // The calibrations the rendered fisheye sequences use, one sequence per camera and texture;
  // "file#id" takes one camera of a rig file (parseCameraReference).
  std::vector<std::string> fisheyeCameras{"configs/cameras/lafida_fisheye0.yaml",
                                          "configs/cameras/double_sphere_example.yaml",
                                          "configs/cameras/kannala_brandt_example.yaml"};
};

// One data set (a name of kBenchmarkDatasets) as a group; appends the files it read to `images`.
// Throws std::runtime_error naming the file at fault.
EvalGroup loadBenchmarkDataset(const std::string& name, const BenchmarkDataPaths& paths,
                               std::vector<std::string>& images);

}  // namespace mdbrief::eval
