#include "toolkit/cpu_model.hpp"

#include <sys/utsname.h>

#include <fstream>

namespace mdbrief::toolkit {

namespace {

// The value of the first "key : value" line of /proc/cpuinfo whose key is `key`.
std::string cpuinfoValue(const std::string& key) {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string name = line.substr(0, colon);
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
    if (name != key) continue;
    const size_t start = line.find_first_not_of(' ', colon + 1);
    return start == std::string::npos ? std::string() : line.substr(start);
  }
  return {};
}

}  // namespace

std::string cpuModel() {
  if (std::string model = cpuinfoValue("model name"); !model.empty()) return model;
  const std::string implementer = cpuinfoValue("CPU implementer"), part = cpuinfoValue("CPU part");
  if (!implementer.empty() || !part.empty()) return "ARM implementer " + implementer + " part " + part;
  utsname u{};
  return uname(&u) == 0 ? std::string(u.machine) : std::string("unknown CPU");
}

}  // namespace mdbrief::toolkit
