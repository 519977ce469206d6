#pragma once
// Refusing a key given twice in one map, in every reader of YAML or JSON: the parsers keep one
// of the values without a word (yaml-cpp the first, nlohmann::json the last), so a file with a
// repeated "tests", "fx" or "cam0" was read as part of what it says (issues 29, 45). Internal to
// the build, as atomic_file.hpp; its users link yaml-cpp (and nlohmann_json for the JSON one).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <set>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mdbrief/internal/base/io/nesting.hpp"

namespace mdbrief::internal {

// Throws std::runtime_error "<path>: key '<key>' appears twice, on lines <a> and <b>". A YAML 1.1
// merge key (`<<: *base`), which yaml-cpp leaves unmerged, is refused as such. The walk stops
// after as many nodes as the text has bytes: only aliases make more, and their expansion could
// be exponential.
void requireUniqueYamlKeys(const std::string& path, const YAML::Node& root, std::size_t textBytes);

// nlohmann's parse(input) (a string or a stream) of a JSON type, throwing std::runtime_error
// "key '<key>' appears twice in one object" for a repeated key, and "nested deeper than 64
// levels" past kMaxNesting (the top-level value is level 0), as every reader of structured text
// refuses it; its own parse errors propagate.
template <typename Json, typename Input>
Json parseJsonUniqueKeys(Input&& input) {
  std::vector<std::set<std::string>> open;  // the keys of each object being read
  return Json::parse(std::forward<Input>(input), [&open](int depth, typename Json::parse_event_t event, Json& parsed) {
    if ((event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start) &&
        depth > kMaxNesting)
      throw std::runtime_error("nested deeper than " + std::to_string(kMaxNesting) + " levels");
    if (event == Json::parse_event_t::object_start) open.emplace_back();
    if (event == Json::parse_event_t::object_end) open.pop_back();
    if (event == Json::parse_event_t::key && !open.back().insert(parsed.template get<std::string>()).second)
      throw std::runtime_error("key '" + parsed.template get<std::string>() + "' appears twice in one object");
    return true;
  });
}

}  // namespace mdbrief::internal
