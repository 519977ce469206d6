#include "mdbrief/internal/base/io/unique_keys.hpp"

#include <map>
#include <stdexcept>
#include <vector>

namespace mdbrief::internal {

void requireUniqueYamlKeys(const std::string& path, const YAML::Node& root, std::size_t textBytes) {
  std::vector<YAML::Node> pending{root};
  for (std::size_t visited = 0; !pending.empty() && visited <= textBytes; ++visited) {
    const YAML::Node node = pending.back();
    pending.pop_back();
    if (node.IsSequence())
      for (const YAML::Node& item : node) pending.push_back(item);
    if (!node.IsMap()) continue;
    std::map<std::string, int> lines;
    for (const auto& entry : node) {
      pending.push_back(entry.second);
      if (!entry.first.IsScalar()) continue;
      const int line = entry.first.Mark().line + 1;
      if (entry.first.Scalar() == "<<" && entry.first.Tag() != "!")
        throw std::runtime_error(path + ": line " + std::to_string(line) +
                                 ": YAML merge keys ('<<') are not supported; write the keys out");
      const auto [first, fresh] = lines.emplace(entry.first.Scalar(), line);
      if (!fresh)
        throw std::runtime_error(path + ": key '" + entry.first.Scalar() + "' appears twice, on lines " +
                                 std::to_string(first->second) + " and " + std::to_string(line));
    }
  }
}

}  // namespace mdbrief::internal
