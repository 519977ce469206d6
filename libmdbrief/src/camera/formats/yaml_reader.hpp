#pragma once
// Typed values out of one YAML map of a calibration, with errors that name the source (a file,
// or the Python constructor), the key as the user spells it and the problem:
// "<source>: key '<prefix><key>' is missing" (the noun is "keyword" for Python's keywords).
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

namespace mdbrief::detail {

class YamlReader {
 public:
  YamlReader(std::string source, YAML::Node map, std::string prefix = "", std::string noun = "key")
      : source_(std::move(source)), map_(std::move(map)), prefix_(std::move(prefix)), noun_(std::move(noun)) {}

  const std::string& source() const { return source_; }
  const std::string& prefix() const { return prefix_; }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::runtime_error(source_ + ": " + noun_ + " '" + prefix_ + key + "' " + what);
  }

  bool has(const std::string& key) const { return static_cast<bool>(map_[key]); }

  YAML::Node node(const std::string& key) const {
    const YAML::Node n = map_[key];
    if (!n) fail(key, "is missing");
    return n;
  }

  double number(const std::string& key) const {
    const YAML::Node n = node(key);
    double value = 0.0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, value)) fail(key, "is not a number");
    if (!std::isfinite(value)) fail(key, "is NaN or infinite");
    return value;
  }

  double number(const std::string& key, double fallback) const { return has(key) ? number(key) : fallback; }

  // A positive integer of at most 10^6 (an image side).
  int size(const std::string& key) const {
    const double value = number(key);
    if (value <= 0.0 || value != std::floor(value) || value > 1e6)
      fail(key, "must be a positive integer (got " + node(key).Scalar() + ")");
    return static_cast<int>(value);
  }

  std::string text(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsScalar()) fail(key, "must be a name");
    return n.Scalar();
  }

  std::vector<double> numbers(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsSequence()) fail(key, "must be a list of numbers");
    std::vector<double> values;
    for (std::size_t i = 0; i < n.size(); ++i) {
      double value = 0.0;
      if (!n[i].IsScalar() || !YAML::convert<double>::decode(n[i], value))
        fail(key, "element " + std::to_string(i) + " is not a number");
      if (!std::isfinite(value)) fail(key, "element " + std::to_string(i) + " is NaN or infinite");
      values.push_back(value);
    }
    return values;
  }

  // `count` numbers, or an error saying how many there are.
  std::vector<double> numbers(const std::string& key, std::size_t count, const std::string& layout) const {
    const std::vector<double> values = numbers(key);
    if (values.size() != count)
      fail(key, "needs " + std::to_string(count) + " numbers (" + layout + "), found " + std::to_string(values.size()));
    return values;
  }

  // [width, height] as two positive integers.
  cv::Size imageSize(const std::string& key) const {
    const std::vector<double> v = numbers(key, 2, "width, height");
    for (const double side : v)
      if (side <= 0.0 || side != std::floor(side) || side > 1e6) fail(key, "must be two positive integers");
    return {static_cast<int>(v[0]), static_cast<int>(v[1])};
  }

  YamlReader sub(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsMap()) fail(key, "must be a map");
    return {source_, n, prefix_ + key + ".", noun_};
  }

  // Element `index` of the list `key`, a map ("<key>[<index>].<member>" in messages).
  YamlReader elementMap(const std::string& key, std::size_t index) const {
    const std::string name = elementName(key, index);
    const YAML::Node n = node(key)[index];
    if (!n.IsMap()) fail(name, "must be a map");
    return {source_, n, prefix_ + name + ".", noun_};
  }

  // Element `index` of the list `key` as an image size [width, height].
  cv::Size elementImageSize(const std::string& key, std::size_t index) const {
    const std::string name = elementName(key, index);
    YAML::Node holder(YAML::NodeType::Map);
    holder[name] = node(key)[index];
    return YamlReader(source_, holder, prefix_, noun_).imageSize(name);
  }

  std::size_t count(const std::string& key) const {
    const YAML::Node n = node(key);
    if (!n.IsSequence()) fail(key, "must be a list");
    return n.size();
  }

  std::set<std::string> keys() const {
    std::set<std::string> result;
    for (const auto& kv : map_) result.insert(kv.first.as<std::string>());
    return result;
  }

  // Rejects keys outside `allowed` so that typos do not silently fall back to defaults.
  void requireOnly(const std::set<std::string>& allowed, const std::string& schema) const {
    for (const std::string& key : keys())
      if (!allowed.count(key)) fail(key, "is not part of the '" + schema + "' schema");
  }

 private:
  // "<key>[<index>]" after checking that the list has that element.
  std::string elementName(const std::string& key, std::size_t index) const {
    const std::size_t n = count(key);
    if (index >= n) fail(key, "has " + std::to_string(n) + " entries, none at index " + std::to_string(index));
    return key + "[" + std::to_string(index) + "]";
  }

  std::string source_;
  YAML::Node map_;
  std::string prefix_;
  std::string noun_;
};

}  // namespace mdbrief::detail
