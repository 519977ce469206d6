#pragma once
// Comparison sets (the paper's test sets) available at run time: compiled-in pattern headers
// (patterns/registry.hpp) and JSON files written by the trainer.
#include <string>
#include <vector>

#include "mdbrief/describe/comparison_set.hpp"

namespace mdbrief {

// Names of the compiled-in sets, sorted.
std::vector<std::string> builtinComparisonSetNames();
// The set the runtime uses when DescriptorOptions::pattern is empty.
std::string defaultComparisonSetName();
// A compiled-in set by name. Throws std::invalid_argument listing the known names.
ComparisonSet builtinComparisonSet(const std::string& name);
// A name from the registry, or else a path to a JSON comparison set file.
ComparisonSet resolveComparisonSet(const std::string& nameOrPath);

// JSON form: {"name": str, "tests": [[x1,y1,x2,y2], ...], optional "training_images": [digest,
// ...], ...extra metadata ignored}.
// Throws std::runtime_error naming the file and the problem (missing key, offset outside
// [-16, 15], wrong arity, not a multiple of 32 tests...).
ComparisonSet loadComparisonSetJson(const std::string& path);

// The names of 0.2, deprecated (a BRIEF test is now called a comparison).
[[deprecated("renamed builtinComparisonSetNames")]] inline std::vector<std::string> builtinTestSetNames() {
  return builtinComparisonSetNames();
}
[[deprecated("renamed defaultComparisonSetName")]] inline std::string defaultTestSetName() {
  return defaultComparisonSetName();
}
[[deprecated("renamed builtinComparisonSet")]] inline ComparisonSet builtinTestSet(const std::string& name) {
  return builtinComparisonSet(name);
}
[[deprecated("renamed resolveComparisonSet")]] inline ComparisonSet resolveTestSet(const std::string& nameOrPath) {
  return resolveComparisonSet(nameOrPath);
}
[[deprecated("renamed loadComparisonSetJson")]] inline ComparisonSet loadTestSetJson(const std::string& path) {
  return loadComparisonSetJson(path);
}

}  // namespace mdbrief
