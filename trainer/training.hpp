#pragma once
// The typed training API: TrainOptions -> TrainResult. Extracts the patches (or reads a patch
// file), learns the tests, and writes the pattern header, its JSON copy and the registry when
// options.out is set. mdbrief-train (train_cli.hpp) and Python's mdbrief.train() are thin layers
// over it.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "trainer/pattern_writer.hpp"
#include "trainer/train_options.hpp"
#include "trainer/trainer.hpp"

namespace mdbrief::train {

struct TrainResult {
  PatternDocument pattern;         // the learned set, as written: name, tests, provenance, comments
  LearnedComparisons learned;            // per-test statistics and stage times
  bool extracted = false;          // patches extracted from images (else read from patchesFile)
  ExtractionReport extraction;     // when extracted
  size_t patches = 0;
  size_t counterparts = 0;         // counterpart patches (matching pairs)
  std::string patchDigest;         // FNV-1a 64 of the patch pixels
  std::vector<std::string> warnings;
  std::vector<std::filesystem::path> written;  // files written (empty when options.out is empty)
  double seconds = 0;              // wall time
  double peakMemoryMiB = 0;        // peak resident memory of the process so far
};

// stage: "detect", "sample" (extraction), "evaluate", "pairs", "greedy" (learning); done/total in
// the stage's units. Called from worker threads during extraction.
using TrainProgress = std::function<void(const char* stage, size_t done, size_t total)>;

// Throws OptionError or std::invalid_argument naming the option or file (validate()), and
// std::invalid_argument when the data cannot give the set (fewer patches than tests, no
// matching pairs for a criterion that needs them). Same options and data: byte-identical outputs.
TrainResult train(const TrainOptions& options, const TrainProgress& progress = {});

// mdbrief-train's summary of a run (images, patches, stage times, output, memory).
void printTrainSummary(const TrainOptions& options, const TrainResult& result, std::ostream& out);

}  // namespace mdbrief::train
