#pragma once
// Test sets available at run time: compiled-in pattern headers (patterns/registry.hpp) and
// JSON files written by the trainer.
#include <string>
#include <vector>

#include "mdbrief/describe/test_set.hpp"

namespace mdbrief {

// Names of the compiled-in sets, sorted.
std::vector<std::string> builtinTestSetNames();
// The set the runtime uses when DescriptorOptions::pattern is empty.
std::string defaultTestSetName();
// A compiled-in set by name. Throws std::invalid_argument listing the known names.
TestSet builtinTestSet(const std::string& name);
// A name from the registry, or else a path to a JSON test set file.
TestSet resolveTestSet(const std::string& nameOrPath);

// JSON form: {"name": str, "tests": [[x1,y1,x2,y2], ...], optional "training_images": [digest,
// ...], ...extra metadata ignored}.
// Throws std::runtime_error naming the file and the problem (missing key, offset outside
// [-16, 15], wrong arity, not a multiple of 32 tests...).
TestSet loadTestSetJson(const std::string& path);

}  // namespace mdbrief
