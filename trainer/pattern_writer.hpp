#pragma once
// Writing test sets: the generated C++ pattern header (patterns/<name>.hpp), its JSON copy
// (loadable with loadComparisonSetJson) and patterns/registry.hpp. One emitter shared by the trainer
// and the random-set generator, so every shipped header has the same form.
//
// Outputs are deterministic (no timestamps) and written atomically
// (mdbrief/internal/base/io/atomic_file.hpp), so an interrupted run leaves the previous files intact.
// A tool module, not installed: the runtime only reads test sets (mdbrief/describe/patterns.hpp).
#include <filesystem>
#include <string>
#include <vector>

#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief {

// Everything a pattern header and its JSON copy contain.
struct PatternDocument {
  std::string name;         // registry name and file stem: [a-z][a-z0-9_]*, not "registry"
  std::string description;  // one line: how the set was made (PatternInfo::description)
  std::string generator;    // the command that made it, without output paths
  // Header-comment lines after the command: settings, patch count, data digest...
  std::vector<std::string> provenance;
  std::vector<ComparisonPair> tests;  // emitted in this order; offsets in [-16, 15]
  // Optional, empty or one per test: the per-test comment (e.g. "mean 0.48 max corr 0.17").
  std::vector<std::string> testComments;
  // Digests of the training images (PatternInfo::trainingImages), sorted; empty for random sets.
  std::vector<std::string> trainingImages;
};

// Throws std::invalid_argument naming the problem (bad name, empty set, offsets out of range,
// testComments of the wrong size, line breaks in single-line fields).
void validate(const PatternDocument& document);

// "brief_random_512" -> "kBriefRandom512" (the array; the PatternInfo is that + "Info").
std::string patternIdentifier(const std::string& name);

std::string patternHeaderText(const PatternDocument& document);
std::string patternJsonText(const PatternDocument& document);
// names: the pattern headers to list (sorted here); defaultName must be one of them.
std::string registryHeaderText(std::vector<std::string> names, const std::string& defaultName);

// Throws std::invalid_argument naming it unless name can be a registry name and file stem
// ([a-z][a-z0-9_]*, not "registry"): for the writers and for what checks names early.
void requirePatternName(const std::string& name);

// Names of the pattern headers in dir (every *.hpp except registry.hpp), sorted.
std::vector<std::string> patternHeaderNames(const std::filesystem::path& dir);
// kDefaultPattern of dir/registry.hpp, or "" when there is none.
std::string registryDefaultName(const std::filesystem::path& dir);

struct PatternWriteOptions {
  bool writeJson = true;      // also write <name>.json next to the header
  bool makeDefault = false;   // make this set the registry's kDefaultPattern
};

// Throws std::runtime_error naming the file when writePattern could not write the set called
// name into dir (no such folder, not writable, a file in the way that is not a regular file):
// for tools to check before the work.
void checkPatternOutputs(const std::string& name, const std::filesystem::path& dir,
                         const PatternWriteOptions& options = {});

// Writes dir/<name>.hpp (and dir/<name>.json) and dir/registry.hpp, regenerated from every
// header in dir, as one set (internal::writeFilesAtomically): a failure leaves the previous
// files. Writers into one folder take turns (an flock on dir), so parallel runs lose no registry
// entry. The registry's default stays what it was unless makeDefault is set or the old default
// no longer exists (then this set becomes the default). dir must exist.
void writePattern(const PatternDocument& document, const std::filesystem::path& dir,
                  const PatternWriteOptions& options = {});

}  // namespace mdbrief
