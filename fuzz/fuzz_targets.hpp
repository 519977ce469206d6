#pragma once
// The parsers of outside input, each as one fuzz target: bytes -> a file -> the parser. A target
// returns normally for any input (a clear exception is the expected answer to bad bytes); a
// crash, a hang or a sanitizer report is a finding. libFuzzer drives them in the fuzz build
// (fuzz_main.cpp), tests/test_fuzz_regressions.cpp replays every kept finding in every build.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mdbrief/recognition/vocabulary.hpp"

namespace mdbrief::fuzz {

struct Target {
  const char* name;  // also the folder of its seeds and regressions: fuzz/{seeds,regressions}/<name>
  void (*run)(const uint8_t* data, size_t size);
};

// camera (loadCamera and readCameraRig: every format of camera/io.hpp, the project YAML,
// calib-adapter, Kalibr, basalt, ORB-SLAM3, EuRoC / Kimera, OpenCV, OpenCV K and D, COLMAP,
// OCamCalib, and the rigs' extrinsics), pattern_json
// (loadComparisonSetJson), keypoints (mdbrief extract --keypoints), patch_set (HDF5 readPatchSet),
// train_config (mdbrief-train --config TOML), vocabulary (Vocabulary::load), vocabulary_text
// (importDbow2Text), database (Database::load with databaseVocabulary()), held_out_list
// (readHeldOutImages: --held-out of the trainers), homography (readHomography: draw
// --homography, eval --user-homographies), descriptor_npy (readDescriptorNpy:
// mdbrief-train-vocabulary --descriptors), nesting (internal::NestingScan, the depth check before
// every YAML, JSON and XML parser, whole and in parts). A vocabulary or
// database that loads is then used (descriptors quantised, entries queried).
const std::vector<Target>& targets();

// The vocabulary the database target loads its inputs with (its seeds were saved with it).
Vocabulary databaseVocabulary();

}  // namespace mdbrief::fuzz
