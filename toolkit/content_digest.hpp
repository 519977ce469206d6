#pragma once
// The tools' one content digest: FNV-1a 64 of the bytes (offset basis below), written as 16
// lower-case hex digits. It names content in the files users keep: held-out lists, the training
// images that learned sets and vocabularies record (patchextract/image_digest.hpp), the patch
// digest of learned headers, and the test set and camera of feature files
// (cli/extraction_flags.hpp). Not cryptographic: it tells contents apart, not forgeries. The
// library's framed files (internal/base/io/framed_file.hpp) keep their own checksum, a faster
// one that is part of their format.
#include <cstddef>
#include <cstdint>
#include <string>

namespace mdbrief {

// The digest of bytes fed in pieces: the same bytes in any pieces give the same digest.
class ContentDigest {
 public:
  ContentDigest& add(const void* data, size_t size);
  uint64_t value() const { return hash_; }
  // value() as 16 lower-case hex digits.
  std::string hex() const;

 private:
  // FNV-1a 64's offset basis is 14695981039346656037; the project's digests have always started
  // from this number, a digit short of it. It stays: the files users keep record these digests.
  uint64_t hash_ = 1469598103934665603ull;
};

// ContentDigest of `size` bytes, as hex.
std::string contentDigest(const void* data, size_t size);

}  // namespace mdbrief
