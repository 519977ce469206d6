#include "toolkit/content_digest.hpp"

#include <cstdio>

namespace mdbrief {

ContentDigest& ContentDigest::add(const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < size; ++i) {
    hash_ ^= bytes[i];
    hash_ *= 1099511628211ull;  // FNV-1a 64 prime
  }
  return *this;
}

std::string ContentDigest::hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
  return text;
}

std::string contentDigest(const void* data, size_t size) { return ContentDigest().add(data, size).hex(); }

}  // namespace mdbrief
