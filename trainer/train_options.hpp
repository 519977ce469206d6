#pragma once
// What mdbrief-train, Python's mdbrief.train() and C++ callers set for one training run, and its
// field table (mdbrief/base/option_fields.hpp): every surface takes the same options, spelled by the
// table, with the same ranges and defaults.
#include <cstddef>
#include <string>
#include <vector>

#include "mdbrief/base/option_fields.hpp"
#include "patchextract/patch_extraction.hpp"
#include "trainer/greedy_selection.hpp"
#include "trainer/separation_selection.hpp"

namespace mdbrief::train {

inline constexpr const char* kDefaultImageFolder = "/usr/share/doc/opencv-doc/examples/data";

struct TrainOptions {
  // Where the patches come from: extraction from extraction.imageDirs (empty = kDefaultImageFolder),
  // or the patch set in patchesFile (mdbrief-patchextract's output) instead.
  // extraction.counterparts = -1: 1 when the selection needs matching pairs, else 0.
  ExtractionOptions extraction = [] {
    ExtractionOptions o;
    o.counterparts = -1;
    return o;
  }();
  std::vector<std::string> heldOutFiles;  // extra held-out lists, added to extraction.heldOut
  std::string patchesFile;
  std::string savePatches;  // also write the extracted patches (HDF5) here
  size_t tests = 512;       // tests to learn
  // The shipped sets' criterion (configs/training/*.toml; docs/training.md "Selection criteria").
  SelectionCriterion selection = SelectionCriterion::Separation;
  GreedyOptions greedy;  // paper, stability: the correlation thresholds (greedy.tests is `tests`)
  SeparationOptions separation;  // separation: pool and weights (separation.tests is `tests`)
  StreamingOptions streaming;    // block sizes of the trainer: time and memory, never the tests
  std::string name;     // registry name; empty = <detector>_<perspective|fisheye>_<tests>
  std::string out;      // patterns folder to write <name>.hpp, <name>.json and registry.hpp into; empty = none
  bool makeDefault = false;  // make the learned set the registry's default
};

// The fields of TrainOptions: Python keyword, mdbrief-train flag, doc and range of each.
const OptionTable<TrainOptions>& trainOptionFields();

// Throws OptionError for a value out of its range, std::invalid_argument naming the option or file
// for the rest (a missing calibration or output folder, --patches-file with --images).
void validate(const TrainOptions& options);

// The name of the learned set: options.name, or <detector>_<perspective|fisheye>_<tests>.
std::string patternName(const TrainOptions& options);

}  // namespace mdbrief::train
