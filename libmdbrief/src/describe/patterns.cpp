#include "mdbrief/describe/patterns.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "mdbrief/internal/base/io/input_file.hpp"
#include "mdbrief/internal/base/io/unique_keys.hpp"
#include "patterns/registry.hpp"

namespace mdbrief {

namespace {

using patterns::PatternInfo;

const PatternInfo* findBuiltin(const std::string& name) {
  for (const PatternInfo* info : patterns::kRegistry)
    if (name == info->name) return info;
  return nullptr;
}

std::string knownNames() {
  std::string list;
  for (const auto& n : builtinComparisonSetNames()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

}  // namespace

std::vector<std::string> builtinComparisonSetNames() {
  std::vector<std::string> names;
  for (const PatternInfo* info : patterns::kRegistry) names.emplace_back(info->name);
  std::sort(names.begin(), names.end());
  return names;
}

std::string defaultComparisonSetName() { return patterns::kDefaultPattern; }

ComparisonSet builtinComparisonSet(const std::string& name) {
  const PatternInfo* info = findBuiltin(name);
  if (!info)
    throw std::invalid_argument("unknown test set '" + name + "' (built-in: " + knownNames() +
                                ")");
  ComparisonSet set{info->name, {}, {}};
  for (int d = 0; d < info->count; ++d) {
    const auto& t = info->tests[d];
    set.tests.push_back({t[0], t[1], t[2], t[3]});
  }
  std::istringstream digests(info->trainingImages ? info->trainingImages : "");
  for (std::string d; digests >> d;) set.trainingImages.push_back(d);
  return set;
}

ComparisonSet resolveComparisonSet(const std::string& nameOrPath) {
  if (findBuiltin(nameOrPath)) return builtinComparisonSet(nameOrPath);
  // Anything at the path is read as a file, so that a device or a folder is named as such (issue
  // 29: /dev/zero was "neither a built-in set nor an existing JSON file").
  std::error_code ec;
  if (std::filesystem::symlink_status(nameOrPath, ec).type() != std::filesystem::file_type::not_found && !ec)
    return loadComparisonSetJson(nameOrPath);
  throw std::invalid_argument("test set '" + nameOrPath +
                              "' is neither a built-in set (" + knownNames() +
                              ") nor an existing JSON file");
}

ComparisonSet loadComparisonSetJson(const std::string& path) {
  const auto fail = [&](const std::string& problem) {
    return std::runtime_error(path + ": " + problem);
  };
  if (const std::string problem = internal::inputFileProblem(path); !problem.empty())
    throw fail("test set file: " + problem);
  std::ifstream f(path, std::ios::binary);
  if (!f) throw fail("cannot open test set file");
  nlohmann::json doc;
  try {
    doc = internal::parseJsonUniqueKeys<nlohmann::json>(f);
  } catch (const nlohmann::json::exception& e) {
    throw fail(std::string("not valid JSON: ") + e.what());
  } catch (const std::runtime_error& e) {
    throw fail(e.what());
  }
  if (!doc.is_object()) throw fail("top level is not a JSON object");
  if (!doc.contains("name") || !doc["name"].is_string())
    throw fail("missing string key \"name\"");
  if (!doc.contains("tests") || !doc["tests"].is_array())
    throw fail("missing array key \"tests\"");

  ComparisonSet set;
  set.name = doc["name"].get<std::string>();
  const auto& tests = doc["tests"];
  set.tests.reserve(tests.size());
  for (size_t i = 0; i < tests.size(); ++i) {
    const auto& t = tests[i];
    const std::string where = "test " + std::to_string(i);
    if (!t.is_array() || t.size() != 4)
      throw fail(where + " is not an array of 4 offsets [x1, y1, x2, y2]");
    int v[4];
    for (int k = 0; k < 4; ++k) {
      const auto& offset = t[k];
      if (!offset.is_number()) throw fail(where + " has a non-integer offset");
      // As parsed: 2^63 is an unsigned (get<long long> made it negative), a whole number beyond
      // 64 bits a double; either is out of range, and said so with its value as read.
      const double value = offset.get<double>();
      const bool whole = !offset.is_number_float() || (std::isfinite(value) && std::floor(value) == value);
      const bool inside = value >= -kPatchHalf && value < kPatchHalf;
      if (!whole || (inside && offset.is_number_float()))
        throw fail(where + " has a non-integer offset " + offset.dump());
      if (!inside) throw fail(where + " has offset " + offset.dump() + " outside [-16, 15]");
      v[k] = offset.get<int>();
    }
    set.tests.push_back(ComparisonPair{static_cast<int8_t>(v[0]), static_cast<int8_t>(v[1]),
                        static_cast<int8_t>(v[2]), static_cast<int8_t>(v[3])});
  }
  if (doc.contains("training_images")) {
    const auto& images = doc["training_images"];
    if (!images.is_array()) throw fail("\"training_images\" is not an array");
    for (const auto& d : images) {
      if (!d.is_string()) throw fail("\"training_images\" holds a non-string");
      set.trainingImages.push_back(d.get<std::string>());
    }
  }
  if (set.tests.empty() || set.tests.size() % 32 != 0)
    throw fail(std::to_string(set.tests.size()) +
               " tests: the count must be a positive multiple of 32");
  return set;
}

}  // namespace mdbrief
